/// \file
/// \brief Zero-copy colour frames (dmabuf_import.h): the EGL attribute list and extension matching
/// (pure), and on a GLES 3 context a frame given only as "dma-bufs" (memfd-backed buffers: mmap
/// works on them, DMA_BUF_IOCTL_SYNC answers ENOTTY) drawn like the same frame given as CPU planes.
/// Where EGL_EXT_image_dma_buf_import exists (a GPU driver) the frame is imported instead; on Mesa
/// llvmpipe (surfaceless) it takes the mapped-upload fallback.

#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "app/render/gles_fixture.h"
#include "app/render/render_test_support.h"
#include "depthtouch/render/dmabuf_import.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"

using namespace depthtouch;
using namespace depthtouch::render;

namespace {

hal::DmaBufImage nv12(int fd, int w, int h, std::uint32_t pitch)
{
    hal::DmaBufImage img;
    img.fourcc = hal::kDrmFormatNv12;
    img.modifier = hal::kDrmFormatModLinear;
    img.width = w;
    img.height = h;
    img.planeCount = 2;
    img.planes[0] = {fd, 0, pitch};
    img.planes[1] = {fd, pitch * static_cast<std::uint32_t>(h), pitch};
    return img;
}

std::int32_t valueOf(const std::vector<std::int32_t> &a, std::int32_t key)
{
    for (std::size_t i = 0; i + 1 < a.size(); i += 2)
        if (a[i] == key)
            return a[i + 1];
    ADD_FAILURE() << "attribute 0x" << std::hex << key << " missing";
    return -1;
}

bool hasKey(const std::vector<std::int32_t> &a, std::int32_t key)
{
    for (std::size_t i = 0; i + 1 < a.size(); i += 2)
        if (a[i] == key)
            return true;
    return false;
}

TEST(DmaBufAttribsTest, planesFourccAndSizeAreListed)
{
    // GIVEN an NV12 frame in one buffer, Y at 0 and CbCr after it
    const hal::DmaBufImage img = nv12(9, 640, 480, 768);
    // WHEN its attribute list is built without modifiers
    auto a = dmaBufEglAttribs(img, false, ColorSpec{YuvMatrix::Bt709, true});
    ASSERT_TRUE(a) << a.error().what;
    // THEN it names size, fourcc, both planes, the colour hints, and ends with EGL_NONE
    EXPECT_EQ(a->size() % 2, 1u);
    EXPECT_EQ(a->back(), EGL_NONE);
    EXPECT_EQ(valueOf(*a, EGL_WIDTH), 640);
    EXPECT_EQ(valueOf(*a, EGL_HEIGHT), 480);
    EXPECT_EQ(static_cast<std::uint32_t>(valueOf(*a, EGL_LINUX_DRM_FOURCC_EXT)),
              hal::kDrmFormatNv12);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE0_FD_EXT), 9);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE0_OFFSET_EXT), 0);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE0_PITCH_EXT), 768);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE1_FD_EXT), 9);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE1_OFFSET_EXT), 768 * 480);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE1_PITCH_EXT), 768);
    EXPECT_FALSE(hasKey(*a, EGL_DMA_BUF_PLANE2_FD_EXT));
    EXPECT_FALSE(hasKey(*a, EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT));
    EXPECT_EQ(valueOf(*a, EGL_YUV_COLOR_SPACE_HINT_EXT), EGL_ITU_REC709_EXT);
    EXPECT_EQ(valueOf(*a, EGL_SAMPLE_RANGE_HINT_EXT), EGL_YUV_FULL_RANGE_EXT);
}

TEST(DmaBufAttribsTest, modifierIsSplitIntoLowAndHighWords)
{
    // GIVEN a YUV420 frame in three buffers with a tiling modifier
    hal::DmaBufImage img;
    img.fourcc = hal::kDrmFormatYuv420;
    img.modifier = 0x0100000000000002ULL; // I915_FORMAT_MOD_Y_TILED
    img.width = 64;
    img.height = 32;
    img.planeCount = 3;
    img.planes[0] = {3, 0, 64};
    img.planes[1] = {4, 16, 32};
    img.planes[2] = {5, 4096, 32};
    auto a = dmaBufEglAttribs(img, true, ColorSpec{});
    ASSERT_TRUE(a) << a.error().what;
    // THEN every plane has its fd and the modifier's low and high 32 bits
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE2_FD_EXT), 5);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE2_OFFSET_EXT), 4096);
    EXPECT_EQ(valueOf(*a, EGL_DMA_BUF_PLANE1_OFFSET_EXT), 16);
    for (EGLint lo : {EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT, EGL_DMA_BUF_PLANE1_MODIFIER_LO_EXT,
                      EGL_DMA_BUF_PLANE2_MODIFIER_LO_EXT})
        EXPECT_EQ(valueOf(*a, lo), 2);
    for (EGLint hi : {EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT, EGL_DMA_BUF_PLANE1_MODIFIER_HI_EXT,
                      EGL_DMA_BUF_PLANE2_MODIFIER_HI_EXT})
        EXPECT_EQ(valueOf(*a, hi), 0x01000000);
    EXPECT_FALSE(hasKey(*a, EGL_DMA_BUF_PLANE3_FD_EXT));
    EXPECT_EQ(valueOf(*a, EGL_YUV_COLOR_SPACE_HINT_EXT), EGL_ITU_REC601_EXT);
    EXPECT_EQ(valueOf(*a, EGL_SAMPLE_RANGE_HINT_EXT), EGL_YUV_NARROW_RANGE_EXT);
}

TEST(DmaBufAttribsTest, malformedImagesAreRefused)
{
    hal::DmaBufImage img = nv12(9, 64, 32, 64);
    img.planeCount = 3; // NV12 has two
    EXPECT_FALSE(dmaBufEglAttribs(img, false, ColorSpec{}));
    img = nv12(9, 64, 32, 64);
    img.planes[1].fd = -1;
    EXPECT_FALSE(dmaBufEglAttribs(img, false, ColorSpec{}));
    img = nv12(9, 64, 32, 0);
    EXPECT_FALSE(dmaBufEglAttribs(img, false, ColorSpec{}));
    img = nv12(9, 0, 32, 64);
    EXPECT_FALSE(dmaBufEglAttribs(img, false, ColorSpec{}));
    EXPECT_FALSE(dmaBufEglAttribs(hal::DmaBufImage{}, false, ColorSpec{}));
    img = nv12(9, 64, 32, 64);
    img.planes[0].offset = 0x80000000u; // beyond EGLint
    EXPECT_FALSE(dmaBufEglAttribs(img, false, ColorSpec{}));
    EXPECT_TRUE(dmaBufEglAttribs(nv12(9, 64, 32, 64), false, ColorSpec{}));
}

TEST(DmaBufAttribsTest, extensionNamesMatchWholeWords)
{
    const char *list = "EGL_KHR_image_base EGL_EXT_image_dma_buf_import_modifiers EGL_MESA_x";
    EXPECT_TRUE(hasExtension(list, "EGL_EXT_image_dma_buf_import_modifiers"));
    EXPECT_FALSE(hasExtension(list, "EGL_EXT_image_dma_buf_import")); // only as a prefix
    EXPECT_TRUE(hasExtension(list, "EGL_KHR_image_base"));
    EXPECT_TRUE(hasExtension(list, "EGL_MESA_x"));
    EXPECT_FALSE(hasExtension(nullptr, "EGL_MESA_x"));
    EXPECT_FALSE(hasExtension(list, ""));
}

/// A memfd holding \a bytes: a stand-in for a dma-buf (mmap works; DMA_BUF_IOCTL_SYNC does not).
class MemFd {
public:
    explicit MemFd(const std::vector<std::uint8_t> &bytes)
    {
        fd_ = memfd_create("dt-dmabuf-test", MFD_CLOEXEC);
        if (fd_ >= 0 &&
            (ftruncate(fd_, static_cast<off_t>(bytes.size())) != 0 ||
             write(fd_, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size()))) {
            close(fd_);
            fd_ = -1;
        }
    }
    ~MemFd()
    {
        if (fd_ >= 0)
            close(fd_);
    }
    MemFd(const MemFd &) = delete;
    MemFd &operator=(const MemFd &) = delete;
    [[nodiscard]] int fd() const noexcept { return fd_; }

private:
    int fd_ = -1;
};

class DmaBufRenderTest : public test::GlesRendererTest {
protected:
    void SetUp() override
    {
        RendererOptions o;
        o.mode = StereoMode::Mono;
        o.stereo.margin = 1.3;
        o.mesh.mode = MeshMode::Fixed;
        o.mesh.fixedStep = 1;
        setUpRenderer(o);
        if (!renderer_)
            return; // skipped, or the options were refused
        ASSERT_TRUE(renderer_->setDepth(depth_.view()));
    }

    std::vector<std::uint8_t> draw() { return test::drawRgb(*renderer_, 96, 64); }

    /// Largest difference of one channel, and the pixels that are not background.
    static int maxDiff(const std::vector<std::uint8_t> &a, const std::vector<std::uint8_t> &b)
    {
        int m = a.size() == b.size() ? 0 : 1000;
        for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
            m = std::max(m, std::abs(int(a[i]) - int(b[i])));
        return m;
    }
    static int lit(const std::vector<std::uint8_t> &a)
    {
        int n = 0;
        for (std::size_t i = 0; i + 2 < a.size(); i += 3)
            n += a[i] + a[i + 1] + a[i + 2] > 30 ? 1 : 0;
        return n;
    }

    /// Tolerance of the comparison: exact when the frame was uploaded (same bytes, same path), a
    /// few codes when a GPU driver converted it (its own Y'CbCr matrix and chroma filter).
    int tolerance() const { return renderer_->dmaBufStats().zeroCopy ? 12 : 0; }

    test::Depth8 depth_{32, 24, [](int c, int r) { return 100 + c + r; }};
    /// Colour with structure in every plane: Y ramps, Cb and Cr vary by quadrant.
    test::Yuv420 color_{
        32, 24, [](int c, int r) {
            return std::array<int, 3>{40 + 5 * c, c < 16 ? 90 : 170, r < 12 ? 200 : 60};
        }};
};

TEST_F(DmaBufRenderTest, yuv420DmaBufOnlyFrameDrawsLikeItsCpuPlanes)
{
    // GIVEN the colour frame as CPU planes, drawn as the reference
    ASSERT_TRUE(renderer_->setColor(color_.view(), ColorSpec{}));
    const auto reference = draw();
    ASSERT_GT(lit(reference), 1000);
    // AND the same frame as a YUV420 "dma-buf": a memfd with padded rows (pitch 40 / 24)
    const std::uint32_t w = 32, h = 24, cw = 16, ch = 12;
    const std::uint32_t yPitch = 40, cPitch = 24;
    std::vector<std::uint8_t> bytes(yPitch * h + 2 * cPitch * ch, 0xee);
    for (std::uint32_t r = 0; r < h; ++r)
        std::copy_n(&color_.y[r * w], w, &bytes[r * yPitch]);
    const std::size_t uAt = yPitch * h, vAt = uAt + cPitch * ch;
    for (std::uint32_t r = 0; r < ch; ++r) {
        std::copy_n(&color_.u[r * cw], cw, &bytes[uAt + r * cPitch]);
        std::copy_n(&color_.v[r * cw], cw, &bytes[vAt + r * cPitch]);
    }
    MemFd mem(bytes);
    ASSERT_GE(mem.fd(), 0);
    hal::DmaBufImage img;
    img.fourcc = hal::kDrmFormatYuv420;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);
    img.planeCount = 3;
    img.planes[0] = {mem.fd(), 0, yPitch};
    img.planes[1] = {mem.fd(), static_cast<std::uint32_t>(uAt), cPitch};
    img.planes[2] = {mem.fd(), static_cast<std::uint32_t>(vAt), cPitch};
    hal::ImageView noPlanes;
    noPlanes.width = img.width;
    noPlanes.height = img.height;
    noPlanes.format = hal::PixelFormat::Yuv420p;
    // WHEN it is given with no CPU planes
    ASSERT_TRUE(renderer_->setColorFrame(noPlanes, img, ColorSpec{}));
    const auto viaDmaBuf = draw();
    // THEN the picture is the reference's, and the frame was either imported or uploaded
    EXPECT_LE(maxDiff(viaDmaBuf, reference), tolerance());
    const DmaBufStats &s = renderer_->dmaBufStats();
    EXPECT_EQ(s.imported + s.uploaded, 1u);
    EXPECT_EQ(s.zeroCopy, s.imported == 1u);
}

TEST_F(DmaBufRenderTest, nv12DmaBufOnlyFrameDrawsLikeItsCpuPlanes)
{
    ASSERT_TRUE(renderer_->setColor(color_.view(), ColorSpec{YuvMatrix::Bt709, false}));
    const auto reference = draw();
    // GIVEN the same frame as NV12 in a memfd (pitch 32: rows packed)
    const int w = 32, h = 24, cw = 16, ch = 12;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(w * h + 2 * cw * ch));
    std::copy(color_.y.begin(), color_.y.end(), bytes.begin());
    for (int i = 0; i < cw * ch; ++i) {
        bytes[static_cast<std::size_t>(w * h + 2 * i)] = color_.u[static_cast<std::size_t>(i)];
        bytes[static_cast<std::size_t>(w * h + 2 * i + 1)] = color_.v[static_cast<std::size_t>(i)];
    }
    MemFd mem(bytes);
    ASSERT_GE(mem.fd(), 0);
    const hal::DmaBufImage img = nv12(mem.fd(), w, h, static_cast<std::uint32_t>(w));
    hal::ImageView noPlanes;
    noPlanes.width = w;
    noPlanes.height = h;
    noPlanes.format = hal::PixelFormat::Nv12;
    // WHEN drawn twice (the second time from the cache when imported)
    ASSERT_TRUE(renderer_->setColorFrame(noPlanes, img, ColorSpec{YuvMatrix::Bt709, false}));
    const auto first = draw();
    ASSERT_TRUE(renderer_->setColorFrame(noPlanes, img, ColorSpec{YuvMatrix::Bt709, false}));
    const auto second = draw();
    // THEN both are the reference
    EXPECT_LE(maxDiff(first, reference), tolerance());
    EXPECT_EQ(maxDiff(second, first), 0);
    EXPECT_EQ(renderer_->dmaBufStats().imported + renderer_->dmaBufStats().uploaded, 2u);
    // AND a CPU frame afterwards is drawn from its planes again
    ASSERT_TRUE(renderer_->setColorFrame(color_.view(), hal::DmaBufImage{},
                                         ColorSpec{YuvMatrix::Bt709, false}));
    EXPECT_EQ(maxDiff(draw(), reference), 0);
}

TEST_F(DmaBufRenderTest, frameWithBothUsesItsCpuPlanesWhenItCannotImport)
{
    // GIVEN a frame with CPU planes and a dma-buf descriptor whose fd is not open
    hal::DmaBufImage img;
    img.fourcc = hal::kDrmFormatYuv420;
    img.width = 32;
    img.height = 24;
    img.planeCount = 3;
    for (auto &p : img.planes)
        p = {987654, 0, 32};
    ASSERT_TRUE(renderer_->setColor(color_.view(), ColorSpec{}));
    const auto reference = draw();
    auto r = renderer_->setColorFrame(color_.view(), img, ColorSpec{});
    // THEN on a platform without import the CPU planes are drawn; with import the bad fd is an
    // error
    if (r) {
        EXPECT_EQ(maxDiff(draw(), reference), 0);
        EXPECT_FALSE(renderer_->dmaBufStats().zeroCopy);
        EXPECT_EQ(renderer_->dmaBufStats().uploaded, 1u);
    } else {
        EXPECT_EQ(r.error().code, Errc::InvalidArgument);
    }
}

TEST_F(DmaBufRenderTest, unreadableDmaBufsAreClearErrors)
{
    hal::ImageView noPlanes;
    noPlanes.width = 32;
    noPlanes.height = 24;
    noPlanes.format = hal::PixelFormat::Nv12;
    // GIVEN a buffer too small for its planes
    MemFd small(std::vector<std::uint8_t>(100, 0));
    ASSERT_GE(small.fd(), 0);
    auto r = renderer_->setColorFrame(noPlanes, nv12(small.fd(), 32, 24, 32), ColorSpec{});
    EXPECT_FALSE(r);
    // AND a tiled buffer (cannot be read on the CPU when it cannot be imported)
    MemFd big(std::vector<std::uint8_t>(4096, 0));
    hal::DmaBufImage tiled = nv12(big.fd(), 32, 24, 32);
    tiled.modifier = 0x0100000000000001ULL;
    auto t = renderer_->setColorFrame(noPlanes, tiled, ColorSpec{});
    if (!renderer_->dmaBufStats().zeroCopy) {
        ASSERT_FALSE(t);
        EXPECT_EQ(t.error().code, Errc::NotSupported);
    }
    // THEN the renderer still draws
    auto target = RenderTarget::create(96, 64);
    ASSERT_TRUE(target);
    EXPECT_TRUE(renderer_->render(*target));
}

} // namespace
