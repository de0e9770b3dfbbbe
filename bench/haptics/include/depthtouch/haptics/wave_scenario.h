#pragma once
/// \file
/// \brief The scenario of `depthtouch bench haptics`, shared by the benchmark and by the
/// `haptics_cost` instruction-count program: a travelling sinusoid sampled into 16-bit depth frames
/// (30 fps video, 1 kHz haptics) and a HIP held still or stroking 2 mm under it.
///
/// Surface (scene-box frame, docs/architecture.md §3, m, s): `z = A·sin(kx·x − ω·t)·cos(ky·y)`, A =
/// 3 mm, wavelengths 40 mm (x) and 50 mm (y), ω such that the motion repeats every 16 frames (the
/// frames are generated once and cycled). Allocates (not real-time). Thread-safety: const use is
/// reentrant.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::bench {

inline constexpr double kHapticRate = 1000.0; ///< Haptic updates per second, Hz.
inline constexpr double kVideoFps = 30.0;     ///< Depth frames per second, Hz.
/// Updates of the approach from above before the timed updates of a grid renderer.
inline constexpr std::size_t kSettleUpdates = 300;

/// \brief The analytic moving surface, its HIP trajectories and the ground-truth force.
class WaveScenario {
public:
    /// \brief Samples the 16 frames of one period at W×H into \a box. Allocates W·H·32 bytes.
    WaveScenario(int width, int height, const SceneBox &box);

    [[nodiscard]] int width() const noexcept { return width_; }
    [[nodiscard]] int height() const noexcept { return height_; }

    /// \return z of the analytic surface at (x, y) and time t, m.
    [[nodiscard]] static double surfaceZ(double x, double y, double t) noexcept;

    /// \return the HIP at time \a t (s) for a stroke at \a speed m/s (0 = still): back and forth
    /// along x over ±35 mm at y = 2 mm, 2 mm under the moving surface (still: at x = 3 mm, 2 mm
    /// under the wave's lowest point).
    [[nodiscard]] static glm::dvec3 hipAt(double speed, double t) noexcept;

    /// \return the HIP of update \a n: during the first \a settle updates it approaches linearly
    /// from 12 mm above the trajectory's start, then it follows hipAt().
    [[nodiscard]] static glm::dvec3 hipAtUpdate(double speed, std::size_t n,
                                                std::size_t settle) noexcept;

    /// \return the haptic time of update \a n, s.
    [[nodiscard]] static double timeAt(std::size_t n) noexcept
    {
        return static_cast<double>(n) / kHapticRate;
    }

    /// \return the index of the depth frame current at time \a t (frame i has PTS i/30 s).
    [[nodiscard]] static int frameIndexAt(double t) noexcept;

    /// \return the view of frame \a index (its PTS is index/30 s; pixels cycle with period 16).
    [[nodiscard]] DepthFrameView frame(int index) const noexcept;

    /// \return the ground-truth force at \a hip and time \a t: k × (closest point of the analytic
    /// surface − HIP) when the HIP is under the surface, clamped to the device maximum, N.
    [[nodiscard]] static glm::dvec3 trueForce(const glm::dvec3 &hip, double t,
                                              const RendererConfig &cfg) noexcept;

private:
    int width_;
    int height_;
    std::vector<std::vector<std::uint16_t>> frames_;
};

/// \brief The pop-through test of the wave's replays (`bench haptics`, `haptics_cost`): \return
/// whether \a proxy (m, box frame), the proxy \a renderer reported, lies under the surface it
/// renders (its own HeightField at its last setTime(); \a fallback, the current frame, for a
/// renderer without one: mesh-bvh; none: false) by more than the renderer's slack: r/4 for the
/// fingertip renderers (the finger's surface is a plane fit held within r/4 of the samples; both
/// pass their force proxy through the offset filter), a millionth of a pixel for the others.
bool poppedThrough(const HapticRenderer &renderer, const glm::dvec3 &proxy,
                   const HeightField *fallback = nullptr) noexcept;

} // namespace depthtouch::haptics::bench
