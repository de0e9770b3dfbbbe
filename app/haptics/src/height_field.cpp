#include "depthtouch/haptics/height_field.h"

#include <algorithm>

namespace depthtouch::haptics {

Result<void> HeightField::setFrames(const DepthFrameView &current, const DepthFrameView *next) noexcept
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
    zScaleCurrent_ = box_.depth / maxSampleValue(current.format);
    zScaleNext_ = hasNext_ ? box_.depth / maxSampleValue(next_.format) : 0.0;
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

bool HeightField::contains(double x, double y) const noexcept
{
    if (!valid())
        return false;
    const double u = xToColumn(x);
    const double v = yToRow(y);
    return u >= 0.0 && u <= current_.width - 1 && v >= 0.0 && v <= current_.height - 1;
}

TriangleId HeightField::triangleAt(double x, double y) const noexcept
{
    const double u = xToColumn(x);
    const double v = yToRow(y);
    const int c = std::clamp(static_cast<int>(std::floor(u)), 0, current_.width - 2);
    const int r = std::clamp(static_cast<int>(std::floor(v)), 0, current_.height - 2);
    return TriangleId{c, r, (u - c) >= (v - r) ? 0 : 1};
}

double HeightField::heightAt(double x, double y) const noexcept
{
    const TriangleId t = triangleAt(x, y);
    const double fu = xToColumn(x) - t.c;
    const double fv = yToRow(y) - t.r;
    const double h00 = vertexZ(t.c, t.r);
    const double h11 = vertexZ(t.c + 1, t.r + 1);
    if (t.upper == 0) {
        const double h10 = vertexZ(t.c + 1, t.r);
        return h00 + fu * (h10 - h00) + fv * (h11 - h10);
    }
    const double h01 = vertexZ(t.c, t.r + 1);
    return h00 + fv * (h01 - h00) + fu * (h11 - h01);
}

} // namespace depthtouch::haptics
