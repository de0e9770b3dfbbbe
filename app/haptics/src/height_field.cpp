#include "depthtouch/haptics/height_field.h"

#include <algorithm>

namespace depthtouch::haptics {

Result<void> HeightField::setFrames(const DepthFrameView &current,
                                    const DepthFrameView *next) noexcept
{
    if (!(box_.width > 0.0) || !(box_.depth > 0.0) || !std::isfinite(box_.width) ||
        !std::isfinite(box_.depth))
        return unexpected(Errc::InvalidArgument, "scene box sizes must be positive");
    DT_TRY(current.validate());
    if (next != nullptr) {
        DT_TRY(next->validate());
        if (next->width != current.width || next->height != current.height)
            return unexpected(Errc::InvalidArgument, "next depth frame has a different size");
        if (!(next->pts > current.pts))
            return unexpected(Errc::InvalidArgument, "next depth frame PTS does not increase");
    }
    current_ = current;
    hasNext_ = next != nullptr;
    next_ = hasNext_ ? *next : DepthFrameView{};
    spacing_ = box_.width / (current.width - 1);
    invSpacing_ = 1.0 / spacing_;
    halfW_ = 0.5 * (current.width - 1);
    halfH_ = 0.5 * (current.height - 1);
    halfDepth_ = 0.5 * box_.depth;
    holeZ_ = -halfDepth_ - holeDrop();
    // Codes farCode()..v_max span the box depth (docs/architecture.md §3 "Holes").
    farCurrent_ = static_cast<double>(current.farCode());
    farNext_ = hasNext_ ? static_cast<double>(next_.farCode()) : 0.0;
    zScaleCurrent_ = box_.depth / (maxSampleValue(current.format) - farCurrent_);
    zScaleNext_ = hasNext_ ? box_.depth / (maxSampleValue(next_.format) - farNext_) : 0.0;
    curWide_ = current_.format == SampleFormat::Gray16;
    nextWide_ = hasNext_ && next_.format == SampleFormat::Gray16;
    sameLayout_ = curWide_ && nextWide_ && next_.strideBytes == current_.strideBytes;
    cut_ = std::isnan(cutSetting_) ? 0.25 * box_.depth : cutSetting_;
    alpha_ = 0.0;
    return ok();
}

void HeightField::setTime(double t, bool interpolate) noexcept
{
    if (!interpolate || !hasNext_) {
        alpha_ = 0.0;
        return;
    }
    const double a = (t - current_.pts) / (next_.pts - current_.pts);
    alpha_ = std::clamp(a, 0.0, 1.0);
}

} // namespace depthtouch::haptics
