#pragma once
/// \file
/// \brief HapticSession: the haptic side of DepthTouch's GStreamer elements (issue 62), without
/// GStreamer: the haptic device opened from the backend table as `play --haptic NAME
/// --haptic-options OPTS` opens it, the depth hand-off (haptic_task::DepthHandoff) and the 1 kHz
/// haptic task (haptic_task::HapticTask) on it, configured by `play`'s own option table
/// (app/cli/play_options.h: its checks, ranges and messages, and where each option lands), so an
/// element and `play` with the same settings run the same task.
///
/// Lifetime, as a GstBaseSink drives it: open() at start() (the device; a bad setting or a device
/// that does not open fails here), configure() when the caps give the frame size and format
/// (allocates the hand-off, creates and starts the task; a new size stops and replaces them),
/// push() per buffer, restart() after a flush, finish() at the end of the stream, and the
/// destructor (or close()) at stop(): zero force, the task stopped, the device closed.
///
/// Units and frames: docs/architecture.md §3 (metres, seconds, newtons; scene box x right, y up,
/// z toward the viewer). Thread-safety: every member function may be called from any thread; an
/// internal mutex (never taken by the haptic thread, which only sees the task's lock-free
/// controls and the hand-off) serialises configure(), push(), close() and the observers.

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <glm/vec3.hpp>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::gst {

/// \brief The settings an element takes from its properties; the defaults are `play`'s
/// (cli::PlayOptions' initializers).
struct HapticSettings {
    HapticSettings();
    std::string device;        ///< Backend name(s), comma-separated, tried in order (`--haptic`).
    std::string deviceOptions; ///< The backend's key=value options (`--haptic-options`).
    double stiffness;          ///< Surface stiffness, N/m, options::kStiffness's range.
    std::string method;        ///< Renderer, a name of the renderer table (`--method`).
};

/// \return an empty string, or the one-line message of the first setting out of range, in the
/// words of `play`'s option table with the property's name ("method must be one of: ...").
std::string checkHapticSettings(const HapticSettings &settings);

/// \brief What the task measured so far (zeros before the task runs).
struct HapticReadout {
    glm::dvec3 force{};            ///< Last force commanded, N, scene-box frame.
    glm::dvec3 hip{};              ///< HIP of the last rendered update, m, scene box.
    glm::dvec3 proxy{};            ///< Proxy of the last rendered update, m, scene box.
    bool posed = false;            ///< hip and proxy hold an update.
    std::uint64_t updates = 0;     ///< Cycles of the haptic loop.
    double servoRateHz = 0.0;      ///< Updates per second measured over the run, Hz (0 before 2).
    std::uint64_t safetyTrips = 0; ///< Renderer force-jump releases + watchdog trips.
    /// Of safetyTrips, the watchdog's (a missed deadline, a device time-out): the machine's load
    /// where the haptic thread is not SCHED_FIFO.
    std::uint64_t watchdogTrips = 0;
    std::uint64_t contactUpdates = 0; ///< Rendered cycles with the proxy on the surface.
    double maxForce = 0.0;            ///< Largest force magnitude commanded, N.
};

class HapticSession {
public:
    /// \brief Checks \a settings (checkHapticSettings()) and opens the device of the backend
    /// table (drivers::createHapticDevice, as `play` does). \a clock must outlive the session.
    /// \return the session, or null with \a why set: the bad setting's message, or the backend
    /// table's report (an unknown backend, bad backend options, a device that does not open).
    static std::unique_ptr<HapticSession> open(const HapticSettings &settings,
                                               platform::Clock &clock, std::string &why);
    /// close().
    ~HapticSession();

    /// \return true when the device is `none` (haptics off: configure() and push() do nothing).
    [[nodiscard]] bool noDevice() const noexcept { return device_ == nullptr; }
    /// \return the backend that opened ("sim", "falcon", "none").
    [[nodiscard]] const std::string &deviceName() const noexcept { return deviceName_; }

    /// \brief Sets up the hand-off for \a width × \a height frames of \a format and starts the
    /// haptic task on it; the same size and format again keeps them. \return Errc::InvalidArgument
    /// (size below 2 or above 16384), the task's create() or start() error.
    [[nodiscard]] Result<void> configure(int width, int height, scene::SampleFormat format);
    /// \brief Publishes \a frame (copied) to the haptic thread as the newest pair (previous frame,
    /// \a frame); its pts is the buffer's running time, s. \a origin is the clock time (of the
    /// clock given to open()) at which the running time was 0. \return the hand-off's error for a
    /// frame of another size or format; nothing is done before configure() or with no device.
    [[nodiscard]] Result<void> push(const scene::DepthFrameView &frame, platform::TimePoint origin);
    /// \brief After a flush (seek): the next frame starts a new pair and the haptic time restarts.
    void restart() noexcept;
    /// \brief End of the stream: the last frame holds still.
    void finish() noexcept;
    /// \brief Sets the stiffness at run time, N/m (options::kStiffness; ignored outside it).
    void setStiffness(double newtonsPerMetre) noexcept;
    /// \return the last force, pose and counters.
    [[nodiscard]] HapticReadout readout();
    /// \brief Zero force, the task stopped, the device closed. Idempotent.
    void close() noexcept;

private:
    HapticSession(platform::Clock &clock, haptic_task::HapticTaskConfig config,
                  std::unique_ptr<hal::HapticDevice> device, std::string deviceName);
    DT_DISABLE_COPY_AND_MOVE(HapticSession)

    /// Stops and drops the task and the hand-off. \pre mutex_ held.
    void dropTask() noexcept;

    platform::Clock &clock_;
    const haptic_task::HapticTaskConfig config_;
    std::unique_ptr<hal::HapticDevice> device_; ///< Null for `none`.
    const std::string deviceName_;
    std::mutex mutex_;
    double stiffness_;
    std::unique_ptr<haptic_task::DepthHandoff> handoff_;
    std::unique_ptr<haptic_task::HapticTask> task_; ///< Destroyed before handoff_.
};

} // namespace depthtouch::gst
