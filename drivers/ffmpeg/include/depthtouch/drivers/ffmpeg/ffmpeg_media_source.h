#pragma once
/// \file
/// \brief FfmpegMediaSource: libavformat demuxer of files, URLs and image sequences. Backend name
/// `ffmpeg`.
///
/// Inputs: anything libavformat opens, plus printf-pattern image sequences (`d/frame-%06d.png`, the
/// image2 demuxer). Options (BackendConfig::options): `fps=N` frame rate of an image sequence
/// (default 25), `format=NAME` forces the demuxer, `timeout_ms=N` bounds a blocking read (default
/// 10000; network inputs). A FIFO is opened without blocking and waits timeout_ms at most for its
/// writer (Errc::Timeout), then is read as a non-seekable stream whose reads honour the timeout.
///
/// Streams: only video streams are listed (StreamInfo::index renumbers them 0..n-1). Kind from the
/// stream title `color`/`depth`; an untitled stream of a one-stream input is depth when its pixel
/// format is gray/gray10/gray16, else color. An H.264 stream whose SPS says 4:0:0 (monochrome) is
/// gray (StreamInfo::format Gray8/Gray10/Gray16) though libavcodec reports it as yuv(j)420p.
/// Depth metadata from the tags depth_near, depth_far, depth_mapping, depth_bits, depth_occupancy
/// on the stream, else on the container; a value that is not a positive finite number
/// (depth_bits: 1..16; depth_occupancy: a whole number 1..65535) is ignored.
///
/// Still-image codecs the HAL has no CodecId for (PNG, TIFF, BMP, PGM…, i.e. image sequences) are
/// decoded here and delivered as CodecId::RawVideo packets: one tightly packed image per packet in
/// the StreamInfo::format (host byte order), which any VideoDecoder for RawVideo turns into frames.
///
/// Times: Packet::pts/dts are nanoseconds from the container's start time. A packet without a PTS
/// gets its DTS, else the previous PTS plus one frame duration.
/// Stop: interrupt() (any thread) sets a flag that libavformat's interrupt callback reads, next to
/// the timeout_ms deadline, so a blocking read, seek or open returns within about 100 ms
/// (Errc::Timeout "Interrupted by a stop request"); the flag holds until close(). cancelRead()
/// does the same for one blocked read (a seek's request), consumed by that read or by seek().
/// Thread-safety: as hal::MediaSource (thread-bound; interrupt() from any thread).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/media_source_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief Settings of FfmpegMediaSource (from the backend options).
struct FfmpegSourceSettings {
    double fps = 0.0;       ///< Image-sequence frame rate (`fps`); 0 = demuxer default.
    std::string format;     ///< Forced demuxer (`format`); empty = probe.
    int timeoutMs = 10'000; ///< Longest blocking libavformat call (`timeout_ms`).
    /// Bytes the stream-info probe reads at most (`probesize`, ffmpeg's option and unit); 0 =
    /// libavformat's 5 000 000.
    int probeSize = 0;
    /// Media time the stream-info probe reads at most, microseconds (`analyzeduration`, ffmpeg's
    /// option and unit); 0 = kLiveAnalyzeDurationUs for a live input (a network URL, a FIFO),
    /// libavformat's 5 s for a file.
    int analyzeDurationUs = 0;
    /// A live input's `analyzeduration` by default: 3 s, longer than the 2 s between key frames
    /// that `depthtouch encode` writes to URLs (a receiver joining just after one waits for the
    /// next), shorter than libavformat's 5 s (docs/playing.md "Tune-in").
    static constexpr int kLiveAnalyzeDurationUs = 3'000'000;
    /// HLS multivariant input: the variant kept (`rendition`: highest, lowest or a height in
    /// pixels, the tallest at most that); 0 = highest, -1 = lowest (drivers/ffmpeg/src/
    /// hls_variants.h).
    int renditionHeight = 0;
    /// `rendition=auto` (the default): start at the tallest, change with the throughput
    /// (drivers/ffmpeg/src/rendition_switch.h).
    bool renditionAuto = true;

    /// \return the settings, or InvalidArgument for an unknown key or a bad value.
    static Result<FfmpegSourceSettings> parse(hal::OptionList options);
};

class FfmpegMediaSource final : public hal::MediaSourceBase {
public:
    /// Backend factory.
    static Result<std::unique_ptr<hal::MediaSource>> create(const hal::BackendConfig &cfg);

    FfmpegMediaSource(platform::Clock &clock, FfmpegSourceSettings settings);
    ~FfmpegMediaSource() override;

    void interrupt() noexcept override;
    void cancelRead() noexcept override;
    [[nodiscard]] Result<void> deliverAudio(int containerIndex) override;

protected:
    // hal::MediaSourceBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> openDevice(const char *url) override;
    void closeDevice() noexcept override;
    [[nodiscard]] const hal::MediaInfo &infoDevice() const noexcept override;
    [[nodiscard]] Result<hal::Packet> readPacketDevice() override;
    [[nodiscard]] Result<void> seekDevice(hal::Pts position) override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::drivers
