#pragma once
/// \file
/// \brief Level-of-detail control for the drawn surface: the quadtree's leaf-block budget
/// (MeshOptions::maxBlocks) chosen frame by frame from the measured draw times, so that drawing a
/// frame stays within a share of the frame period where the renderer is slow (a software
/// rasterizer, a loaded SoC) and the mesh keeps its full tolerance where it is fast. Feedback on
/// frame time, as games scale their render resolution; here the triangle count is the knob, since
/// a per-triangle cost (setup and binning, about 0.2 µs a triangle an eye on llvmpipe) is what
/// grows with the scene's detail. The haptic renderer is not touched: it always works on the
/// full-resolution height field.
///
/// Control law (after each drawn frame, on the median of the last `window` draw times, so a single
/// stall does not move it):
/// - over the target: the budget becomes the blocks just drawn × target / median (at least
///   `maxShrink` of them, at most 0.9), not below `minBlocks`. Taking the time as proportional to
///   the blocks overestimates what a block costs (a frame also has a fixed cost, its pixels), so
///   a step shrinks too little, never too much; where the fixed cost alone is over the target the
///   budget comes to rest on `minBlocks`;
/// - under `growBelow` × target, while the budget is what limits the mesh: the budget grows by
///   `growFactor`;
/// - otherwise it holds. After each change the window restarts, so the next decision sees only
///   frames drawn after it (the player's mesh is made a frame ahead).
/// It starts at `initialBlocks`: dropping frames while it finds its level costs the viewer more
/// than a few coarser frames.
///
/// Thread-safety: thread-bound (the render thread). No allocation.

#include <array>
#include <cstddef>

#include "depthtouch/render/adaptive_mesh.h"

namespace depthtouch::render {

/// \brief LodController settings.
struct LodOptions {
    double targetSeconds = 0.025;  ///< Draw-time goal per frame, s (> 0).
    std::size_t initialBlocks = 4000; ///< Budget of the first frames, leaf blocks.
    std::size_t minBlocks = 500;   ///< The budget never goes below this, leaf blocks (the
                                   ///< player: one block per 16 × 16 samples).
    int window = 5;                ///< Draw times in the median, 1..kMaxWindow.
    double growBelow = 0.8;        ///< Grow only under this share of the target.
    double growFactor = 1.15;      ///< Growth per decision (> 1).
    double maxShrink = 0.35;       ///< Smallest shrink factor per decision (0..1).

    static constexpr int kMaxWindow = 15;
};

/// See the file comment.
class LodController {
public:
    /// \pre \a options within the ranges documented (else they are clamped into them).
    explicit LodController(const LodOptions &options) noexcept;

    /// \brief Takes the draw time of a frame, s, and the stats of the mesh it drew.
    /// \return the budget for the next meshes (MeshOptions::maxBlocks).
    std::size_t update(double drawSeconds, const MeshStats &mesh) noexcept;

    /// \return the current budget, leaf blocks.
    [[nodiscard]] std::size_t budget() const noexcept { return budget_; }
    /// \return the median of the draw times in the window, s (0 before the first).
    [[nodiscard]] double medianSeconds() const noexcept;

private:
    LodOptions options_;
    std::size_t budget_;
    std::array<double, LodOptions::kMaxWindow> times_{};
    int count_ = 0; ///< Times in the window (since the last change).
};

} // namespace depthtouch::render
