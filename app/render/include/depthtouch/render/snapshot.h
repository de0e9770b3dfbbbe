#pragma once
/// \file
/// \brief Snapshots of the presented frame: read the render target back (glReadPixels) and write it
/// as PNG through dt_media (libavcodec's PNG encoder), every N frames or on request, so a headless
/// box can show what the viewer sees.
///
/// Thread-safety: thread-bound (the render thread: read-back needs the GL context). request() is
/// the exception: it may be called from any thread.

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

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

    /// Asks for a snapshot of the next frame. Thread-safe.
    void request() noexcept { requested_.store(true, std::memory_order_relaxed); }

    /// \brief Call once per presented frame, after drawing it into \a target.
    /// \return the path written, nullopt when this frame is not snapshotted; Errc::Io when the
    /// directory cannot be made or the file cannot be written.
    Result<std::optional<std::string>> onFrame(const RenderTarget &target);

    [[nodiscard]] std::uint64_t frames() const noexcept { return frames_; }   ///< Frames seen.
    [[nodiscard]] std::uint64_t written() const noexcept { return written_; } ///< PNGs written.

private:
    std::string dir_;
    std::string prefix_;
    std::uint64_t everyN_ = 0;
    std::uint64_t frames_ = 0;
    std::uint64_t written_ = 0;
    std::atomic<bool> requested_{false};
};

} // namespace depthtouch::render
