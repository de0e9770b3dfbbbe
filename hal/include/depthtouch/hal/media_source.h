#pragma once
/// \file
/// \brief MediaSource: a demuxer that reads the color and depth streams of a 3D video
/// (docs/architecture.md §4).
///
/// State machine:
/// \verbatim
///   Closed --open(url)--> Open --close()--> Closed
///                          |  readPacket(), seek()
/// \endverbatim
/// A call that is not allowed in the current state returns Errc::InvalidState and has no effect.
/// open() on an Open source is InvalidState (close first).
///
/// Ownership: the source owns the packet data; Packet::data stays valid until the next
/// readPacket(), seek(), close() or the destruction of the source. info() is valid while Open.
/// Thread-safety: thread-bound (the decode thread), except interrupt(), which any thread may call.
/// Not real-time safe (file and network I/O).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// Compression of a video stream.
enum class CodecId : std::uint8_t {
    Unknown,
    H264,
    Hevc,
    Ffv1,
    RawVideo,
    Mjpeg,
    Mock, ///< Synthetic packets of drivers/mock (MockMediaSource → MockVideoDecoder).
};

/// \return the codec's name, e.g. "h264" (static string).
const char *codecName(CodecId codec) noexcept;

/// \brief How the samples of a depth stream map to distance (docs/architecture.md §3, metadata tags
/// depth_near, depth_far, depth_mapping, depth_bits, depth_occupancy).
struct DepthMetadata {
    double nearMetres = 0.0; ///< Distance of the maximum nearness value; 0 when not given.
    double farMetres = 0.0;  ///< Distance of nearness 0; 0 when not given.
    std::string
        mapping; ///< Mapping name, e.g. "inverse" (MPEG 3DV 1/Z) or "linear"; empty when not given.
    int bits = 0; ///< Significant bits per depth sample (8, 10 or 16); 0 when not given.
    /// depth_occupancy (docs/architecture.md §3 "Holes"): a sample below it is a hole (not
    /// measured), in the stream's own sample units (0..2^bits − 1, before any widening by a
    /// decoder); 0 when not given (every sample measured).
    std::uint32_t occupancy = 0;
};

/// \brief One stream of an opened source.
struct StreamInfo {
    int index = -1;                      ///< Packet::streamIndex of its packets.
    /// The stream's number in its container (libavformat's stream index: another reader of the
    /// same file finds the stream by it); -1 where the source has no container (a mock).
    int containerIndex = -1;
    StreamKind kind = StreamKind::Color; ///< From the stream title ("color" / "depth").
    /// The stream's role name: the container's stream title (MKV), else its MP4 handler name, else
    /// the order DepthTouch's MPEG-TS metadata gives (color, then depth); empty when none says.
    std::string title;
    /// Where title came from: "title", "MP4 handler name", "MPEG-TS timed metadata" or (files
    /// written before it) "MPEG-TS service" (static string; empty when title is empty).
    const char *titleFrom = "";
    CodecId codec = CodecId::Unknown;
    PixelFormat format = PixelFormat::Unknown; ///< Decoded pixel format the stream declares.
    int width = 0;                             ///< Pixels.
    int height = 0;                            ///< Pixels.
    Rational frameRate;                        ///< Frames per second; den == 0 when unknown.
    Rational timeBase; ///< Container time base (informational: Packet times are Pts).
    std::vector<std::uint8_t> extradata; ///< Codec setup data (e.g. H.264 SPS/PPS), possibly empty.
    DepthMetadata depth;                 ///< Meaningful when kind == StreamKind::Depth.
};

/// \brief An audio stream of the input, as the container describes it. Listed (`probe`); its
/// packets are delivered only once asked for (MediaSource::deliverAudio(): a live stream's sound).
struct AudioStreamInfo {
    int containerIndex = -1; ///< The stream's number in the container (not a Packet::streamIndex).
    std::string codec;       ///< The codec's libavcodec name ("aac", "opus", "pcm_s16le").
    int sampleRate = 0;      ///< Samples per second per channel, Hz; 0 when unknown.
    int channels = 0;        ///< 0 when unknown.
    /// The first sample's time on the clock of the video packets' Pts (the input's start is 0),
    /// and the stream's length (zero when the container does not say).
    Pts start{0};
    Pts duration{0};
    std::string language;                ///< The language tag (ISO 639-2, "eng"), empty when none.
    std::vector<std::uint8_t> extradata; ///< Codec setup data (AAC's AudioSpecificConfig), or none.
};

/// \brief What an opened source contains.
/// \brief One rendition of an adaptive input (an HLS multivariant playlist).
struct RenditionInfo {
    int width = 0; ///< Its tallest video stream's size (pixels); 0 when unknown.
    int height = 0;
    long long bitRate = 0; ///< The playlist's BANDWIDTH (bits/s); 0 when not given.
    bool kept = false;     ///< The rendition whose streams are listed and read.
};

struct MediaInfo {
    std::vector<StreamInfo> streams; ///< In container order; streams[i].index == i.
    /// An adaptive input's renditions, in the playlist's order (one kept); empty otherwise.
    std::vector<RenditionInfo> renditions;
    std::vector<AudioStreamInfo> audio; ///< Its audio streams, in container order.
    platform::Duration
        duration{};        ///< Length of the longest stream; zero when unknown (live stream).
    bool seekable = false; ///< Whether seek() can succeed.
};

/// \brief One compressed packet of one stream. Non-owning: see MediaSource for the lifetime of
/// data.
struct Packet {
    int streamIndex = -1;
    const std::uint8_t *data = nullptr;
    std::size_t size =
        0; ///< Bytes at data. 0 with data == nullptr marks end of stream (decoder drain).
    Pts pts = kNoPts;      ///< Presentation time on the stream timeline.
    Pts dts = kNoPts;      ///< Decode time on the stream timeline.
    bool keyframe = false; ///< The packet starts an independently decodable picture.
    /// A packet of the audio stream MediaSource::deliverAudio() chose: streamIndex is then its
    /// AudioStreamInfo::containerIndex, and pts/dts lie on the video packets' clock.
    bool audio = false;

    /// An end-of-stream packet: queueing it into a VideoDecoder drains the decoder.
    static constexpr Packet endOfStream(int stream = -1) noexcept
    {
        Packet p;
        p.streamIndex = stream;
        return p;
    }
    [[nodiscard]] constexpr bool isEndOfStream() const noexcept
    {
        return data == nullptr && size == 0;
    }
};

/// \brief A demuxer: opens a file or stream URL and reads its packets in container order.
class MediaSource {
public:
    enum class State : std::uint8_t { Closed, Open };

    virtual ~MediaSource() = default;

    /// \return the current state.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Opens \a url and reads the stream list.
    /// \pre Closed.
    /// \param[in] url A file path or stream URL the backend understands (NUL-terminated).
    /// \return nothing on success (state Open; see info()). Errors: InvalidState (not Closed),
    /// NotSupported (scheme or container the backend cannot read), NoDevice or Io (cannot open or
    /// read), InvalidArgument (a null or empty \a url, malformed file, no video stream). On error
    /// the source stays Closed. Backends derive from MediaSourceBase (media_source_base.h), which
    /// keeps this contract.
    [[nodiscard]] virtual Result<void> open(const char *url) = 0;

    /// \brief Closes the source and frees its buffers. Always allowed; no-op when Closed.
    virtual void close() noexcept = 0;

    /// \return the streams, duration and seekability of the opened source.
    /// \pre Open (when Closed: an empty MediaInfo).
    [[nodiscard]] virtual const MediaInfo &info() const noexcept = 0;

    /// \brief Reads the next packet of any stream, in container order.
    /// \pre Open.
    /// \return the packet (its data valid until the next call, seek() or close()). Errors:
    /// InvalidState (not Open), EndOfStream (no more packets: the normal end), Io (read failure or
    /// truncated file; the source stays Open and seek() may recover).
    [[nodiscard]] virtual Result<Packet> readPacket() = 0;

    /// \brief Moves the read position so the next packets start at the keyframe at or before \a
    /// position. \pre Open. \param[in] position Target on the stream timeline; clamped to [0,
    /// duration]. \return nothing on success. Errors: InvalidState (not Open), NotSupported (not
    /// seekable), Io (the seek failed; the read position is unspecified but the source stays Open).
    [[nodiscard]] virtual Result<void> seek(Pts position) = 0;

    /// \brief Makes a blocking open(), readPacket() or seek() running on another thread return
    /// within 100 ms, whatever the network does (a silent or stalled live stream), and every later
    /// one fail at once, until close(): the stop request of the player (mpv's quit during a stalled
    /// read). The call that was interrupted returns Errc::Timeout.
    /// Thread-safe and async-signal-safe (one atomic store); allowed in every state. The default
    /// does nothing: for a backend whose calls never block.
    virtual void interrupt() noexcept {}

    /// \brief Makes a readPacket() blocked on another thread (a stalled input) return within
    /// 100 ms with Errc::Timeout, once: for a seek requested meanwhile. The next seek() consumes
    /// the request if no read did; later calls work as usual. Thread-safe and async-signal-safe;
    /// allowed in every state. The default does nothing: for a backend whose reads never block.
    virtual void cancelRead() noexcept {}

    /// \brief Makes readPacket() also return the packets of the audio stream listed with
    /// \a containerIndex (Packet::audio set), from the next read on; -1 stops it. For a live
    /// input, whose sound cannot be read a second time beside it.
    /// \pre Open. \return Errors: InvalidState (not Open), InvalidArgument (no such audio stream),
    /// NotSupported (the backend delivers no sound: the default).
    /// Thread-safety: the reading thread, or any thread before it reads.
    [[nodiscard]] virtual Result<void> deliverAudio(int containerIndex)
    {
        (void)containerIndex;
        return unexpected(Errc::NotSupported, "This media source delivers no sound");
    }

protected:
    MediaSource() = default;
    DT_DISABLE_COPY_AND_MOVE(MediaSource)
};

/// \return the name of \a s: "Closed" or "Open" (a static string; "?" for another value), for
/// messages. Thread-safe.
[[nodiscard]] const char *toString(MediaSource::State s) noexcept;

} // namespace depthtouch::hal
