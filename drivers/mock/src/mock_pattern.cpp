#include "depthtouch/drivers/mock/mock_pattern.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace depthtouch::drivers {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBumpPeriodSeconds = 4.0;
constexpr double kBackgroundNearness = 0.2;

std::uint32_t fnv1a(const std::uint8_t *data, std::size_t size) noexcept
{
    std::uint32_t h = 2166136261u;
    for (std::size_t i = 0; i < size; ++i) {
        h ^= data[i];
        h *= 16777619u;
    }
    return h;
}

void storeSample(std::uint8_t *row, int x, int bytesPerSample, std::uint32_t value) noexcept
{
    if (bytesPerSample == 1) {
        row[x] = static_cast<std::uint8_t>(value);
    } else {
        const auto v = static_cast<std::uint16_t>(value);
        std::memcpy(row + 2 * x, &v, sizeof(v));
    }
}

} // namespace

std::size_t writeMockPacket(std::uint8_t *out, hal::StreamKind kind, std::uint32_t frameIndex,
                            int width, int height, bool keyframe) noexcept
{
    MockPacketHeader h;
    h.magic = kMockPacketMagic;
    h.version = kMockPacketVersion;
    h.kind = static_cast<std::uint8_t>(kind);
    h.keyframe = keyframe ? 1 : 0;
    h.frameIndex = frameIndex;
    h.width = static_cast<std::uint16_t>(width);
    h.height = static_cast<std::uint16_t>(height);
    h.payloadBytes = keyframe ? 96u : 24u;
    static_assert(sizeof(MockPacketHeader) + 96 <= kMockPacketMaxBytes);
    std::uint8_t *payload = out + sizeof(MockPacketHeader);
    for (std::uint32_t i = 0; i < h.payloadBytes; ++i)
        payload[i] = static_cast<std::uint8_t>((frameIndex * 31u + i * 7u + h.kind) & 0xffu);
    h.checksum = fnv1a(payload, h.payloadBytes);
    std::memcpy(out, &h, sizeof(h));
    return sizeof(h) + h.payloadBytes;
}

MockPacketCheck parseMockPacket(const std::uint8_t *data, std::size_t size,
                                MockPacketHeader &header) noexcept
{
    if (data == nullptr || size < sizeof(MockPacketHeader))
        return MockPacketCheck::Malformed;
    std::memcpy(&header, data, sizeof(header));
    if (header.magic != kMockPacketMagic || header.version != kMockPacketVersion ||
        header.kind > 1 || sizeof(MockPacketHeader) + header.payloadBytes != size)
        return MockPacketCheck::Malformed;
    return fnv1a(data + sizeof(MockPacketHeader), header.payloadBytes) == header.checksum
               ? MockPacketCheck::Ok
               : MockPacketCheck::Damaged;
}

double mockDepthNearness(double x, double y, int width, int height, double seconds) noexcept
{
    const double w = static_cast<double>(width);
    const double h = static_cast<double>(height);
    const double phase = 2.0 * kPi * seconds / kBumpPeriodSeconds;
    const double cx = 0.5 * (w - 1.0) + 0.25 * w * std::cos(phase);
    const double cy = 0.5 * (h - 1.0) + 0.25 * h * std::sin(phase);
    const double sigma = 0.15 * std::min(w, h);
    const double dx = x - cx;
    const double dy = y - cy;
    const double bump = std::exp(-(dx * dx + dy * dy) / (2.0 * sigma * sigma));
    return kBackgroundNearness + (1.0 - kBackgroundNearness) * bump;
}

namespace {

/// Writes 0 into every byte of \a image's planes.
void zeroPlanes(const hal::ImageView &image) noexcept
{
    for (int p = 0; p < hal::planeCount(image.format); ++p) {
        const hal::PlaneLayout l = hal::planeLayout(image.format, image.width, image.height, p);
        for (int y = 0; y < l.rows; ++y)
            std::memset(image.row(p, y), 0, static_cast<std::size_t>(l.rowBytes));
    }
}

} // namespace

void renderMockDepth(const hal::ImageView &image, double seconds) noexcept
{
    const int bits = hal::bitsPerSample(image.format);
    const bool gray = image.format == hal::PixelFormat::Gray8 ||
                      image.format == hal::PixelFormat::Gray10 ||
                      image.format == hal::PixelFormat::Gray16;
    if (!gray || image.empty()) { // no pattern for this layout: zeros, as the pools no longer are
        if (!image.empty())
            zeroPlanes(image);
        return;
    }
    const double maxValue = static_cast<double>((1u << bits) - 1u);
    const int bytesPerSample = bits > 8 ? 2 : 1;
    for (int y = 0; y < image.height; ++y) {
        std::uint8_t *row = image.row(0, y);
        for (int x = 0; x < image.width; ++x) {
            const double v = mockDepthNearness(x, y, image.width, image.height, seconds);
            storeSample(row, x, bytesPerSample,
                        static_cast<std::uint32_t>(std::lround(v * maxValue)));
        }
    }
}

void renderMockColor(const hal::ImageView &image, std::uint32_t frameIndex) noexcept
{
    if (image.empty())
        return;
    switch (image.format) {
    case hal::PixelFormat::Gray8:
    case hal::PixelFormat::Yuv420p:
        for (int y = 0; y < image.height; ++y) {
            std::uint8_t *row = image.row(0, y);
            for (int x = 0; x < image.width; ++x)
                row[x] = mockColorLuma(x, y, frameIndex);
        }
        if (image.format == hal::PixelFormat::Yuv420p) {
            const int cw = (image.width + 1) / 2;
            const int ch = (image.height + 1) / 2;
            for (int y = 0; y < ch; ++y) {
                std::uint8_t *u = image.row(1, y);
                std::uint8_t *v = image.row(2, y);
                for (int x = 0; x < cw; ++x) {
                    u[x] = static_cast<std::uint8_t>(64 + (128 * x) / std::max(cw - 1, 1));
                    v[x] = static_cast<std::uint8_t>(64 + (128 * y) / std::max(ch - 1, 1));
                }
            }
        }
        break;
    case hal::PixelFormat::Rgb24:
        for (int y = 0; y < image.height; ++y) {
            std::uint8_t *row = image.row(0, y);
            for (int x = 0; x < image.width; ++x) {
                row[3 * x + 0] = mockColorLuma(x, y, frameIndex);
                row[3 * x + 1] =
                    static_cast<std::uint8_t>((255 * y) / std::max(image.height - 1, 1));
                row[3 * x + 2] = static_cast<std::uint8_t>(frameIndex & 0xffu);
            }
        }
        break;
    default: // no pattern for this layout: black (the frame pools do not zero their frames)
        zeroPlanes(image);
        return;
    }
    // The index stamp: four bytes of row 0 (needs a row of at least 4 bytes).
    if (hal::planeLayout(image.format, image.width, image.height, 0).rowBytes >= 4) {
        const std::uint8_t stamp[4] = {static_cast<std::uint8_t>(frameIndex),
                                       static_cast<std::uint8_t>(frameIndex >> 8),
                                       static_cast<std::uint8_t>(frameIndex >> 16),
                                       static_cast<std::uint8_t>(frameIndex >> 24)};
        std::memcpy(image.row(0, 0), stamp, sizeof(stamp));
    }
}

std::uint32_t readMockFrameIndex(const hal::ImageView &image) noexcept
{
    if (image.empty())
        return 0;
    const std::uint8_t *p = image.row(0, 0);
    return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
           static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

void renderMockConcealed(const hal::ImageView &image) noexcept
{
    for (int p = 0; p < hal::planeCount(image.format); ++p) {
        const hal::PlaneLayout l = hal::planeLayout(image.format, image.width, image.height, p);
        const bool wide = hal::bitsPerSample(image.format) > 8;
        for (int y = 0; y < l.rows; ++y) {
            std::uint8_t *row = image.row(p, y);
            if (wide) {
                const std::uint16_t mid =
                    static_cast<std::uint16_t>(1u << (hal::bitsPerSample(image.format) - 1));
                for (int x = 0; x < l.rowBytes / 2; ++x)
                    std::memcpy(row + 2 * x, &mid, sizeof(mid));
            } else {
                std::memset(row, 128, static_cast<std::size_t>(l.rowBytes));
            }
        }
    }
}

} // namespace depthtouch::drivers
