#include "depthtouch/receiver/depth_file.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <new>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::receiver {

namespace {

/// Metric depth converted here is coded as a lossless 16-bit stream would be.
constexpr depth::Occupancy kMetricOccupancy = depth::occupancyFor(16, true);

} // namespace

DepthFile::DepthFile(std::unique_ptr<hal::MediaSource> source,
                     std::unique_ptr<hal::VideoDecoder> decoder, double fps) noexcept
    : source_(std::move(source)), decoder_(std::move(decoder)), fps_(fps)
{
}

DepthFile::~DepthFile() = default;

bool DepthFile::open(const std::string &url, std::optional<Metric> metric, const Metric &unplanned,
                     std::string &error)
{
    metric_ = std::move(metric);
    if (!source_ || !decoder_) {
        error = "no media source or video decoder to read depth input '" + url + "' with";
        return false;
    }
    // The frames are counted first, then decoded: a FIFO cannot be read twice (and opening one
    // would wait for a writer).
    if (const auto kind = platform::pathKind(url.c_str()); kind == platform::PathKind::Fifo ||
                                                           kind == platform::PathKind::Directory ||
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
        error = "depth input '" + url + "' cannot be read twice (a pipe): save it to a file first";
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
    if (config_.format != hal::PixelFormat::Gray8 && config_.format != hal::PixelFormat::Gray10 &&
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
    if (auto r = decoder_->configure(config_); !r) {
        error = "cannot decode depth input '" + url + "': " + r.error().what;
        return false;
    }
    return true;
}

std::string DepthFile::readingNote() const
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

Result<scene::DepthFrameView> DepthFile::frame(std::size_t i) noexcept
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
        v.strideBytes = static_cast<std::size_t>(config_.width) * scene::bytesPerSample(f.format);
        v.pts = f.pts;
        v.holeBelow = holeBelow_;
        return v;
    } catch (const std::bad_alloc &) {
        return unexpected(Errc::OutOfResources, "out of memory decoding the depth video");
    }
}

Result<void> DepthFile::decodeNext()
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

Result<void> DepthFile::store(const hal::Frame &frame)
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
            std::memcpy(s.bytes.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w),
                        img.row(0, y), static_cast<std::size_t>(w));
    } else {
        depth::Plane<std::uint16_t> raw(w, h);
        for (int y = 0; y < h; ++y)
            std::memcpy(&raw.at(0, y), img.row(0, y), static_cast<std::size_t>(w) * 2u);
        if (metric_) {
            if (!metric_->convert.range) {
                auto r = depth::robustRange(raw, metric_->convert.raw, metric_->convert.lowFraction,
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

} // namespace depthtouch::receiver
