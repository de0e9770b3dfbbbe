#pragma once
/// \file
/// \brief MockDepthCamera: a simulated RGB-D camera looking at a sphere that moves in front of a
/// wall, paced on the injected clock, with fault injection. Backend name `mock`.
///
/// Scene (camera frame: x right, y down, z forward along the optical axis, metres): a flat wall at
/// z = kMockWallMetres and a sphere of radius kMockSphereRadius whose centre moves on an ellipse at
/// z = kMockSphereDepth (mockSphereCentre()). Pinhole with a 60° horizontal field of view. Wall
/// pixels in the sphere's shadow (the few pixels left of its silhouette, as a structured-light
/// camera sees them) have no measurement (0). Depth: Z16 millimetres or Gray16 nearness; color:
/// Rgb24, a checkerboard wall and a shaded red sphere. Frames: frame k is exposed at start() + k /
/// fps; sequence = k; pts = k / fps. Thread-safety: thread-bound, as hal::DepthCamera; the
/// fault-injection calls too.

#include <cstdint>
#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/depth_camera_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

class FramePool;

inline constexpr double kMockWallMetres = 1.2;
inline constexpr double kMockSphereRadius = 0.12;
inline constexpr double kMockSphereDepth = 0.7;

/// \return the sphere centre (camera frame, metres) \a seconds after start().
hal::Vec3 mockSphereCentre(double seconds) noexcept;

/// \brief Pool size of the mock camera.
struct MockCameraSettings {
    int poolFrames = 4; ///< Frames per stream (option `pool`, 1..32).

    /// \return the settings from \a options; InvalidArgument for an unknown key or a value out of
    /// range.
    static Result<MockCameraSettings> parse(hal::OptionList options);
};

class MockDepthCamera final : public hal::DepthCameraBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::DepthCamera>> create(const hal::BackendConfig &cfg);

    explicit MockDepthCamera(platform::Clock &clock, const MockCameraSettings &settings = {});
    ~MockDepthCamera() override;

    /// \name Fault injection
    ///@{
    /// Unplugs the camera: capture(), start() and configure() return NoDevice until replug().
    void unplug() noexcept { present_ = false; }
    void replug() noexcept { present_ = true; }
    /// The next \a count frames are lost on the way (capture() skips them: sequence gap).
    void dropFrames(int count) noexcept
    {
        pendingDrops_ += count > 0 ? static_cast<std::uint64_t>(count) : 0;
    }
    ///@}

    /// \return frames skipped since start() (injected drops, late consumer, full pool).
    [[nodiscard]] std::uint64_t framesDropped() const noexcept { return dropped_; }

protected:
    // hal::DepthCameraBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> configureDevice(const hal::CameraConfig &cfg) override;
    [[nodiscard]] hal::CameraIntrinsics intrinsicsDevice() const noexcept override;
    [[nodiscard]] Result<void> startDevice() override;
    [[nodiscard]] Result<hal::Capture> captureDevice(hal::Deadline until) override;
    void stopDevice() noexcept override {}

private:
    [[nodiscard]] platform::TimePoint exposure(std::uint64_t k) const noexcept;
    void render(hal::Frame *depth, hal::Frame *color, double seconds) const noexcept;

    platform::Clock &clock_;
    const MockCameraSettings settings_;
    std::unique_ptr<FramePool> depthPool_;
    std::unique_ptr<FramePool> colorPool_;
    hal::CameraConfig config_;
    bool present_ = true;
    platform::TimePoint start_{};
    std::uint64_t next_ = 0; ///< Index of the next frame to deliver.
    std::uint64_t pendingDrops_ = 0;
    std::uint64_t dropped_ = 0;
};

} // namespace depthtouch::drivers
