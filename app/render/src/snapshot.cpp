#include "depthtouch/render/snapshot.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "depthtouch/media/image.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/work_queue.h"
#include "depthtouch/render/render_target.h"

namespace depthtouch::render {

DT_LOG_CATEGORY(Snapshot)

namespace {

Result<void> writeRgb(const std::string &path, int width, int height,
                      const std::vector<std::uint8_t> &rgb)
{
    media::Image img = media::Image::make(width, height, media::PixelFormat::Rgb24);
    for (int y = 0; y < img.height; ++y)
        std::memcpy(img.row(y),
                    rgb.data() +
                        static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) * 3,
                    static_cast<std::size_t>(img.width) * 3);
    return media::writePng(path, img);
}

} // namespace

Result<void> writeSnapshot(const RenderTarget &target, const std::string &path)
{
    std::vector<std::uint8_t> rgb;
    if (auto r = target.readRgb(rgb); !r)
        return r;
    return writeRgb(path, target.width(), target.height(), rgb);
}

Snapshotter::Snapshotter(std::string dir, std::uint64_t everyN, std::string prefix)
    : dir_(std::move(dir)), prefix_(std::move(prefix)), everyN_(everyN)
{
}

Snapshotter::~Snapshotter()
{
    platform::raiseAndNotifyAll(mutex_, stop_, cv_);
    if (writer_)
        writer_->join();
}

Result<void> Snapshotter::write(const Job &job)
{
    auto r = writeRgb(job.path, job.width, job.height, job.rgb);
    if (r)
        written_.fetch_add(1, std::memory_order_acq_rel);
    return r;
}

void Snapshotter::writerLoop()
{
    std::unique_lock<std::mutex> lock(mutex_);
    // Until stopped, and everything written.
    while (std::optional<Job> job = platform::waitForJob(lock, cv_, stop_, queue_)) {
        busy_ = true;
        lock.unlock();
        auto r = write(*job);
        lock.lock();
        busy_ = false;
        if (!r) {
            DT_LOG(Snapshot, Error, "Failed to write %s: %s", job->path.c_str(), r.error().what);
            failed_ = true;
            failedErrno_ = r.error().sysErrno;
        }
        cv_.notify_all();
    }
}

bool Snapshotter::startWriter()
{
    if (writer_)
        return true;
    writer_.emplace(platform::kSnapshotThread, platform::kPlainThreadOptions,
                    [this](platform::StopToken) { writerLoop(); });
    if (auto r = writer_->start(); !r)
        writer_.reset(); // no thread to be had: this snapshot is written on the calling thread
    return writer_.has_value();
}

Result<void> Snapshotter::takeError()
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failed_)
        return ok();
    failed_ = false;
    return unexpected(Errc::Io, "Failed to write a snapshot", failedErrno_);
}

Result<void> Snapshotter::flush()
{
    {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [this] { return queue_.empty() && !busy_; });
    }
    return takeError();
}

Result<std::optional<std::string>> Snapshotter::onFrame(const RenderTarget &target)
{
    // An earlier snapshot's write error is reported now (this frame's snapshot is taken anyway).
    // It is taken before this frame's snapshot: the writer thread, already running, may fail this
    // frame's write before the call returns, and that error belongs to the next call.
    const Result<void> earlier = takeError();
    auto taken = snapshot(target);
    if (!earlier)
        return unexpected(earlier.error());
    return taken;
}

Result<std::optional<std::string>> Snapshotter::snapshot(const RenderTarget &target)
{
    const std::uint64_t frame = frames_++;
    const bool periodic = everyN_ > 0 && frame % everyN_ == 0;
    const bool requested = requested_.exchange(false, std::memory_order_relaxed);
    if (!periodic && !requested)
        return std::optional<std::string>{};
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
        return unexpected(Errc::Io, "Failed to create the snapshot directory");
    char name[64];
    std::snprintf(name, sizeof name, "-%06llu.png", static_cast<unsigned long long>(frame));
    Job job;
    job.path = dir_ + "/" + prefix_ + name;
    job.width = target.width();
    job.height = target.height();
    if (auto r = target.readRgb(job.rgb); !r)
        return unexpected(r.error());
    std::string path = job.path;
    {
        std::unique_lock<std::mutex> lock(mutex_);
        const bool writer = startWriter();
        if (writer && queue_.size() < kMaxQueued) {
            queue_.push_back(std::move(job));
            cv_.notify_all();
            return std::optional<std::string>{std::move(path)};
        }
    }
    // The writer is behind: write here rather than lose the snapshot.
    if (auto r = write(job); !r)
        return unexpected(r.error());
    return std::optional<std::string>{std::move(path)};
}

} // namespace depthtouch::render
