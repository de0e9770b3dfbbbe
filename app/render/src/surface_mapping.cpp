#include "depthtouch/render/surface_mapping.h"

#include <cstdint>

namespace depthtouch::render {

SurfaceMapping SurfaceMapping::fromHeightField(const haptics::HeightField &field) noexcept
{
    SurfaceMapping m;
    const haptics::DepthFrameView &frame = field.current();
    m.columns = field.columns();
    m.rows = field.rows();
    m.x0 = field.columnToX(0.0);
    m.dx = field.columnToX(1.0) - m.x0;
    m.y0 = field.rowToY(0.0);
    m.dy = field.rowToY(1.0) - m.y0;
    m.vmax = haptics::maxSampleValue(frame.format);
    // z at nearness 0 and at v_max, read through the haptic renderer's own sample → z conversion.
    static constexpr std::uint8_t kProbe8[4] = {0, 255, 0, 255};
    static constexpr std::uint16_t kProbe16[4] = {0, 65535, 0, 65535};
    haptics::DepthFrameView probe;
    probe.width = 2;
    probe.height = 2;
    probe.format = frame.format;
    if (frame.format == haptics::SampleFormat::Gray8) {
        probe.data = kProbe8;
        probe.strideBytes = 2;
    } else {
        probe.data = reinterpret_cast<const std::uint8_t *>(kProbe16);
        probe.strideBytes = 4;
    }
    m.z0 = field.frameZ(probe, 0, 0);
    m.dz = field.frameZ(probe, 1, 0) - m.z0;
    return m;
}

} // namespace depthtouch::render
