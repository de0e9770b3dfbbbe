#pragma once
/// \file
/// \brief Snapshots of the presented frame: read the render target back (glReadPixels) and write it
/// as PNG through dt_media (libavcodec's PNG encoder), every N frames or on request, so a headless
/// box can show what the viewer sees. The read-back happens on the calling (render) thread; the PNG
/// encoding (about 50 ms for 1280×480 here, a frame and a half) on a writer thread of its own, so
/// a snapshot does not make the next frames late.
///
/// Thread-safety: thread-bound (the render thread: read-back needs the GL context). request() is
/// the exception: it may be called from any thread.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::render {

class RenderTarget;

/// \brief Writes the colour buffer of \a target to \a path as an 8-bit RGB PNG (top row first).
/// \return Errc::InvalidState (not an RGBA8 target), Errc::Io (read-back or file write failed).
Result<void> writeSnapshot(const RenderTarget &target, const std::string &path);

/// \brief Writes `DIR/PREFIX-NNNNNN.png` (NNNNNN = frame number) every \a everyN frames and
/// whenever request() was called since the last frame.
class Snapshotter {
public:
    /// \param dir existing or creatable directory \param everyN 0 = only on request
    Snapshotter(std::string dir, std::uint64_t everyN, std::string prefix = "snapshot");
    /// Waits until every snapshot taken has been written.
    ~Snapshotter();
    Snapshotter(const Snapshotter &) = delete;
    Snapshotter &operator=(const Snapshotter &) = delete;

    /// Asks for a snapshot of the next frame. Thread-safe.
    void request() noexcept { requested_.store(true, std::memory_order_relaxed); }

    /// \brief Call once per presented frame, after drawing it into \a target. A snapshotted frame
    /// is read back now and written by the writer thread (on this thread when kMaxQueued are
    /// waiting already: none is lost).
    /// \return the path the frame goes to, nullopt when this frame is not snapshotted;
    /// Errc::InvalidState (not an RGBA8 target), Errc::Io when the directory cannot be made or an
    /// earlier snapshot could not be written (reported once, by the next call, which still takes
    /// its own frame's snapshot).
    Result<std::optional<std::string>> onFrame(const RenderTarget &target);

    /// \brief Waits until every snapshot taken has been written.
    /// \return the first write error not yet reported (Errc::Io).
    Result<void> flush();

    [[nodiscard]] std::uint64_t frames() const noexcept { return frames_; } ///< Frames seen.
    /// PNGs written so far (the writer thread's count; after flush(), every snapshot taken).
    [[nodiscard]] std::uint64_t written() const noexcept
    {
        return written_.load(std::memory_order_acquire);
    }

    static constexpr std::size_t kMaxQueued = 3; ///< Snapshots waiting for the writer, at most.

private:
    struct Job {
        std::string path;
        int width = 0;
        int height = 0;
        std::vector<std::uint8_t> rgb; ///< width × height × 3, top row first.
    };
    Result<std::optional<std::string>> snapshot(const RenderTarget &target);
    void writerLoop();
    /// Starts the writer thread unless it runs (mutex_ held). \return false: no thread to be had.
    bool startWriter();
    Result<void> write(const Job &job);
    Result<void> takeError();

    std::string dir_;
    std::string prefix_;
    std::uint64_t everyN_ = 0;
    std::uint64_t frames_ = 0;
    std::atomic<std::uint64_t> written_{0};
    std::atomic<bool> requested_{false};
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Job> queue_;  ///< Guarded by mutex_.
    bool busy_ = false;      ///< The writer is writing a job (guarded by mutex_).
    bool stop_ = false;      ///< Guarded by mutex_.
    bool failed_ = false;    ///< A write failed since the last report (guarded by mutex_).
    int failedErrno_ = 0;    ///< errno of that failure, 0 when unknown (guarded by mutex_).
    /// The writer thread (kSnapshotThread), started with the first snapshot (guarded by mutex_).
    std::optional<platform::RealtimeThread> writer_;
};

} // namespace depthtouch::render
