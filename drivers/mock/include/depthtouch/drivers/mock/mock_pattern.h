#pragma once
/// \file
/// \brief The synthetic content of the mock backends: the packet format MockMediaSource writes and
/// MockVideoDecoder reads, and the images they stand for. Tests use these functions to compute the
/// expected pixels.
///
/// Every function is a pure function of its arguments: the same inputs give the same bytes on every
/// run. Thread-safety: reentrant. Real-time safe (no allocation).

#include <cstddef>
#include <cstdint>

#include "depthtouch/hal/types.h"

namespace depthtouch::drivers {

/// \brief Header of a Mock codec packet (host byte order), followed by payloadBytes of payload.
struct MockPacketHeader {
    std::uint32_t magic = 0;   ///< kMockPacketMagic.
    std::uint8_t version = 0;  ///< kMockPacketVersion.
    std::uint8_t kind = 0;     ///< hal::StreamKind.
    std::uint8_t keyframe = 0; ///< 1 for a keyframe.
    std::uint8_t reserved = 0;
    std::uint32_t frameIndex = 0;   ///< Frame number in the stream, from 0.
    std::uint16_t width = 0;        ///< Pixels.
    std::uint16_t height = 0;       ///< Pixels.
    std::uint32_t payloadBytes = 0; ///< Bytes after the header.
    std::uint32_t checksum = 0;     ///< FNV-1a of the payload; a mismatch means damaged data.
};

inline constexpr std::uint32_t kMockPacketMagic = 0x4b4d5444; // "DTMK"
inline constexpr std::uint8_t kMockPacketVersion = 1;
/// Largest Mock packet (header + payload) in bytes.
inline constexpr std::size_t kMockPacketMaxBytes = 128;

/// \brief Writes the packet of frame \a frameIndex of a \a kind stream into \a out.
/// \param[out] out At least kMockPacketMaxBytes bytes.
/// \return the packet size in bytes (keyframes are larger, like real streams).
std::size_t writeMockPacket(std::uint8_t *out, hal::StreamKind kind, std::uint32_t frameIndex,
                            int width, int height, bool keyframe) noexcept;

/// Outcome of parseMockPacket().
enum class MockPacketCheck : std::uint8_t {
    Ok,        ///< Well-formed, checksum correct.
    Damaged,   ///< Well-formed header, payload checksum wrong (conceal).
    Malformed, ///< Not a Mock packet (wrong magic, version or size).
};

/// \brief Reads the header of the Mock packet \a data of \a size bytes into \a header and checks
/// it.
MockPacketCheck parseMockPacket(const std::uint8_t *data, std::size_t size,
                                MockPacketHeader &header) noexcept;

/// \brief Depth nearness of the mock depth video at pixel (\a x, \a y) of a \a width × \a height
/// frame at \a seconds on the stream timeline: a smooth Gaussian bump over a flat background (0.2)
/// whose centre circles the image centre once every 4 s. \return nearness in [0, 1] (1 = nearest).
double mockDepthNearness(double x, double y, int width, int height, double seconds) noexcept;

/// \brief Fills \a image (Gray8, Gray10 or Gray16; others are left untouched) with
/// mockDepthNearness() scaled to the format's maximum and rounded.
void renderMockDepth(const hal::ImageView &image, double seconds) noexcept;

/// \brief Fills \a image (Yuv420p, Rgb24 or Gray8; others are left untouched) with the mock color
/// video: a diagonal gradient that shifts with the frame, with \a frameIndex written into the first
/// four bytes of row 0 (little-endian) so a consumer can tell which frame it got
/// (readMockFrameIndex()).
void renderMockColor(const hal::ImageView &image, std::uint32_t frameIndex) noexcept;

/// \return the frame index written by renderMockColor() into \a image.
std::uint32_t readMockFrameIndex(const hal::ImageView &image) noexcept;

/// \return the luma / gray value renderMockColor() writes at pixel (\a x, \a y) outside the index
/// stamp.
constexpr std::uint8_t mockColorLuma(int x, int y, std::uint32_t frameIndex) noexcept
{
    return static_cast<std::uint8_t>(
        (2u * static_cast<unsigned>(x) + static_cast<unsigned>(y) + 3u * frameIndex) & 0xffu);
}

/// \brief Fills a frame that failed to decode (concealment): mid-gray / nearness 0.5.
void renderMockConcealed(const hal::ImageView &image) noexcept;

} // namespace depthtouch::drivers
