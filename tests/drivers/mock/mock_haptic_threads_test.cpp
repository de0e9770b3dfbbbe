// Cross-thread use of the mock haptic device: a servo loop on one thread, fault injection and
// observers on another. A separate program because it starts a thread (not in the unit label run
// under qemu-user).
#include "depthtouch/drivers/mock/mock_haptic_device.h"

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace depthtouch::drivers {
namespace {

using hal::Vec3;

TEST(MockHapticThreadsTest, unplugFromAnotherThreadWhileTheLoopRuns)
{
    platform::ManualClock clock;
    MockHapticDevice dev(clock);
    ASSERT_TRUE(dev.open());
    // GIVEN a servo loop on its own thread  WHEN a test thread unplugs  THEN the loop sees NoDevice
    std::atomic<bool> sawNoDevice{false};
    std::atomic<bool> started{false};
    // The loop runs until it sees the unplug; the 60 s deadline only keeps a loop that never sees
    // it from hanging the test.
    const auto hangGuard = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    std::thread loop([&] {
        hal::HapticState s;
        while (!sawNoDevice && std::chrono::steady_clock::now() < hangGuard) {
            if (!dev.read(s) || !dev.commandForce({0.0, 0.0, 1.0}))
                sawNoDevice = true;
            started = true;
        }
    });
    while (!started)
        std::this_thread::yield();
    // The observer reads a whole vector: the one commanded, never a torn mix.
    const Vec3 seen = dev.lastForce();
    EXPECT_TRUE(seen == Vec3{} || seen == (Vec3{0.0, 0.0, 1.0}));
    dev.disconnect();
    loop.join();
    EXPECT_TRUE(sawNoDevice) << "the loop did not see the unplug within 60 s";
    EXPECT_EQ(dev.lastForce(), Vec3{});
}

} // namespace
} // namespace depthtouch::drivers
