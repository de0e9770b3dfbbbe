#include "depthtouch/scene/surface_mapping.h"

#include <cmath>

namespace depthtouch::scene {

Result<SurfaceMapping> SurfaceMapping::of(const SceneBox &box, const DepthFrameView &frame) noexcept
{
    if (!(box.width > 0.0) || !(box.depth > 0.0) || !std::isfinite(box.width) ||
        !std::isfinite(box.depth))
        return unexpected(Errc::InvalidArgument, "scene box sizes must be positive");
    DT_TRY(frame.validate());
    // HeightField::setFrames() and its columnToX(), rowToY() and frameZ(), written out.
    const double s = box.width / (frame.width - 1);
    const double halfW = 0.5 * (frame.width - 1);
    const double halfH = 0.5 * (frame.height - 1);
    const double vmax = maxSampleValue(frame.format);
    SurfaceMapping m;
    m.columns = frame.width;
    m.rows = frame.height;
    m.x0 = (0.0 - halfW) * s;
    m.dx = (1.0 - halfW) * s - m.x0;
    m.y0 = (halfH - 0.0) * s;
    m.dy = (halfH - 1.0) * s - m.y0;
    m.vmax = vmax;
    // Codes farCode()..v_max span the box depth (docs/architecture.md §3 "Holes").
    const auto far = static_cast<double>(frame.farCode());
    m.z0 = (0.0 - far) * (box.depth / (vmax - far)) - 0.5 * box.depth;
    m.dz = (vmax - far) * (box.depth / (vmax - far)) - 0.5 * box.depth - m.z0;
    return m;
}

} // namespace depthtouch::scene
