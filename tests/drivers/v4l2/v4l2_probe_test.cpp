// The V4L2 node probes (capabilities, formats, depth camera autoprobe, M2M H.264 decoder) and the
// fake kernel's own V4L2 semantics.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/v4l2/v4l2_device.h"
#include "depthtouch/drivers/v4l2/v4l2_probe.h"
#include "fake_v4l2_kernel.h"

namespace depthtouch::drivers {
namespace {

using fake::fakeCameraNode;
using fake::fakeM2mNode;
using fake::FakeV4l2Kernel;

class V4l2ProbeTest : public ::testing::Test {
protected:
    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance,
                                 platform::TimePoint(std::chrono::seconds(10))};
    FakeV4l2Kernel kernel_{clock_};
};

TEST_F(V4l2ProbeTest, queryListsFormatsSizesAndRates)
{
    // GIVEN a depth node with Z16 and GREY at two sizes and two rates
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_GREY},
                                   {{64, 48}, {32, 24}}, {30.0, 15.0}));
    // WHEN it is queried
    auto info = queryV4l2Node(kernel_, "/dev/video0");
    // THEN every format, size and rate is listed, and the descriptor is closed again
    ASSERT_TRUE(info) << info.error().what;
    EXPECT_NE(info->deviceCaps & V4L2_CAP_VIDEO_CAPTURE, 0U);
    ASSERT_EQ(info->capture.size(), 2U);
    EXPECT_EQ(info->capture[0].fourcc, V4L2_PIX_FMT_Z16);
    ASSERT_EQ(info->capture[0].sizes.size(), 2U);
    EXPECT_EQ(info->capture[0].sizes[1].width, 32);
    EXPECT_EQ(info->capture[0].sizes[1].height, 24);
    ASSERT_EQ(info->capture[0].sizes[1].fps.size(), 2U);
    EXPECT_DOUBLE_EQ(info->capture[0].sizes[1].fps[1], 15.0);
    EXPECT_EQ(bestDepthFourcc(*info), V4L2_PIX_FMT_Z16);
    EXPECT_EQ(kernel_.openDescriptors(), 0);
}

TEST_F(V4l2ProbeTest, missingNodeIsNoDevice)
{
    auto info = queryV4l2Node(kernel_, "/dev/video9");
    ASSERT_FALSE(info);
    EXPECT_EQ(info.error().code, Errc::NoDevice);
}

TEST_F(V4l2ProbeTest, interruptedIoctlsAreRetried)
{
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16}));
    kernel_.failIoctl(VIDIOC_QUERYCAP, EINTR, 2);
    auto info = queryV4l2Node(kernel_, "/dev/video0");
    ASSERT_TRUE(info) << info.error().what;
    EXPECT_EQ(kernel_.ioctlCount(VIDIOC_QUERYCAP), 3);
}

TEST_F(V4l2ProbeTest, depthAutoprobePrefersZ16ThenY16ThenGrey)
{
    // GIVEN an infrared node (GREY), a color node (YUYV), a Y16 node and a Z16 node
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_GREY}));
    kernel_.addNode(fakeCameraNode("/dev/video1", {V4L2_PIX_FMT_YUYV}));
    kernel_.addNode(fakeCameraNode("/dev/video2", {V4L2_PIX_FMT_Y16}));
    kernel_.addNode(fakeCameraNode("/dev/video3", {V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_GREY}));
    auto found = findDepthCameraNode(kernel_);
    ASSERT_TRUE(found) << found.error().what;
    EXPECT_EQ(*found, "/dev/video3");

    FakeV4l2Kernel noZ16(clock_);
    noZ16.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_GREY}));
    noZ16.addNode(fakeCameraNode("/dev/video4", {V4L2_PIX_FMT_Y16}));
    auto y16 = findDepthCameraNode(noZ16);
    ASSERT_TRUE(y16);
    EXPECT_EQ(*y16, "/dev/video4");
}

TEST_F(V4l2ProbeTest, depthAutoprobeWithoutDepthFormatIsNoDevice)
{
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG}));
    kernel_.addNode(fakeM2mNode("/dev/video1", {V4L2_PIX_FMT_H264}, false));
    auto found = findDepthCameraNode(kernel_);
    ASSERT_FALSE(found);
    EXPECT_EQ(found.error().code, Errc::NoDevice);
}

TEST_F(V4l2ProbeTest, m2mProbeIgnoresCamerasAndEncoders)
{
    // GIVEN a depth camera, a webcam and an M2M encoder (H.264 comes out of it, raw goes in)
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16}));
    kernel_.addNode(fakeCameraNode("/dev/video1", {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG}));
    kernel_.addNode(fakeM2mNode("/dev/video2", {V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_YUV420}, false));
    // WHEN an H.264 decoder is looked for THEN there is none
    auto none = findM2mH264Decoder(kernel_);
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, Errc::NoDevice);
    EXPECT_EQ(kernel_.openDescriptors(), 0);

    // GIVEN a multi-planar stateful decoder taking HEVC and H.264 THEN it is found
    kernel_.addNode(fakeM2mNode("/dev/video11", {V4L2_PIX_FMT_HEVC, V4L2_PIX_FMT_H264}, true));
    auto found = findM2mH264Decoder(kernel_);
    ASSERT_TRUE(found) << found.error().what;
    EXPECT_EQ(*found, "/dev/video11");
}

TEST_F(V4l2ProbeTest, m2mProbeFindsSinglePlanarDecoder)
{
    kernel_.addNode(fakeM2mNode("/dev/video10", {V4L2_PIX_FMT_MPEG2}, false));
    kernel_.addNode(fakeM2mNode("/dev/video12", {V4L2_PIX_FMT_H264}, false));
    auto found = findM2mH264Decoder(kernel_);
    ASSERT_TRUE(found);
    EXPECT_EQ(*found, "/dev/video12");
}

/// The kernel side the backend tables get while a test runs (the decoder-probe tests below).
bool gWithDecoder = false;
std::unique_ptr<V4l2Device> makeProbeKernel(platform::Clock &clock)
{
    auto k = std::make_unique<FakeV4l2Kernel>(clock);
    k->addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16}));
    if (gWithDecoder)
        k->addNode(fakeM2mNode("/dev/video1", {V4L2_PIX_FMT_H264}, false));
    return k;
}

class V4l2m2mBackendProbeTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        previous_ = setV4l2DeviceFactory(&makeProbeKernel);
        if (backendNames(BackendKind::VideoDecoder).find("v4l2m2m") == std::string::npos)
            GTEST_SKIP() << "No v4l2m2m backend in this build (FFmpeg feature off)";
    }
    void TearDown() override { setV4l2DeviceFactory(previous_); }
    V4l2DeviceFactory previous_ = nullptr;
};

TEST_F(V4l2m2mBackendProbeTest, aCameraNodeDoesNotMakeV4l2m2mAvailable)
{
    // GIVEN only a depth camera node WHEN the v4l2m2m decoder is created THEN it reports that no
    // M2M H.264 decoder exists (it used to be chosen whenever any /dev/video* existed)
    gWithDecoder = false;
    hal::SelectionReport report;
    auto dec = createVideoDecoder("v4l2m2m", {}, &report);
    ASSERT_FALSE(dec);
    EXPECT_EQ(dec.error().code, Errc::NoDevice);
    EXPECT_NE(report.message.find("No V4L2 M2M device decodes H.264"), std::string::npos)
        << report.message;
}

TEST_F(V4l2m2mBackendProbeTest, anM2mH264DecoderPassesTheProbe)
{
    // GIVEN a fake M2M H.264 decoder WHEN v4l2m2m is created THEN the node probe passes: creation
    // either succeeds or fails further on (libavcodec's h264_v4l2m2m opens real /dev nodes).
    gWithDecoder = true;
    hal::SelectionReport report;
    auto dec = createVideoDecoder("v4l2m2m", {}, &report);
    if (!dec) {
        EXPECT_EQ(report.message.find("No V4L2 M2M device decodes H.264"), std::string::npos)
            << report.message;
    }
}

TEST_F(V4l2ProbeTest, fakeKernelMmapStreamingSemantics)
{
    // The fake must behave like the kernel where the driver relies on it.
    kernel_.addNode(fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16}));
    const int fd = kernel_.open("/dev/video0", O_RDWR | O_NONBLOCK);
    ASSERT_GE(fd, 0);
    v4l2_requestbuffers req{};
    req.count = 2;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_USERPTR;
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_REQBUFS, &req), EINVAL) << "MMAP only";
    req.memory = V4L2_MEMORY_MMAP;
    ASSERT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_REQBUFS, &req), 0);
    v4l2_format f{};
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_S_FMT, &f), EBUSY)
        << "format is fixed while buffers exist";
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    ASSERT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_QUERYBUF, &b), 0);
    void *p = kernel_.mmap(b.length, PROT_READ, MAP_SHARED, fd, b.m.offset);
    ASSERT_NE(p, MAP_FAILED);
    req.count = 0;
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_REQBUFS, &req), EBUSY) << "still mapped";
    ASSERT_EQ(kernel_.munmap(p, b.length), 0);
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_DQBUF, &b), EINVAL) << "not streaming";
    ASSERT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_QBUF, &b), 0);
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_QBUF, &b), EINVAL) << "queued twice";
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    ASSERT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_STREAMON, &type), 0);
    ASSERT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_DQBUF, &b), 0) << "frame 0 is exposed at STREAMON";
    EXPECT_EQ(b.sequence, 0U);
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_DQBUF, &b), EAGAIN);
    kernel_.unplug();
    EXPECT_EQ(v4l2Ioctl(kernel_, fd, VIDIOC_QBUF, &b), ENODEV);
    EXPECT_LT(kernel_.open("/dev/video0", O_RDWR), 0);
    EXPECT_EQ(kernel_.close(fd), 0);
    EXPECT_EQ(kernel_.openDescriptors(), 0);
}

} // namespace
} // namespace depthtouch::drivers
