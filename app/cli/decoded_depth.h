#pragma once
/// \file
/// \brief The depth input of `depthtouch touch` through the `ffmpeg` media source and decoder
/// backends: frames decoded lazily and in order, 16-bit metric depth converted to nearness
/// (docs/architecture.md §3) with its invalid samples (0 and saturated) kept as holes, 10-bit
/// depth widened to 16 bits by bit replication as the player widens it, and every frame carrying
/// its hole threshold (DepthFrameView::holeBelow, §3 "Holes"). Used by cmd_touch.cpp only. Not
/// thread-safe.

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/occupancy.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::cli {

/// \brief Depth frames decoded by the `ffmpeg` backends, lazily and in order (the replay asks for
/// increasing indices and holds two frames): keeps the last few converted frames only.
class DecodedFrameProvider final : public haptics::FrameProvider {
public:
    struct Metric {
        depth::ConvertOptions convert;
    };

    /// Opens \a url; \a error receives a one-line message on failure. \a metric: the given
    /// planes (--near/--far), or nullopt; \a unplanned: the conversion used, with its range taken
    /// from the first frame, when \a metric is nullopt and the input's 16-bit samples are metric
    /// (it says nothing of depth).
    bool open(const std::string &url, double fps, std::optional<Metric> metric,
              const Metric &unplanned, std::string &error)
    {
        metric_ = std::move(metric);
        fps_ = fps;
        fpsOption_ = "fps=" + std::to_string(fps);
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(fpsOption_);
        auto src = drivers::createMediaSource("ffmpeg", cfg);
        if (!src) {
            error = std::string("no FFmpeg media source in this build: ") + src.error().what;
            return false;
        }
        source_ = std::move(*src);
        // The frames are counted first, then decoded: a FIFO cannot be read twice (and opening one
        // would wait for a writer).
        if (const auto kind = platform::pathKind(url.c_str());
            kind == platform::PathKind::Fifo || kind == platform::PathKind::Directory ||
            kind == platform::PathKind::Socket) {
            error = "cannot read depth input '" + url + "': it is " + platform::pathKindName(kind) +
                    " (touch reads the depth video twice: give a file)";
            return false;
        }
        if (auto r = source_->open(url.c_str()); !r) {
            error = "cannot read depth input '" + url + "': " + r.error().what + " (" +
                    errcName(r.error().code) + ")";
            return false;
        }
        if (!source_->info().seekable && url.find("://") == std::string::npos) {
            // The frames are counted first, then decoded: a pipe cannot be read twice.
            error =
                "depth input '" + url + "' cannot be read twice (a pipe): save it to a file first";
            return false;
        }
        const auto &streams = source_->info().streams;
        // The depth stream as play and probe find it: by title, MP4 handler name, MPEG-TS
        // service, or gray pixel format (an untagged TS, an HLS playlist); a single stream is
        // depth.
        stream_ = receiver::identifyStreams(source_->info(), receiver::SingleStream::Depth).depth;
        if (stream_ < 0) {
            error = "no depth stream in '" + url + "' (several streams, none titled depth or gray)";
            return false;
        }
        const hal::StreamInfo &si = streams[static_cast<std::size_t>(stream_)];
        // Nothing says depth (no title, no metadata: a depth camera's image sequence): 16-bit
        // samples are its metric depth.
        if (!metric_ && si.format == hal::PixelFormat::Gray16 && si.title.empty() &&
            si.depth.nearMetres == 0.0)
            metric_ = unplanned;
        config_ = hal::StreamConfig::fromStream(si);
        config_.kind = hal::StreamKind::Depth;
        if (config_.format != hal::PixelFormat::Gray8 &&
            config_.format != hal::PixelFormat::Gray10 &&
            config_.format != hal::PixelFormat::Gray16)
            config_.format = hal::PixelFormat::Gray8; // luma of a YUV/RGB stream, as is
        if (metric_ && config_.format == hal::PixelFormat::Gray8) {
            error = "--near/--far convert 16-bit metric depth; '" + url + "' has 8-bit samples";
            return false;
        }
        // 10-bit nearness comes out as 16 bits by bit replication, as in the player.
        if (!metric_ && config_.format == hal::PixelFormat::Gray10)
            config_.format = hal::PixelFormat::Gray16;
        holeBelow_ =
            metric_ ? kMetricOccupancy.threshold : receiver::depthHoleBelow(si, config_.format);
        // Count the frames (demux only) so the replay knows the last one.
        for (;;) {
            auto p = source_->readPacket();
            if (!p) {
                if (p.error().code != Errc::EndOfStream) {
                    error = "cannot read depth input '" + url + "': " + p.error().what;
                    return false;
                }
                break;
            }
            if (p->streamIndex == stream_)
                ++count_;
        }
        if (count_ == 0) {
            error = "depth input '" + url + "' has no frames";
            return false;
        }
        // Opened again rather than sought to 0: an MPEG-TS seek lands on a packet after the first
        // (a keyframe search by bytes), and the replay would find fewer frames than counted.
        source_->close();
        if (auto o = source_->open(url.c_str()); !o) {
            error = "cannot reopen depth input '" + url + "'";
            return false;
        }
        auto dec = drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
        if (!dec) {
            error = std::string("no FFmpeg video decoder: ") + dec.error().what;
            return false;
        }
        decoder_ = std::move(*dec);
        if (auto r = decoder_->configure(config_); !r) {
            error = "cannot decode depth input '" + url + "': " + r.error().what;
            return false;
        }
        url_ = url;
        return true;
    }

    [[nodiscard]] std::size_t frameCount() const noexcept override { return count_; }

    /// \return how the depth was read when the input said nothing of depth and no planes were
    /// given ("metric depth, near … m, far … m, the robust range of the first frame"); empty
    /// otherwise.
    [[nodiscard]] std::string readingNote() const
    {
        if (!rangeTaken_ || !metric_ || !metric_->convert.range)
            return {};
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "16-bit samples read as metric depth (%g m per unit), near %.4g m, far "
                      "%.4g m: the robust range of the first frame (--near/--far set them)",
                      metric_->convert.raw.metresPerUnit, metric_->convert.range->nearM,
                      metric_->convert.range->farM);
        return buf;
    }

    Result<scene::DepthFrameView> frame(std::size_t i) noexcept override
    {
        try {
            while (decoded_ <= i) {
                auto r = decodeNext();
                if (!r)
                    return unexpected(r.error());
            }
            const std::size_t first = decoded_ - frames_.size();
            if (i < first)
                return unexpected(Errc::InvalidArgument, "depth frame requested out of order");
            const Stored &f = frames_[i - first];
            scene::DepthFrameView v;
            v.data = f.bytes.data();
            v.width = config_.width;
            v.height = config_.height;
            v.format = f.format;
            v.strideBytes =
                static_cast<std::size_t>(config_.width) * scene::bytesPerSample(f.format);
            v.pts = f.pts;
            v.holeBelow = holeBelow_;
            return v;
        } catch (const std::bad_alloc &) {
            return unexpected(Errc::OutOfResources, "out of memory decoding the depth video");
        }
    }

private:
    struct Stored {
        std::vector<std::uint8_t> bytes;
        scene::SampleFormat format = scene::SampleFormat::Gray8;
        double pts = 0.0;
    };

    Result<void> decodeNext()
    {
        const platform::TimePoint now = platform::SteadyClock::instance().now();
        for (int guard = 0; guard < 1'000'000; ++guard) {
            auto f = decoder_->dequeueFrame(now);
            if (f)
                return store(**f);
            const Errc e = f.error().code;
            if (e == Errc::EndOfStream)
                return unexpected(Errc::InvalidArgument,
                                  "the depth video ended early (damaged or truncated)");
            if (e == Errc::Io)
                return unexpected(Errc::InvalidArgument, "a depth frame failed to decode");
            if (e != Errc::Timeout && e != Errc::InvalidState)
                return unexpected(f.error());
            // Needs input.
            if (eos_)
                continue;
            auto p = source_->readPacket();
            if (!p) {
                if (p.error().code != Errc::EndOfStream)
                    return unexpected(Errc::InvalidArgument, "cannot read the depth input");
                eos_ = true;
                DT_TRY(decoder_->queuePacket(hal::Packet::endOfStream(stream_)));
                continue;
            }
            if (p->streamIndex != stream_)
                continue;
            if (auto q = decoder_->queuePacket(*p); !q)
                return unexpected(Errc::InvalidArgument, "the decoder refused a depth packet");
        }
        return unexpected(Errc::InvalidArgument, "the depth decoder makes no progress");
    }

    Result<void> store(const hal::Frame &frame)
    {
        Stored s;
        s.pts = frame.pts == hal::kNoPts ? static_cast<double>(decoded_) / fps_
                                         : std::chrono::duration<double>(frame.pts).count();
        const hal::ImageView &img = frame.image;
        const int w = img.width;
        const int h = img.height;
        if (img.format == hal::PixelFormat::Gray8) {
            s.format = scene::SampleFormat::Gray8;
            s.bytes.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
            for (int y = 0; y < h; ++y)
                std::memcpy(s.bytes.data() +
                                static_cast<std::size_t>(y) * static_cast<std::size_t>(w),
                            img.row(0, y), static_cast<std::size_t>(w));
        } else {
            depth::Plane<std::uint16_t> raw(w, h);
            for (int y = 0; y < h; ++y)
                std::memcpy(&raw.at(0, y), img.row(0, y), static_cast<std::size_t>(w) * 2u);
            if (metric_) {
                if (!metric_->convert.range) {
                    auto r =
                        depth::robustRange(raw, metric_->convert.raw, metric_->convert.lowFraction,
                                           metric_->convert.highFraction);
                    if (!r)
                        return unexpected(Errc::InvalidArgument,
                                          "the first depth frame has no valid metric sample");
                    metric_->convert.range = *r;
                    rangeTaken_ = true;
                }
                auto n = depth::metricToNearness(raw, metric_->convert);
                if (!n)
                    return unexpected(n.error());
                // Invalid samples (0, saturated) are holes: free space, not a filled surface.
                std::size_t holes = 0;
                raw = depth::quantizeOccupied(n->nearness, n->valid, metric_->convert.vmax,
                                              kMetricOccupancy, holes);
            }
            s.format = scene::SampleFormat::Gray16;
            s.bytes.resize(raw.size() * 2u);
            std::memcpy(s.bytes.data(), raw.samples.data(), s.bytes.size());
        }
        frames_.push_back(std::move(s));
        if (frames_.size() > 4)
            frames_.pop_front();
        ++decoded_;
        return ok();
    }

    /// Metric depth converted here is coded as a lossless 16-bit stream would be.
    static constexpr depth::Occupancy kMetricOccupancy = depth::occupancyFor(16, true);

    std::unique_ptr<hal::MediaSource> source_;
    std::unique_ptr<hal::VideoDecoder> decoder_;
    hal::StreamConfig config_;
    std::optional<Metric> metric_;
    std::string fpsOption_;
    std::string url_;
    double fps_ = 30.0;
    int stream_ = -1;
    std::size_t count_ = 0;
    std::size_t decoded_ = 0;
    bool eos_ = false;
    bool rangeTaken_ = false;     ///< The planes are the first frame's robust range.
    std::uint32_t holeBelow_ = 0; ///< Every frame's DepthFrameView::holeBelow.
    std::deque<Stored> frames_;
};

} // namespace depthtouch::cli
