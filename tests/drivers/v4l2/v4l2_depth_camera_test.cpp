// V4l2DepthCamera against the fake kernel: format negotiation, the mmap streaming loop, timeouts,
// unplug, EINTR, damaged buffers, color conversion and depth/color pairing.
#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"
#include "fake_v4l2_kernel.h"
#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using fake::fakeCameraNode;
using fake::FakeV4l2Kernel;
using hal::PixelFormat;
using std::chrono::milliseconds;

constexpr const char *kDepth = "/dev/video0";
constexpr const char *kColor = "/dev/video1";

std::uint16_t sampleAt(const hal::Frame &f, int x, int y)
{
    std::uint16_t v = 0;
    std::memcpy(&v, f.image.row(0, y) + 2 * x, sizeof(v));
    return v;
}

/// RGB of a YUYV pixel with neutral chroma (BT.601 limited range).
int expectedGrey(std::uint8_t luma)
{
    return static_cast<int>(std::lround((luma - 16) * 255.0 / 219.0));
}

using depthtouch::testing::errcOf;

hal::CameraConfig mode(PixelFormat depth, PixelFormat color = PixelFormat::Unknown, int w = 64,
                       int h = 48, double fps = 30.0)
{
    hal::CameraConfig c;
    c.width = w;
    c.height = h;
    c.fps = fps;
    c.depthFormat = depth;
    c.color = color != PixelFormat::Unknown;
    c.colorFormat = color;
    return c;
}

class V4l2DepthCameraTest : public ::testing::Test {
protected:
    std::unique_ptr<FakeV4l2Kernel> makeKernel(std::vector<std::uint32_t> depth,
                                               std::vector<std::uint32_t> color = {})
    {
        auto k = std::make_unique<FakeV4l2Kernel>(clock_);
        auto d = fakeCameraNode(kDepth, std::move(depth));
        d.linePadding = 8; // rows longer than the image: the driver must honour bytesperline
        k->addNode(std::move(d));
        if (!color.empty())
            k->addNode(fakeCameraNode(kColor, std::move(color)));
        return k;
    }
    void open(std::unique_ptr<FakeV4l2Kernel> k, bool withColor)
    {
        kernel_ = k.get();
        V4l2CameraSettings s;
        s.depthNode = kDepth;
        if (withColor)
            s.colorNode = kColor;
        auto c = V4l2DepthCamera::open(std::move(k), clock_, s);
        ASSERT_TRUE(c) << c.error().what;
        camera_ = std::move(*c);
    }
    bool offers(PixelFormat depth, PixelFormat color) const
    {
        const auto &m = camera_->capabilities().modes;
        return std::any_of(m.begin(), m.end(), [&](const hal::CameraMode &x) {
            return x.depthFormat == depth && x.colorFormat == color;
        });
    }
    void startWith(const hal::CameraConfig &cfg)
    {
        ASSERT_TRUE(camera_->configure(cfg));
        ASSERT_TRUE(camera_->start());
    }
    hal::Deadline soon() const { return clock_.now() + std::chrono::seconds(1); }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance,
                                 platform::TimePoint(std::chrono::seconds(10))};
    FakeV4l2Kernel *kernel_ = nullptr; // owned by camera_
    std::unique_ptr<V4l2DepthCamera> camera_;
};

TEST_F(V4l2DepthCameraTest, negotiationPrefersZ16ThenY16ThenGrey)
{
    struct Case {
        std::vector<std::uint32_t> offered;
        std::uint32_t chosen;
    };
    for (const Case &c :
         {Case{{V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_Y16, V4L2_PIX_FMT_Z16}, V4L2_PIX_FMT_Z16},
          Case{{V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_Y16}, V4L2_PIX_FMT_Y16},
          Case{{V4L2_PIX_FMT_GREY}, V4L2_PIX_FMT_GREY}}) {
        open(makeKernel(c.offered), false);
        const PixelFormat want =
            c.chosen == V4L2_PIX_FMT_GREY ? PixelFormat::Gray16 : PixelFormat::Z16;
        ASSERT_TRUE(camera_->configure(mode(want)));
        EXPECT_EQ(camera_->depthFourcc(), c.chosen);
        EXPECT_EQ(kernel_->currentFourcc(kDepth), c.chosen);
        // GREY is nearness: it has no millimetre mode.
        EXPECT_EQ(offers(PixelFormat::Z16, PixelFormat::Unknown), c.chosen != V4L2_PIX_FMT_GREY);
        camera_.reset();
    }
}

TEST_F(V4l2DepthCameraTest, modesCoverEverySizeAndRate)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    const auto &modes = camera_->capabilities().modes;
    // 2 sizes × 2 rates × (Z16, Gray16 nearness)
    EXPECT_EQ(modes.size(), 8U);
    EXPECT_EQ(camera_->capabilities().poolFrames, 4);
    EXPECT_EQ(errcOf(camera_->configure(mode(PixelFormat::Z16, PixelFormat::Unknown, 640, 480))),
              Errc::NotSupported);
    EXPECT_EQ(errcOf(camera_->configure(mode(PixelFormat::Z16, PixelFormat::Rgb24))),
              Errc::NotSupported)
        << "no color node";
}

TEST_F(V4l2DepthCameraTest, z16DepthIsTheSensorsMillimetres)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    const platform::TimePoint t0 = clock_.now();
    startWith(mode(PixelFormat::Z16));
    for (std::uint32_t k = 0; k < 3; ++k) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        ASSERT_TRUE(c->depth);
        EXPECT_FALSE(c->color);
        const hal::Frame &d = *c->depth;
        EXPECT_EQ(d.image.format, PixelFormat::Z16);
        EXPECT_EQ(d.sequence, k);
        // Frame k is exposed at k / 30 s after start; timestamps are microseconds (timeval).
        const auto expected = t0 + platform::fromSeconds(k / 30.0);
        EXPECT_LE(std::chrono::abs(d.time - expected), std::chrono::microseconds(1));
        EXPECT_LE(std::chrono::abs(d.pts - (expected - t0)), std::chrono::microseconds(1));
        int mismatches = 0;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x)
                mismatches += sampleAt(d, x, y) != FakeV4l2Kernel::depthMm(x, y, k) ? 1 : 0;
        EXPECT_EQ(mismatches, 0);
    }
}

TEST_F(V4l2DepthCameraTest, nearnessFollowsTheInverseDepthMapping)
{
    open(makeKernel({V4L2_PIX_FMT_Y16}), false);
    hal::CameraConfig cfg = mode(PixelFormat::Gray16);
    cfg.nearMetres = 0.5;
    cfg.farMetres = 2.0;
    startWith(cfg);
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    const hal::Frame &d = *c->depth;
    EXPECT_EQ(d.image.format, PixelFormat::Gray16);
    for (const auto &[x, y] : {std::pair{0, 0}, std::pair{20, 10}, std::pair{62, 47}}) {
        const double z = FakeV4l2Kernel::depthMm(x, y, 0) / 1000.0;
        const double v = std::clamp((1.0 / z - 1.0 / 2.0) / (1.0 / 0.5 - 1.0 / 2.0), 0.0, 1.0);
        EXPECT_NEAR(sampleAt(d, x, y), v * 65535.0, 1.0) << x << "," << y;
    }
    EXPECT_EQ(sampleAt(d, 15, 15), 0) << "no measurement stays 0";
}

TEST_F(V4l2DepthCameraTest, greyNearnessWidensTo16Bits)
{
    open(makeKernel({V4L2_PIX_FMT_GREY}), false);
    startWith(mode(PixelFormat::Gray16, PixelFormat::Unknown, 32, 24, 15.0));
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    for (int y = 0; y < 24; y += 5)
        for (int x = 0; x < 32; x += 3)
            EXPECT_EQ(sampleAt(*c->depth, x, y), FakeV4l2Kernel::greyValue(x, y, 0) * 257);
}

TEST_F(V4l2DepthCameraTest, buffersAreMappedAtStartAndRequeuedInOrder)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    EXPECT_TRUE(kernel_->streaming(kDepth));
    EXPECT_EQ(kernel_->mappings(), 4);
    for (std::uint32_t k = 0; k < 10; ++k) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        EXPECT_EQ(c->depth->sequence, k) << "no frame lost: each buffer goes back at once";
    }
    // Every buffer is dequeued in the order it was queued, and queued again right after.
    const std::vector<std::uint32_t> order{0, 1, 2, 3, 0, 1, 2, 3, 0, 1};
    EXPECT_EQ(kernel_->dequeuedOrder(kDepth), order);
    const auto queued = kernel_->queuedOrder(kDepth);
    ASSERT_EQ(queued.size(), 14U);
    EXPECT_TRUE(std::equal(order.begin(), order.end(), queued.begin() + 4));
    EXPECT_EQ(kernel_->framesLost(kDepth), 0U);
    ASSERT_TRUE(camera_->stop());
    EXPECT_FALSE(kernel_->streaming(kDepth));
    EXPECT_EQ(kernel_->mappings(), 0);
    EXPECT_EQ(kernel_->openDescriptors(), 1);
}

TEST_F(V4l2DepthCameraTest, lateConsumerGetsTheNewestFrame)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    ASSERT_TRUE(camera_->capture(soon()));
    // GIVEN the caller comes back three frame periods late
    clock_.advance(milliseconds(101));
    // THEN it gets frame 3 and frames 1 and 2 count as dropped
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    EXPECT_EQ(c->depth->sequence, 3U);
    EXPECT_EQ(camera_->stats().framesDropped, 2U);
}

TEST_F(V4l2DepthCameraTest, deadlinesGiveTimeout)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    ASSERT_TRUE(camera_->capture(soon()));
    // A deadline before the next exposure polls without waiting.
    const platform::TimePoint now = clock_.now();
    EXPECT_EQ(errcOf(camera_->capture(now)), Errc::Timeout);
    EXPECT_EQ(clock_.now(), now);
    // A covered sensor: the wait ends at the deadline.
    kernel_->stall(kDepth, true);
    const hal::Deadline until = clock_.now() + milliseconds(200);
    EXPECT_EQ(errcOf(camera_->capture(until)), Errc::Timeout);
    EXPECT_EQ(clock_.now(), until);
    kernel_->stall(kDepth, false);
    EXPECT_TRUE(camera_->capture(soon()));
}

TEST_F(V4l2DepthCameraTest, unplugMidStreamIsNoDeviceUntilReplugged)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_YUYV}), true);
    startWith(mode(PixelFormat::Z16, PixelFormat::Yuyv));
    ASSERT_TRUE(camera_->capture(soon()));
    kernel_->unplug();
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::NoDevice);
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::NoDevice);
    ASSERT_TRUE(camera_->stop());
    EXPECT_EQ(kernel_->mappings(), 0) << "buffers unmapped even though the device is gone";
    EXPECT_EQ(kernel_->openDescriptors(), 0);
    EXPECT_EQ(errcOf(camera_->start()), Errc::NoDevice);
    EXPECT_EQ(camera_->state(), hal::DepthCamera::State::Configured);
    kernel_->replug();
    ASSERT_TRUE(camera_->start());
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    EXPECT_EQ(c->depth->sequence, 0U);
    EXPECT_TRUE(c->color);
}

TEST_F(V4l2DepthCameraTest, interruptedCallsAreRetried)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    ASSERT_TRUE(camera_->capture(soon()));
    kernel_->failIoctl(VIDIOC_DQBUF, EINTR, 3);
    kernel_->failIoctl(VIDIOC_QBUF, EINTR, 1);
    kernel_->failPoll(EINTR, 2);
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    EXPECT_EQ(c->depth->sequence, 1U);
}

TEST_F(V4l2DepthCameraTest, damagedBuffersAreCountedAndSkipped)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    kernel_->damageFrames(kDepth, 2);  // V4L2_BUF_FLAG_ERROR
    kernel_->shortenFrames(kDepth, 3); // frames 0..2 short too; frame 2 only short
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    EXPECT_EQ(c->depth->sequence, 3U);
    EXPECT_EQ(camera_->stats().framesDamaged, 3U);
    EXPECT_EQ(sampleAt(*c->depth, 1, 1), FakeV4l2Kernel::depthMm(1, 1, 3));
}

TEST_F(V4l2DepthCameraTest, onlyDamagedFramesBeforeTheDeadlineIsIo)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    kernel_->damageFrames(kDepth, 1000);
    EXPECT_EQ(errcOf(camera_->capture(clock_.now() + milliseconds(100))), Errc::Io);
    EXPECT_GE(camera_->stats().framesDamaged, 3U);
}

TEST_F(V4l2DepthCameraTest, heldFramesExhaustThePool)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}), false);
    startWith(mode(PixelFormat::Z16));
    std::vector<hal::Capture> held;
    for (int i = 0; i < 4; ++i) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        held.push_back(std::move(*c));
    }
    clock_.advance(milliseconds(50));
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::Busy);
    EXPECT_GE(camera_->stats().framesDropped, 1U)
        << "the ready frame was dropped, its buffer requeued";
    held.clear();
    EXPECT_TRUE(camera_->capture(soon()));
}

TEST_F(V4l2DepthCameraTest, yuyvColorPassesThroughAndPairs)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_YUYV}), true);
    startWith(mode(PixelFormat::Z16, PixelFormat::Yuyv));
    for (std::uint32_t k = 0; k < 3; ++k) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        ASSERT_TRUE(c->color);
        const hal::Frame &col = *c->color;
        EXPECT_EQ(col.image.format, PixelFormat::Yuyv);
        EXPECT_EQ(col.sequence, c->depth->sequence);
        EXPECT_EQ(col.time, c->depth->time);
        EXPECT_EQ(col.kind, hal::StreamKind::Color);
        for (int x = 0; x < 64; x += 9) {
            EXPECT_EQ(col.image.row(0, 5)[2 * x], FakeV4l2Kernel::lumaValue(x, 5, k));
            EXPECT_EQ(col.image.row(0, 5)[2 * x + 1], 128);
        }
    }
    EXPECT_EQ(camera_->colorFourcc(), V4L2_PIX_FMT_YUYV);
}

TEST_F(V4l2DepthCameraTest, yuyvColorConvertsToRgb)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_YUYV}), true);
    if (!offers(PixelFormat::Z16, PixelFormat::Rgb24))
        GTEST_SKIP() << "No RGB conversion in this build (FFmpeg feature off)";
    startWith(mode(PixelFormat::Z16, PixelFormat::Rgb24));
    for (std::uint32_t k = 0; k < 2; ++k) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        const hal::Frame &col = *c->color;
        EXPECT_EQ(col.image.format, PixelFormat::Rgb24);
        for (int x = 0; x < 64; x += 5) {
            const std::uint8_t *px = col.image.row(0, 7) + 3 * x;
            const int g = expectedGrey(FakeV4l2Kernel::lumaValue(x, 7, k));
            EXPECT_NEAR(px[0], g, 2) << x;
            EXPECT_NEAR(px[1], g, 2) << x;
            EXPECT_NEAR(px[2], g, 2) << x;
        }
    }
}

TEST_F(V4l2DepthCameraTest, mjpegColorDecodesToRgb)
{
    if (!fake::fakeJpegAvailable())
        GTEST_SKIP() << "No MJPEG encoder for the fake kernel (FFmpeg feature off)";
    open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_MJPEG}), true);
    ASSERT_TRUE(offers(PixelFormat::Z16, PixelFormat::Rgb24));
    EXPECT_FALSE(offers(PixelFormat::Z16, PixelFormat::Yuyv));
    startWith(mode(PixelFormat::Z16, PixelFormat::Rgb24));
    EXPECT_EQ(camera_->colorFourcc(), V4L2_PIX_FMT_MJPEG);
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    const hal::Frame &col = *c->color;
    int worst = 0;
    for (int y = 0; y < 48; y += 4)
        for (int x = 0; x < 64; ++x) {
            const std::uint8_t *px = col.image.row(0, y) + 3 * x;
            const int g = expectedGrey(FakeV4l2Kernel::lumaValue(x, y, 0));
            for (int ch = 0; ch < 3; ++ch)
                worst = std::max(worst, std::abs(px[ch] - g));
        }
    EXPECT_LE(worst, 8) << "JPEG at high quality stays close to the pattern";

    // A JPEG that does not decode is a damaged frame: Io, counted, and the next one is fine.
    kernel_->garbleFrames(kColor, 1);
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::Io);
    EXPECT_EQ(camera_->stats().framesDamaged, 1U);
    EXPECT_TRUE(camera_->capture(soon()));
}

TEST_F(V4l2DepthCameraTest, mjpegOnlyColorNeedsADecoder)
{
    // GIVEN a color node that offers MJPEG only
    V4l2CameraSettings s;
    s.depthNode = kDepth;
    s.colorNode = kColor;
    auto c = V4l2DepthCamera::open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_MJPEG}), clock_, s);
    // THEN with libavcodec it decodes to RGB, without it the camera is refused with NotSupported
    if (c) {
        const auto &modes = (*c)->capabilities().modes;
        EXPECT_TRUE(std::any_of(modes.begin(), modes.end(), [](const hal::CameraMode &m) {
            return m.colorFormat == PixelFormat::Rgb24;
        }));
    } else {
        EXPECT_EQ(c.error().code, Errc::NotSupported);
        EXPECT_NE(std::string(c.error().what).find("FFmpeg"), std::string::npos);
    }
}

TEST_F(V4l2DepthCameraTest, colorIsPairedByTimestamp)
{
    // GIVEN color exposures 20 ms after depth ones (more than half a 33 ms period)
    auto kernel = std::make_unique<FakeV4l2Kernel>(clock_);
    kernel->addNode(fakeCameraNode(kDepth, {V4L2_PIX_FMT_Z16}));
    auto color = fakeCameraNode(kColor, {V4L2_PIX_FMT_YUYV});
    color.phase = milliseconds(20);
    kernel->addNode(std::move(color));
    open(std::move(kernel), true);
    startWith(mode(PixelFormat::Z16, PixelFormat::Yuyv));
    // THEN depth frame 0 has no partner, depth k pairs with color k − 1 (13 ms earlier)
    for (std::uint32_t i = 0; i < 3; ++i) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        EXPECT_EQ(c->depth->sequence, i + 1);
        EXPECT_EQ(c->color->image.row(0, 0)[0], FakeV4l2Kernel::lumaValue(0, 0, i));
    }
    EXPECT_EQ(camera_->stats().framesUnpaired, 1U);
}

TEST_F(V4l2DepthCameraTest, stalledColorTimesOutAndKeepsTheDepthFrame)
{
    open(makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_YUYV}), true);
    startWith(mode(PixelFormat::Z16, PixelFormat::Yuyv));
    ASSERT_TRUE(camera_->capture(soon()));
    kernel_->stall(kColor, true);
    EXPECT_EQ(errcOf(camera_->capture(clock_.now() + milliseconds(40))), Errc::Timeout);
    kernel_->stall(kColor, false);
    auto c = camera_->capture(soon());
    ASSERT_TRUE(c) << c.error().what;
    EXPECT_EQ(c->color->sequence, c->depth->sequence);
}

TEST_F(V4l2DepthCameraTest, nodesWithoutTheRightFormatsAreRefused)
{
    // A webcam given as the depth node.
    auto webcam = std::make_unique<FakeV4l2Kernel>(clock_);
    webcam->addNode(fakeCameraNode(kDepth, {V4L2_PIX_FMT_YUYV}));
    V4l2CameraSettings s;
    s.depthNode = kDepth;
    auto c = V4l2DepthCamera::open(std::move(webcam), clock_, s);
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, Errc::NotSupported);

    // A color node with a format the camera cannot use.
    auto k = makeKernel({V4L2_PIX_FMT_Z16}, {V4L2_PIX_FMT_NV12});
    s.colorNode = kColor;
    auto c2 = V4l2DepthCamera::open(std::move(k), clock_, s);
    ASSERT_FALSE(c2);
    EXPECT_EQ(c2.error().code, Errc::NotSupported);
}

TEST_F(V4l2DepthCameraTest, driverThatChangesTheFormatIsRefused)
{
    auto k = std::make_unique<FakeV4l2Kernel>(clock_);
    auto d = fakeCameraNode(kDepth, {V4L2_PIX_FMT_Z16});
    d.sfmtKeepsFirstSize = true; // S_FMT answers 64×48 whatever is asked
    k->addNode(std::move(d));
    open(std::move(k), false);
    EXPECT_EQ(errcOf(camera_->configure(mode(PixelFormat::Z16, PixelFormat::Unknown, 32, 24))),
              Errc::NotSupported);
    EXPECT_EQ(camera_->state(), hal::DepthCamera::State::Unconfigured);
    EXPECT_TRUE(camera_->configure(mode(PixelFormat::Z16)));
    // A refusal after a good configuration leaves no stale pools behind: the camera is
    // Unconfigured.
    EXPECT_EQ(errcOf(camera_->configure(mode(PixelFormat::Z16, PixelFormat::Unknown, 32, 24))),
              Errc::NotSupported);
    EXPECT_EQ(camera_->state(), hal::DepthCamera::State::Unconfigured);
    EXPECT_EQ(errcOf(camera_->start()), Errc::InvalidState);
}

TEST_F(V4l2DepthCameraTest, tooFewBuffersIsOutOfResources)
{
    auto k = std::make_unique<FakeV4l2Kernel>(clock_);
    auto d = fakeCameraNode(kDepth, {V4L2_PIX_FMT_Z16});
    d.maxBuffers = 1;
    k->addNode(std::move(d));
    open(std::move(k), false);
    ASSERT_TRUE(camera_->configure(mode(PixelFormat::Z16)));
    EXPECT_EQ(errcOf(camera_->start()), Errc::OutOfResources);
    EXPECT_EQ(kernel_->mappings(), 0);
    EXPECT_EQ(camera_->state(), hal::DepthCamera::State::Configured);
}

TEST(V4l2CameraSettingsTest, optionsAreCheckedAndDeviceComesFromEitherPlace)
{
    hal::BackendConfig cfg;
    cfg.device = "/dev/video2";
    cfg.options = hal::OptionList("color=/dev/video4,pool=6,buffers=3,hfov=70");
    auto s = V4l2CameraSettings::parse(cfg);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->depthNode, "/dev/video2");
    EXPECT_EQ(s->colorNode, "/dev/video4");
    EXPECT_EQ(s->poolFrames, 6);
    EXPECT_EQ(s->buffers, 3);
    EXPECT_DOUBLE_EQ(s->hfovDegrees, 70.0);

    for (const char *bad : {"colour=/dev/video4", "pool=0", "buffers=1", "hfov=180",
                            "device=/dev/video3", "color=/dev/video2"}) {
        cfg.options = hal::OptionList(bad);
        auto r = V4l2CameraSettings::parse(cfg);
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument) << bad;
    }
    cfg.device = {};
    cfg.options = hal::OptionList("device=/dev/video5,color=none");
    auto opt = V4l2CameraSettings::parse(cfg);
    ASSERT_TRUE(opt);
    EXPECT_EQ(opt->depthNode, "/dev/video5");
    EXPECT_TRUE(opt->colorNode.empty());
}

std::unique_ptr<V4l2Device> makeTableKernel(platform::Clock &clock)
{
    auto k = std::make_unique<FakeV4l2Kernel>(clock);
    k->addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_YUYV})); // a webcam first
    k->addNode(fakeCameraNode("/dev/video2", {V4L2_PIX_FMT_Z16}));
    return k;
}

TEST(V4l2DepthCameraBackendTest, autoprobeFindsTheDepthNode)
{
    const V4l2DeviceFactory previous = setV4l2DeviceFactory(&makeTableKernel);
    platform::ManualClock clock;
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    hal::SelectionReport report;
    auto cam = createDepthCamera("", cfg, &report);
    setV4l2DeviceFactory(previous);
    ASSERT_TRUE(cam) << report.message;
    EXPECT_EQ(report.chosen, "v4l2");
    auto *v4l2 = dynamic_cast<V4l2DepthCamera *>(cam->get());
    ASSERT_NE(v4l2, nullptr);
    ASSERT_TRUE((*cam)->configure(mode(PixelFormat::Z16)));
    EXPECT_EQ(v4l2->depthFourcc(), V4L2_PIX_FMT_Z16);
}

} // namespace
} // namespace depthtouch::drivers
