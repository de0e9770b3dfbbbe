#include "depthtouch/scene/depth_frame.h"

#include <cmath>

namespace depthtouch::scene {

Result<void> DepthFrameView::validate() const noexcept
{
    if (data == nullptr)
        return unexpected(Errc::InvalidArgument, "depth frame has no pixels");
    if (width < 2 || height < 2)
        return unexpected(Errc::InvalidArgument, "depth frame must be at least 2x2 samples");
    if (strideBytes < static_cast<std::size_t>(width) * bytesPerSample(format))
        return unexpected(Errc::InvalidArgument, "depth frame row stride is shorter than a row");
    if (!std::isfinite(pts))
        return unexpected(Errc::InvalidArgument, "depth frame PTS is not finite");
    if (2.0 * holeBelow >= maxSampleValue(format))
        return unexpected(Errc::InvalidArgument,
                          "depth frame hole threshold leaves no measured codes (2 x threshold is "
                          "v_max or more)");
    if (material.present() && material.strideBytes < 3 * static_cast<std::size_t>(width))
        return unexpected(Errc::InvalidArgument, "material row stride is shorter than a row");
    return ok();
}

} // namespace depthtouch::scene
