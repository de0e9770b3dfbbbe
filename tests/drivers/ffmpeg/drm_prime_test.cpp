/// \file
/// \brief dmaBufFromDrmDescriptor(): libavutil DRM PRIME descriptors, built by hand as
/// h264_v4l2m2m and other exporters fill them, described as hal::DmaBufImage.

#include "depthtouch/drivers/ffmpeg/drm_prime.h"

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <gtest/gtest.h>

extern "C" {
#include <libavutil/hwcontext_drm.h>
}

#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using testing::errcOf;

constexpr std::uint32_t kR8 = hal::drmFourcc('R', '8', ' ', ' ');
constexpr std::uint32_t kGr88 = hal::drmFourcc('G', 'R', '8', '8');
constexpr std::uint64_t kTiled = 0x0100000000000001ULL; // I915_FORMAT_MOD_X_TILED

/// One layer of a descriptor: its DRM fourcc and its planes, each {object index, offset, pitch}.
struct Layer {
    std::uint32_t format = 0;
    std::vector<AVDRMPlaneDescriptor> planes;
};

/// A descriptor, zeroed, then filled with \a objects (each {fd, size, format modifier}) and \a
/// layers, in order.
AVDRMFrameDescriptor descriptor(std::initializer_list<AVDRMObjectDescriptor> objects,
                                std::initializer_list<Layer> layers)
{
    AVDRMFrameDescriptor d{};
    d.nb_objects = static_cast<int>(objects.size());
    std::copy(objects.begin(), objects.end(), d.objects);
    d.nb_layers = static_cast<int>(layers.size());
    AVDRMLayerDescriptor *out = d.layers;
    for (const Layer &l : layers) {
        out->format = l.format;
        out->nb_planes = static_cast<int>(l.planes.size());
        std::copy(l.planes.begin(), l.planes.end(), out->planes);
        ++out;
    }
    return d;
}

/// NV12 640×480 with a 704-byte pitch, Y at 0 and UV right after it, all in one object of fd 7.
AVDRMFrameDescriptor nv12OneObject()
{
    return descriptor({{7, 704 * 480 * 3 / 2, hal::kDrmFormatModLinear}},
                      {{hal::kDrmFormatNv12, {{0, 0, 704}, {0, 704 * 480, 704}}}});
}

TEST(DrmPrimeTest, nv12TwoPlanesInOneObject)
{
    // GIVEN an NV12 descriptor with both planes in one object
    const AVDRMFrameDescriptor d = nv12OneObject();
    // WHEN it is mapped
    auto img = dmaBufFromDrmDescriptor(d, 640, 480);
    // THEN both planes take the object's fd at their offsets, with the fourcc and modifier
    ASSERT_TRUE(img) << img.error().what;
    EXPECT_EQ(img->fourcc, hal::kDrmFormatNv12);
    EXPECT_EQ(img->modifier, hal::kDrmFormatModLinear);
    EXPECT_EQ(img->width, 640);
    EXPECT_EQ(img->height, 480);
    ASSERT_EQ(img->planeCount, 2);
    EXPECT_EQ(img->planes[0].fd, 7);
    EXPECT_EQ(img->planes[0].offset, 0u);
    EXPECT_EQ(img->planes[0].pitch, 704u);
    EXPECT_EQ(img->planes[1].fd, 7);
    EXPECT_EQ(img->planes[1].offset, 704u * 480u);
    EXPECT_EQ(img->planes[1].pitch, 704u);
    EXPECT_EQ(img->planes[2].fd, -1);
}

TEST(DrmPrimeTest, yuv420ThreePlanes)
{
    // GIVEN a YUV420 descriptor, 5×3 (odd: chroma 3×2), one object, pitches 8 and 4; the object
    // ends where the last Cr row's 3 bytes end (32 + 4 + 3)
    AVDRMFrameDescriptor d =
        descriptor({{3, 39, hal::kDrmFormatModInvalid}},
                   {{hal::kDrmFormatYuv420, {{0, 0, 8}, {0, 24, 4}, {0, 32, 4}}}});
    // WHEN mapped  THEN three planes in order, the implied modifier kept
    auto img = dmaBufFromDrmDescriptor(d, 5, 3);
    ASSERT_TRUE(img) << img.error().what;
    EXPECT_EQ(img->fourcc, hal::kDrmFormatYuv420);
    EXPECT_EQ(img->modifier, hal::kDrmFormatModInvalid);
    ASSERT_EQ(img->planeCount, 3);
    EXPECT_EQ(img->planes[1].offset, 24u);
    EXPECT_EQ(img->planes[1].pitch, 4u);
    EXPECT_EQ(img->planes[2].offset, 32u);

    // AND one byte less in the object puts the last chroma row outside it
    d.objects[0].size -= 1;
    auto cut = dmaBufFromDrmDescriptor(d, 5, 3);
    ASSERT_FALSE(cut);
    EXPECT_EQ(cut.error().code, Errc::InvalidArgument);
}

TEST(DrmPrimeTest, planesInSeveralObjects)
{
    // GIVEN NV12 with Y and UV in two objects (separate buffers), a tiling modifier on both
    AVDRMFrameDescriptor d = descriptor({{10, 0, kTiled}, {11, 0, kTiled}},
                                        {{hal::kDrmFormatNv12, {{0, 0, 1024}, {1, 64, 1024}}}});
    // WHEN mapped  THEN each plane has its object's fd, and the tiling modifier is kept
    auto img = dmaBufFromDrmDescriptor(d, 1000, 500);
    ASSERT_TRUE(img) << img.error().what;
    EXPECT_EQ(img->modifier, kTiled);
    EXPECT_EQ(img->planes[0].fd, 10);
    EXPECT_EQ(img->planes[1].fd, 11);
    EXPECT_EQ(img->planes[1].offset, 64u);

    // AND objects with different modifiers are refused
    d.objects[1].format_modifier = hal::kDrmFormatModLinear;
    auto mixed = dmaBufFromDrmDescriptor(d, 1000, 500);
    ASSERT_FALSE(mixed);
    EXPECT_EQ(mixed.error().code, Errc::NotSupported);
}

TEST(DrmPrimeTest, separateLayersBecomeNv12AndYuv420)
{
    // GIVEN NV12 described as an R8 layer and a GR88 layer
    AVDRMFrameDescriptor d = descriptor({{4, 0, hal::kDrmFormatModLinear}},
                                        {{kR8, {{0, 0, 64}}}, {kGr88, {{0, 64 * 32, 64}}}});
    auto nv12 = dmaBufFromDrmDescriptor(d, 64, 32);
    ASSERT_TRUE(nv12) << nv12.error().what;
    EXPECT_EQ(nv12->fourcc, hal::kDrmFormatNv12);
    EXPECT_EQ(nv12->planeCount, 2);
    EXPECT_EQ(nv12->planes[1].offset, 64u * 32u);

    // AND three R8 layers are YUV420
    d.nb_layers = 3;
    d.layers[1].format = kR8;
    d.layers[1].planes[0] = {0, 64 * 32, 32};
    d.layers[2].format = kR8;
    d.layers[2].nb_planes = 1;
    d.layers[2].planes[0] = {0, 64 * 32 + 32 * 16, 32};
    auto yuv = dmaBufFromDrmDescriptor(d, 64, 32);
    ASSERT_TRUE(yuv) << yuv.error().what;
    EXPECT_EQ(yuv->fourcc, hal::kDrmFormatYuv420);
    EXPECT_EQ(yuv->planeCount, 3);
}

TEST(DrmPrimeTest, refusesTooManyPlanes)
{
    // GIVEN a layer claiming 5 planes (more than AV_DRM_MAX_PLANES)
    AVDRMFrameDescriptor d = nv12OneObject();
    d.layers[0].nb_planes = 5;
    EXPECT_EQ(errcOf(dmaBufFromDrmDescriptor(d, 640, 480)), Errc::InvalidArgument);
    // AND 5 objects
    d = nv12OneObject();
    d.nb_objects = 5;
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    // AND NV12 with 3 planes does not match its format
    d = nv12OneObject();
    d.layers[0].nb_planes = 3;
    d.layers[0].planes[2] = {0, 0, 704};
    EXPECT_EQ(errcOf(dmaBufFromDrmDescriptor(d, 640, 480)), Errc::NotSupported);
}

TEST(DrmPrimeTest, refusesUnknownLayouts)
{
    // GIVEN a packed RGB layer (XRGB8888): not a layout the HAL describes
    AVDRMFrameDescriptor d = nv12OneObject();
    d.layers[0].format = hal::drmFourcc('X', 'R', '2', '4');
    d.layers[0].nb_planes = 1;
    EXPECT_EQ(errcOf(dmaBufFromDrmDescriptor(d, 640, 480)), Errc::NotSupported);
    // AND two R8 layers (neither NV12 nor YUV420)
    d = nv12OneObject();
    d.nb_layers = 2;
    d.layers[0].format = kR8;
    d.layers[0].nb_planes = 1;
    d.layers[1].format = kR8;
    d.layers[1].nb_planes = 1;
    d.layers[1].planes[0] = {0, 704 * 480, 704};
    EXPECT_EQ(errcOf(dmaBufFromDrmDescriptor(d, 640, 480)), Errc::NotSupported);
}

TEST(DrmPrimeTest, refusesInconsistentPlanes)
{
    // GIVEN planes pointing at a missing object, a negative fd, a zero pitch, a short pitch
    AVDRMFrameDescriptor d = nv12OneObject();
    d.layers[0].planes[1].object_index = 1;
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    d = nv12OneObject();
    d.objects[0].fd = -1;
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    d = nv12OneObject();
    d.layers[0].planes[0].pitch = 0;
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    d = nv12OneObject();
    d.layers[0].planes[0].pitch = 600; // below the 640-byte row
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    // AND no layer, or a non-positive size
    d = nv12OneObject();
    d.nb_layers = 0;
    EXPECT_FALSE(dmaBufFromDrmDescriptor(d, 640, 480));
    EXPECT_FALSE(dmaBufFromDrmDescriptor(nv12OneObject(), 0, 480));
    // WHILE the untouched descriptor maps
    EXPECT_TRUE(dmaBufFromDrmDescriptor(nv12OneObject(), 640, 480));
}

} // namespace
} // namespace depthtouch::drivers
