#pragma once
/// \file
/// \brief The sender's encoders and muxer (docs/architecture.md §4): color H.264 4:2:0 and depth
/// H.264 4:0:0 (gray, gray10) or FFV1 gray16, muxed into MKV, MP4 or MPEG-TS, written to a file or
/// to any URL libavformat can write (udp://, srt://, tcp://…).
///
/// Use: Muxer::open() → VideoEncoder::create() once per stream (color first, then depth) →
/// Muxer::start() → VideoEncoder::encode() per frame → VideoEncoder::flush() each →
/// Muxer::finish(). Muxer::abort() (or destroying an unfinished Muxer) removes a file output.
///
/// File outputs are written to a temporary name in the same directory (`OUT.tmp.PID`) and renamed
/// to OUT by finish(): a failed encode never leaves a partial file. Only a regular file or a new
/// path is replaced so; a character device or a FIFO with a reader is written in place, anything
/// else refused (platform::planOutput()). URLs are written directly.
///
/// Time: PTS are seconds, carried in a 90 kHz time base: frames given the same PTS come out of
/// the muxer with the same PTS in every container. Errors: static messages; FFmpeg's own message is
/// logged (category "Media", Warning). Thread-safety: thread-bound (one thread drives the muxer
/// and its encoders).

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/media/image.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// Frame rates an encoder takes, frames/s (0.1: one frame every 10 s).
inline constexpr double kMinEncodeFps = 0.1;
inline constexpr double kMaxEncodeFps = 1000.0;

/// \return true when a \a width × \a height frame may be encoded: each side 1..16384 pixels and at
/// most H.264 level 6.2's largest frame, 139264 macroblocks (35.6 Mpixel, e.g. 8192×4352; ITU-T
/// H.264 Table A-1), within libavutil's image size limit. Checked before any frame is converted,
/// so a huge size fails at once instead of after gigabytes of buffers.
bool isEncodableSize(int width, int height) noexcept;

/// \brief Containers the sender writes.
/// Hls: an HLS playlist (`.m3u8`) with MPEG-TS segments beside it (libavformat's hls muxer).
enum class Container : std::uint8_t { Matroska, Mp4, MpegTs, Hls };

/// \return "matroska", "mp4", "mpegts" or "hls" (libavformat muxer names).
const char *containerName(Container c) noexcept;

/// \brief Parses a `--format` value: "mkv"/"matroska", "mp4", "ts"/"mpegts", "hls".
/// \return the container or Errc::InvalidArgument.
Result<Container> parseContainer(const std::string &text);

/// \brief The container for an output name when no format is given: by extension (.mkv, .mp4,
/// .m4v, .mov → MP4, .ts/.m2ts), MPEG-TS for a URL without one (live streams), MKV otherwise.
Container containerForOutput(const std::string &output);

/// \return true when \a output is a URL (`scheme://…`, but not `file:`), written without a
/// temporary name.
bool isOutputUrl(const std::string &output);

/// \brief Options of Muxer::open().
struct MuxerOptions {
    std::string output; ///< File name or URL.
    Container container = Container::Matroska;
    /// Container-level metadata (e.g. the depth tags, so every tool finds them).
    std::vector<std::pair<std::string, std::string>> tags;
    /// A live stream (paced, possibly endless): an HLS playlist keeps a sliding window of six
    /// segments and deletes older ones; otherwise it lists every segment (an event playlist).
    bool live = false;
    /// MPEG-TS only: a constant multiplex rate (bits/s, ffmpeg's `-muxrate`), padded with null
    /// packets, as broadcast multiplexers and IPTV head-ends expect; 0: variable.
    long long muxRate = 0;
    /// HLS: the target length of a segment (s, the muxer's `hls_time`); 2 s, within Apple's 2 to
    /// 6 s for low latency.
    static constexpr int kHlsSegmentSeconds = 2;
};

class VideoEncoder;
class AudioTrack;

/// \brief One output file or stream: owns the libavformat context and the output I/O.
class Muxer {
public:
    ~Muxer();
    Muxer(const Muxer &) = delete;
    Muxer &operator=(const Muxer &) = delete;

    /// \brief Creates the output (the temporary file for a file output).
    /// \return the muxer; Errc::InvalidArgument for an output path that must not be written (a
    ///         directory, block device, socket, FIFO without a reader, a missing or read-only
    ///         folder); Errc::Io when the output cannot be created (no permission, unreachable
    ///         URL), Errc::NotSupported when FFmpeg lacks the muxer.
    static Result<std::unique_ptr<Muxer>> open(const MuxerOptions &options);

    /// \brief Writes the container header. \pre every stream added (VideoEncoder::create()).
    /// \return Errc::Io on a write error, Errc::InvalidArgument when the container refuses a
    ///         stream (e.g. a codec it cannot carry).
    Result<void> start();

    /// \brief Writes the trailer, closes the output and (file output) renames the temporary
    /// file to the output name. \pre start() succeeded and every encoder flushed.
    /// \return Errc::Io when writing, closing or renaming fails (the temporary file is removed).
    Result<void> finish();

    /// \brief Closes the output without a trailer and removes a file output's temporary file.
    void abort() noexcept;

    /// \return bytes written so far (0 for HLS, whose muxer writes files of its own).
    [[nodiscard]] long long bytesWritten() const noexcept;
    /// \return HLS file output: the bytes of each MPEG-TS segment completed so far, in order (the
    /// last 4096 of an endless output); empty otherwise.
    [[nodiscard]] std::vector<long long> segmentBytes() const;
    /// \return HLS file output: the MPEG-TS segments completed so far; 0 otherwise.
    [[nodiscard]] long long segmentsCompleted() const noexcept;
    /// \return the container.
    [[nodiscard]] Container container() const noexcept;

    struct Impl;

private:
    Muxer();
    std::unique_ptr<Impl> impl_;
    friend class VideoEncoder;
    friend class AudioTrack;
};

/// \brief Codecs and sample layouts an encoder produces.
enum class VideoCodec : std::uint8_t {
    H264Yuv420p, ///< libx264, 8-bit 4:2:0, from Rgb24 (BT.601 limited range via libswscale).
    H264Gray,    ///< libx264, 8-bit 4:0:0, from Gray8 (full range: levels 0..255 as they are).
    H264Gray10,  ///< libx264, 10-bit 4:0:0, from Gray16 holding 0..1023.
    Ffv1Gray16,  ///< FFV1 level 3 with slice CRCs, 16-bit gray, from Gray16 (always lossless).
    /// libx265, HEVC Main10 4:2:0 from Gray16 holding 0..1023: the samples in the luma plane,
    /// both chroma planes neutral (512), as MPEG Immersive Video carries geometry (ISO/IEC
    /// 23090-12), so that the hardware HEVC decoders of set-top SoCs and GPUs decode it. Even
    /// width and height. Lossless: x265 lossless mode.
    HevcMain10,
    /// libx264rgb, 8-bit 4:4:4 RGB (High 4:4:4 Predictive), from Rgb24, always lossless (qp 0,
    /// VideoEncoderConfig::crf and lossless ignored): decodes to gbrp bit-exactly. The material
    /// track (depthtouch/scene/material.h, materialStreamConfig()).
    H264Rgb,
};

/// \brief An H.264 stream's rate control, with ffmpeg's meanings (`-b:v`, `-maxrate`, `-bufsize`;
/// libx264's ABR and VBV, H.264 Annex C's hypothetical reference decoder). Ignored by lossless
/// streams (qp 0, FFV1). bitRate == maxRate with a bufSize is a constant bit rate for broadcast.
struct RateControl {
    long long bitRate = 0; ///< Average bits/s in place of the CRF (x264 ABR); 0: the CRF.
    long long maxRate = 0; ///< Peak bits/s that the VBV buffer drains at; 0: none. Needs bufSize.
    long long bufSize = 0; ///< VBV buffer (bits); 0: none.
};

/// \return a bit rate or buffer size as ffmpeg reads one (`-b:v 4M`): a number with an optional
/// SI prefix (k, M, G; Ki, Mi, Gi for powers of 1024) and an optional B for bytes, parsed by
/// libavutil's av_strtod(); nullopt when the text is not one, or the value is not whole bits
/// in 1000..2^40 (x264 counts kbit/s).
std::optional<long long> parseBitRate(const std::string &text);

/// \brief Options of VideoEncoder::create().
struct VideoEncoderConfig {
    VideoCodec codec = VideoCodec::H264Yuv420p;
    int width = 0;         ///< Pixels (even for 4:2:0).
    int height = 0;        ///< Pixels (even for 4:2:0).
    double fps = 30.0;     ///< Nominal frames/s, kMinEncodeFps..kMaxEncodeFps.
    int crf = 23;          ///< x264 constant rate factor 0..51 (ignored when lossless and by FFV1).
    bool lossless = false; ///< x264 qp 0 (x264 then uses High 4:4:4 Predictive).
    std::string preset = "medium";                         ///< x264 preset (ultrafast … placebo).
    int threads = 0;                                       ///< Encoder threads; 0 = automatic.
    /// H.264 frames between key frames (0: x264's default, 250, with key frames at scene cuts
    /// too). Set: a key frame exactly every gop frames and nowhere else (x264's scene-cut
    /// detection off), so streams of one output with the same gop have their key frames on the
    /// same pictures. A live stream sets about 2 s, the longest a joining receiver waits and the
    /// length of an HLS segment.
    int gop = 0;
    RateControl rate; ///< Bit rate (H.264, not lossless); default: the CRF alone.
    std::string title;                                     ///< Stream title ("color", "depth").
    std::vector<std::pair<std::string, std::string>> tags; ///< Extra stream metadata.
};

/// \return the settings of the color stream of a DepthTouch file ("color", H.264 4:2:0): \a width
/// × \a height at \a fps, x264 \a crf and \a preset, \a threads. The depth stream's settings are
/// these with its own codec, quality, title and tags.
VideoEncoderConfig colorStreamConfig(int width, int height, double fps, int crf,
                                     const std::string &preset, int threads);

/// \brief One stream's encoder, feeding its stream of a Muxer.
class VideoEncoder {
public:
    ~VideoEncoder();
    VideoEncoder(const VideoEncoder &) = delete;
    VideoEncoder &operator=(const VideoEncoder &) = delete;

    /// \brief Opens the codec and adds its stream to \a muxer. \pre muxer not started.
    /// \return the encoder; Errc::InvalidArgument for bad options (size, crf, preset),
    ///         Errc::NotSupported when FFmpeg lacks the encoder or the container cannot carry it
    ///         (FFV1 outside MKV).
    static Result<std::unique_ptr<VideoEncoder>> create(const VideoEncoderConfig &config,
                                                        Muxer &muxer);

    /// \brief Encodes one picture with presentation time \a ptsSeconds and writes the packets
    /// that come out. \param[in] image config.width × config.height in the codec's input layout
    /// (see VideoCodec). \pre Muxer started; PTS strictly increasing.
    /// \return Errc::InvalidArgument for a picture of the wrong size or layout or a PTS not
    ///         after the previous one, Errc::Io when writing fails.
    Result<void> encode(const Image &image, double ptsSeconds);

    /// \brief Drains the encoder's delayed frames into the muxer.
    Result<void> flush();

    /// \return frames encoded so far.
    [[nodiscard]] long long frames() const noexcept;
    /// \return compressed bytes produced so far.
    [[nodiscard]] long long bytes() const noexcept;

    struct Impl;

private:
    VideoEncoder();
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::media
