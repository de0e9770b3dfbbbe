#pragma once
/// \file
/// \brief Recorder: the output recording. Presented frames are read back on the render thread and
/// encoded (x264, H.264 4:2:0) by a thread of its own (kRecordThread), so the encoder's time per
/// frame does not add to every frame's draw. At most kQueue frames wait; when the encoder is that
/// far behind the render thread waits for it, so every presented frame is recorded. PTS is the
/// presentation time since the first recorded frame (strictly increasing).
///
/// Thread-safety: open(), add(), finish() and the destructor on one thread (the render thread);
/// the encoder thread is internal. Built with EGL/GLES only (gl_presenter.cpp).

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/media/encoder.h"
#include "depthtouch/media/image.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/render/render_target.h"

namespace depthtouch::playback {

/// See the file comment.
class Recorder {
public:
    bool failed = false; ///< Render thread: recording stopped after an error.

    Recorder() = default;
    Recorder(const Recorder &) = delete;
    Recorder &operator=(const Recorder &) = delete;
    ~Recorder() { (void)finish(); }

    /// \return whether open() succeeded.
    [[nodiscard]] bool isOpen() const noexcept { return encoder_ != nullptr; }

    /// \brief Opens config.recordPath (muxer by extension) for frames of \a width × \a height
    /// pixels (rounded down to even) and starts the encoder thread.
    /// \return an error text, or empty.
    std::string open(const PlaybackConfig &config, int width, int height);

    /// \brief Reads \a target back and queues it for encoding at presentation time \a now.
    /// \return an error text (of this frame, or of the encoding of an earlier one), or empty.
    std::string add(const render::RenderTarget &target, platform::TimePoint now);

    /// \brief Encodes what is queued, ends the file (renamed into place only when complete) and
    /// stops the thread (once).
    /// \return why the file could not be finished (nothing is then left under its name), or empty
    /// (also when nothing was recording).
    std::string finish() noexcept;

private:
    struct Job {
        media::Image image;
        double pts = 0.0;
    };
    static constexpr std::size_t kQueue = 3;

    void encodeLoop();

    std::unique_ptr<media::Muxer> muxer_;
    std::unique_ptr<media::VideoEncoder> encoder_;
    int width_ = 0;
    int height_ = 0;
    std::vector<std::uint8_t> rgb_; ///< Render thread: the read-back.
    platform::TimePoint start_{};
    double lastPts_ = -1.0;
    std::optional<platform::RealtimeThread> thread_; ///< The encoder thread (kRecordThread).
    std::mutex mutex_;
    std::condition_variable workCv_;  ///< A job or stop for the encoder thread.
    std::condition_variable spaceCv_; ///< Room in the queue (or an error) for the render thread.
    std::deque<Job> queue_;           ///< Guarded by mutex_.
    std::vector<media::Image> spare_; ///< Encoded frames' images, reused (guarded by mutex_).
    std::string error_;               ///< First encoding error (guarded by mutex_).
    bool stop_ = false;               ///< Guarded by mutex_.
};

} // namespace depthtouch::playback
