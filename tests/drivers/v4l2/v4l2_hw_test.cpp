// The `v4l2` depth camera on the real kernel: skips (exit code 77) when no node offers a depth
// format. Label hw. DT_V4L2_OPTIONS (e.g. "device=/dev/video2,color=/dev/video4") picks the nodes.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "support/camera_config.h"

namespace depthtouch::drivers {
namespace {

TEST(V4l2HardwareTest, capturesFromTheConnectedCamera)
{
    const char *env = std::getenv("DT_V4L2_OPTIONS");
    const std::string options = env != nullptr ? env : "";
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList(options);
    hal::SelectionReport report;
    auto cam = createDepthCamera("v4l2", cfg, &report);
    if (!cam && cam.error().code == Errc::NoDevice)
        GTEST_SKIP() << "No V4L2 depth camera: " << report.message;
    ASSERT_TRUE(cam) << report.message;
    const hal::CameraMode *best = nullptr;
    for (const hal::CameraMode &m : (*cam)->capabilities().modes)
        if (best == nullptr || m.width * m.height < best->width * best->height)
            best = &m;
    ASSERT_NE(best, nullptr);
    ASSERT_TRUE((*cam)->configure(depthtouch::testing::configOf(*best)));
    ASSERT_TRUE((*cam)->start());
    std::uint64_t last = 0;
    for (int i = 0; i < 10; ++i) {
        auto frame =
            (*cam)->capture(platform::SteadyClock::instance().now() + std::chrono::seconds(2));
        ASSERT_TRUE(frame) << frame.error().what;
        ASSERT_TRUE(frame->depth);
        if (i > 0) {
            EXPECT_GT(frame->depth->sequence, last);
        }
        last = frame->depth->sequence;
    }
    EXPECT_TRUE((*cam)->stop());
}

} // namespace
} // namespace depthtouch::drivers
