#include "depthtouch/render/lod_controller.h"

#include <algorithm>
#include <cmath>

namespace depthtouch::render {

namespace {

LodOptions clamped(LodOptions o) noexcept
{
    if (!(o.targetSeconds > 0.0))
        o.targetSeconds = 0.025;
    o.minBlocks = std::max<std::size_t>(o.minBlocks, 1);
    o.initialBlocks = std::max(o.initialBlocks, o.minBlocks);
    o.window = std::clamp(o.window, 1, LodOptions::kMaxWindow);
    if (!(o.growBelow > 0.0 && o.growBelow <= 1.0))
        o.growBelow = 0.8;
    if (!(o.growFactor > 1.0))
        o.growFactor = 1.15;
    if (!(o.maxShrink > 0.0 && o.maxShrink < 1.0))
        o.maxShrink = 0.35;
    return o;
}

} // namespace

LodController::LodController(const LodOptions &options) noexcept
    : options_(clamped(options)), budget_(options_.initialBlocks)
{
}

double LodController::medianSeconds() const noexcept
{
    if (count_ == 0)
        return 0.0;
    std::array<double, LodOptions::kMaxWindow> sorted = times_;
    const auto n = static_cast<std::ptrdiff_t>(count_);
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.begin() + n);
    return sorted[static_cast<std::size_t>(n / 2)];
}

std::size_t LodController::update(double drawSeconds, const MeshStats &mesh) noexcept
{
    if (!std::isfinite(drawSeconds) || drawSeconds < 0.0)
        return budget_;
    if (count_ < options_.window) {
        times_[static_cast<std::size_t>(count_++)] = drawSeconds;
    } else {
        std::move(times_.begin() + 1, times_.begin() + count_, times_.begin());
        times_[static_cast<std::size_t>(count_ - 1)] = drawSeconds;
    }
    if (count_ < options_.window)
        return budget_;
    const double median = medianSeconds();
    const double target = options_.targetSeconds;
    const double drawn = static_cast<double>(std::max(mesh.blocks, 1));
    std::size_t next = budget_;
    if (median > target) {
        // Time taken as proportional to the blocks (no fixed cost): this overestimates what a
        // block costs, so a step shrinks too little, never too much.
        const double factor = std::clamp(target / median, options_.maxShrink, 0.9);
        next = std::min(budget_,
                        std::max(options_.minBlocks, static_cast<std::size_t>(drawn * factor)));
    } else if (median < options_.growBelow * target && mesh.budgetLimited) {
        next =
            static_cast<std::size_t>(std::ceil(static_cast<double>(budget_) * options_.growFactor));
    }
    if (next != budget_) {
        budget_ = next;
        count_ = 0;
    }
    return budget_;
}

} // namespace depthtouch::render
