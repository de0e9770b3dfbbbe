// Contract harness of the `v4l2` depth camera: the backend factory runs on a fake kernel (a Z16
// depth node and a YUYV color node), installed as the V4L2 kernel side of this test program.
#include <linux/videodev2.h>

#include <memory>

#include "contract_support.h"
#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"
#include "fake_v4l2_kernel.h"

namespace depthtouch::contract {

namespace {

std::unique_ptr<drivers::V4l2Device> makeContractKernel(platform::Clock &clock)
{
    auto kernel = std::make_unique<drivers::fake::FakeV4l2Kernel>(clock);
    kernel->addNode(drivers::fake::fakeCameraNode("/dev/video0", {V4L2_PIX_FMT_Z16},
                                                  {{64, 48}, {32, 24}}, {30.0}));
    auto color = drivers::fake::fakeCameraNode("/dev/video1", {V4L2_PIX_FMT_YUYV},
                                               {{64, 48}, {32, 24}}, {30.0});
    color.phase = std::chrono::milliseconds(2); // color exposures are not in lockstep with depth
    kernel->addNode(std::move(color));
    return kernel;
}

drivers::fake::FakeV4l2Kernel &kernelOf(hal::DepthCamera &c)
{
    return dynamic_cast<drivers::fake::FakeV4l2Kernel &>(
        dynamic_cast<drivers::V4l2DepthCamera &>(c).device());
}

} // namespace

const DepthCameraHarness *v4l2DepthCameraHarness()
{
    static const bool installed = [] {
        drivers::setV4l2DeviceFactory(&makeContractKernel);
        return true;
    }();
    (void)installed;
    static const DepthCameraHarness kV4l2{
        "device=/dev/video0,color=/dev/video1",
        true,
        [](hal::DepthCamera &c) { kernelOf(c).unplug(); },
        [](hal::DepthCamera &c) { kernelOf(c).replug(); },
    };
    return &kV4l2;
}

} // namespace depthtouch::contract
