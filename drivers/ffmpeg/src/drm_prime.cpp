#include "depthtouch/drivers/ffmpeg/drm_prime.h"

#include <cstddef>
#include <cstdint>

extern "C" {
#include <libavutil/hwcontext_drm.h>
}

namespace depthtouch::drivers {

namespace {

constexpr std::uint32_t kDrmFormatR8 = hal::drmFourcc('R', '8', ' ', ' ');
constexpr std::uint32_t kDrmFormatGr88 = hal::drmFourcc('G', 'R', '8', '8');

/// Bytes of one row and number of rows of plane \a plane of a \a fourcc image.
struct Extent {
    std::int64_t rowBytes = 0;
    std::int64_t rows = 0;
};

Extent planeExtent(std::uint32_t fourcc, int plane, int width, int height) noexcept
{
    const std::int64_t w = width;
    const std::int64_t h = height;
    if (plane == 0)
        return {w, h};
    const std::int64_t cw = (w + 1) / 2;
    const std::int64_t ch = (h + 1) / 2;
    return fourcc == hal::kDrmFormatNv12 ? Extent{2 * cw, ch} : Extent{cw, ch};
}

} // namespace

Result<hal::DmaBufImage> dmaBufFromDrmDescriptor(const AVDRMFrameDescriptor &desc, int width,
                                                 int height) noexcept
{
    if (width <= 0 || height <= 0)
        return unexpected(Errc::InvalidArgument, "DRM PRIME frame of non-positive size");
    if (desc.nb_objects < 1 || desc.nb_objects > AV_DRM_MAX_PLANES)
        return unexpected(Errc::InvalidArgument, "DRM PRIME frame with 0 or more than 4 objects");
    if (desc.nb_layers < 1 || desc.nb_layers > AV_DRM_MAX_PLANES)
        return unexpected(Errc::InvalidArgument, "DRM PRIME frame with 0 or more than 4 layers");

    // The planes in order, whichever way the layers group them.
    const AVDRMPlaneDescriptor *planes[hal::DmaBufImage::kMaxPlanes] = {};
    int count = 0;
    std::uint32_t fourcc = 0;
    if (desc.nb_layers == 1) {
        const AVDRMLayerDescriptor &l = desc.layers[0];
        if (l.nb_planes < 1 || l.nb_planes > AV_DRM_MAX_PLANES)
            return unexpected(Errc::InvalidArgument, "DRM PRIME layer with 0 or too many planes");
        if (hal::drmPlaneCount(l.format) == 0 || hal::drmPlaneCount(l.format) != l.nb_planes)
            return unexpected(Errc::NotSupported, "DRM PRIME layer of an unknown format or layout");
        fourcc = l.format;
        for (int p = 0; p < l.nb_planes; ++p)
            planes[count++] = &l.planes[p];
    } else {
        for (int i = 0; i < desc.nb_layers; ++i) {
            const AVDRMLayerDescriptor &l = desc.layers[i];
            if (l.nb_planes != 1)
                return unexpected(Errc::NotSupported,
                                  "DRM PRIME separate layers must have one plane each");
            planes[count++] = &l.planes[0];
        }
        const std::uint32_t f0 = desc.layers[0].format;
        const std::uint32_t f1 = desc.layers[1].format;
        if (desc.nb_layers == 2 && f0 == kDrmFormatR8 && f1 == kDrmFormatGr88)
            fourcc = hal::kDrmFormatNv12;
        else if (desc.nb_layers == 3 && f0 == kDrmFormatR8 && f1 == kDrmFormatR8 &&
                 desc.layers[2].format == kDrmFormatR8)
            fourcc = hal::kDrmFormatYuv420;
        else
            return unexpected(Errc::NotSupported, "DRM PRIME layers of an unknown layout");
    }

    for (int p = 0; p < count; ++p)
        if (planes[p]->object_index < 0 || planes[p]->object_index >= desc.nb_objects)
            return unexpected(Errc::InvalidArgument, "DRM PRIME plane of a missing object");

    hal::DmaBufImage img;
    img.fourcc = fourcc;
    img.width = width;
    img.height = height;
    img.planeCount = count;
    img.modifier = desc.objects[planes[0]->object_index].format_modifier;
    const bool linear =
        img.modifier == hal::kDrmFormatModLinear || img.modifier == hal::kDrmFormatModInvalid;
    for (int p = 0; p < count; ++p) {
        const AVDRMPlaneDescriptor &pl = *planes[p];
        const AVDRMObjectDescriptor &obj = desc.objects[pl.object_index];
        if (obj.fd < 0)
            return unexpected(Errc::InvalidArgument, "DRM PRIME object without an fd");
        if (obj.format_modifier != img.modifier)
            return unexpected(Errc::NotSupported, "DRM PRIME planes with different modifiers");
        if (pl.pitch <= 0 || pl.offset < 0 ||
            static_cast<std::uint64_t>(pl.pitch) > std::uint64_t{0xffffffff} ||
            static_cast<std::uint64_t>(pl.offset) > std::uint64_t{0xffffffff})
            return unexpected(Errc::InvalidArgument,
                              "DRM PRIME plane pitch or offset out of range");
        if (linear) {
            const Extent e = planeExtent(fourcc, p, width, height);
            const auto pitch = static_cast<std::int64_t>(pl.pitch);
            const auto end =
                static_cast<std::int64_t>(pl.offset) + pitch * (e.rows - 1) + e.rowBytes;
            if (pitch < e.rowBytes)
                return unexpected(Errc::InvalidArgument, "DRM PRIME plane pitch below its row");
            if (obj.size > 0 && static_cast<std::uint64_t>(end) > obj.size)
                return unexpected(Errc::InvalidArgument, "DRM PRIME plane outside its object");
        }
        hal::DmaBufPlane &out = img.planes[static_cast<std::size_t>(p)];
        out.fd = obj.fd;
        out.offset = static_cast<std::uint32_t>(pl.offset);
        out.pitch = static_cast<std::uint32_t>(pl.pitch);
    }
    return img;
}

} // namespace depthtouch::drivers
