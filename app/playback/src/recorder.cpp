/// \file
/// \brief Recorder: see recorder.h.

#include "recorder.h"

#include <cstring>
#include <optional>

#include "depthtouch/platform/log.h"
#include "depthtouch/platform/thread_config.h"
#include "depthtouch/platform/work_queue.h"

DT_LOG_CATEGORY(Playback)

namespace depthtouch::playback {

std::string Recorder::open(const PlaybackConfig &config, int width, int height)
{
    media::MuxerOptions mo;
    mo.output = config.recordPath;
    auto m = media::Muxer::open(mo);
    if (!m)
        return std::string("cannot record to '") + config.recordPath + "': " + m.error().what;
    media::VideoEncoderConfig vc;
    vc.codec = media::VideoCodec::H264Yuv420p;
    vc.width = width & ~1;
    vc.height = height & ~1;
    vc.crf = config.recordCrf;
    vc.preset = config.recordPreset;
    vc.title = "output";
    auto e = media::VideoEncoder::create(vc, **m);
    if (!e)
        return std::string("cannot record: ") + e.error().what;
    if (auto r = (*m)->start(); !r)
        return std::string("cannot record: ") + r.error().what;
    muxer_ = std::move(*m);
    encoder_ = std::move(*e);
    width_ = vc.width;
    height_ = vc.height;
    thread_.emplace(platform::kRecordThread, platform::kPlainThreadOptions,
                    [this](platform::StopToken) { encodeLoop(); });
    if (auto r = thread_->start(); !r) {
        thread_.reset();
        encoder_.reset();
        muxer_.reset();
        return "cannot record: no thread for the encoder";
    }
    return {};
}

std::string Recorder::add(const render::RenderTarget &target, platform::TimePoint now)
{
    std::unique_lock<std::mutex> lock(mutex_);
    spaceCv_.wait(lock, [this] { return queue_.size() < kQueue || !error_.empty(); });
    if (!error_.empty())
        return error_;
    Job job;
    if (!spare_.empty()) {
        job.image = std::move(spare_.back());
        spare_.pop_back();
    }
    lock.unlock();
    if (job.image.width != width_ || job.image.height != height_)
        job.image = media::Image::make(width_, height_, media::PixelFormat::Rgb24);
    if (auto r = target.readRgb(rgb_); !r)
        return std::string("cannot read the frame back: ") + r.error().what;
    const std::size_t srcRow = static_cast<std::size_t>(target.width()) * 3;
    const std::size_t dstRow = static_cast<std::size_t>(width_) * 3;
    for (int y = 0; y < height_; ++y)
        std::memcpy(job.image.row(y), rgb_.data() + static_cast<std::size_t>(y) * srcRow, dstRow);
    if (lastPts_ < 0.0)
        start_ = now;
    double pts = platform::toSeconds(now - start_);
    if (pts <= lastPts_)
        pts = lastPts_ + 1e-3;
    lastPts_ = pts;
    job.pts = pts;
    lock.lock();
    queue_.push_back(std::move(job));
    workCv_.notify_one();
    return {};
}

std::string Recorder::finish() noexcept
{
    if (!thread_ || !thread_->joinable())
        return {};
    platform::raiseAndNotifyAll(mutex_, stop_, workCv_); // the encoder thread is its one waiter
    thread_->join();
    std::string why = error_;
    if (why.empty()) {
        if (auto f = encoder_->flush(); !f)
            why = std::string("cannot encode the recording: ") + f.error().what;
    }
    if (why.empty()) {
        if (auto m = muxer_->finish(); !m) {
            char text[160];
            why =
                std::string("cannot finish the recording: ") + m.error().format(text, sizeof text);
        }
    }
    if (!why.empty()) {
        DT_LOG(Playback, Error, "The recording could not be finished: %s", why.c_str());
        muxer_->abort(); // the temporary file goes; nothing is left under the final name
    }
    encoder_.reset();
    muxer_.reset();
    return why;
}

void Recorder::encodeLoop()
{
    std::unique_lock<std::mutex> lock(mutex_);
    while (std::optional<Job> job = platform::waitForJob(lock, workCv_, stop_, queue_)) {
        lock.unlock();
        auto r = encoder_->encode(job->image, job->pts);
        lock.lock();
        if (!r && error_.empty()) {
            error_ = std::string("cannot encode the recording: ") + r.error().what;
            queue_.clear();
        }
        spare_.push_back(std::move(job->image));
        spaceCv_.notify_one();
    }
}

} // namespace depthtouch::playback
