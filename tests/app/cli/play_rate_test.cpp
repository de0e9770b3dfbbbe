/// \file
/// \brief `play --rate` reaches the haptic task's servo loop: the option parsed from the command
/// line, landed in the player's config (play_options.h) and played on simulated time
/// (tests/app/playback/sim_player.h, one ManualClock) at 500 Hz. The task runs 500 updates a
/// simulated second, its stats say 500 Hz, and what is timed in seconds (the enable ramp, the
/// force-rate limit) keeps its duration in seconds, not in updates.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/playback/sim_player.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "command_line.h"
#include "option_cli.h"
#include "play_options.h"

namespace depthtouch::cli {
namespace {

using namespace std::chrono_literals;

/// \return the player's config of `play x.mkv` + \a args, parsed with play's option table.
playback::PlaybackConfig configOf(std::vector<std::string> args)
{
    PlayOptions opt;
    CommandLine line{"play"};
    addOptions(line.root(), playOptionTable(), opt);
    args.insert(args.begin(), "x.mkv");
    EXPECT_EQ(line.parse(args), "");
    EXPECT_EQ(checkPlayOptionValues(opt), "");
    return landPlayOptions(opt);
}

/// The mock fingertip, held still at (0, 0, −13) mm: 2 mm into the clip's surface at −11 mm.
std::unique_ptr<hal::HapticDevice> stillFinger(platform::Clock &clock)
{
    auto mock = std::make_unique<drivers::MockHapticDevice>(clock);
    mock->setWaypoints({{clock.now(), {0.0, 0.0, -0.013}, 0}});
    return mock;
}

TEST(PlayRateTest, TheServoLoopRunsAtTheRateOfTheOptionAndItsRampsKeepTheirSeconds)
{
    // GIVEN `play --rate 500` on the still finger 2 mm into a still surface (k·2 mm = 1.6 N)
    const playback::PlaybackConfig config = configOf({"--rate", "500"});
    playback_test::SimPlayer p(config, &stillFinger, [](std::uint32_t) { return -0.011; });
    auto &mock = static_cast<drivers::MockHapticDevice &>(*p.device());
    p.play("mock://clip?frames=60&fps=30&width=64&height=48&depth_bits=16", 60);
    haptic_task::HapticTask *task = p.playback().hapticTask();
    ASSERT_NE(task, nullptr);
    // WHEN a simulated second passes  THEN the task updated 500 times, and its stats say 500 Hz
    const std::uint64_t u0 = task->updates();
    p.step(1000);
    EXPECT_EQ(task->updates() - u0, 500u);
    ASSERT_NEAR(mock.lastForce().z, 1.6, 0.01);
    const auto stats = p.playback().hapticStats();
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->servoRateHz, 500.0);

    // WHEN haptics are switched off and on  THEN the force ramps out and in over the task's
    // 0.25 s (rampTime), smoothstep-shaped: half of it (0.8 N) at 125 ms, all at 250 ms. A period
    // taken as 1 ms would ramp over 0.5 s (0.25 N at 125 ms); a loop at 1 kHz over 0.125 s.
    ASSERT_TRUE(p.machine().execute("haptics off").accepted);
    p.step(125);
    EXPECT_NEAR(mock.lastForce().z, 0.8, 0.03) << "half-way down the ramp";
    p.step(130);
    EXPECT_EQ(mock.lastForce().z, 0.0);
    ASSERT_TRUE(p.machine().execute("haptics on").accepted);
    p.step(125);
    EXPECT_NEAR(mock.lastForce().z, 0.8, 0.03) << "half-way up the ramp";
    p.step(130);
    EXPECT_NEAR(mock.lastForce().z, 1.6, 0.01);

    // WHEN the stiffness steps from 800 to 3000 N/m (1.6 N → 6 N)  THEN the renderer's slew
    // limit (maxForceStep, 2 N an update), tighter than the task's force-rate limit (2000 N/s:
    // 4 N in the 2 ms of one update), lets it rise 2 N an update: the stiffness is applied before
    // the renderer's safety, which shapes the force the device is sent
    const double step = config.haptics.renderer.maxForceStep;
    ASSERT_LT(step, config.haptics.maxForceRate * 0.002);
    ASSERT_TRUE(p.machine().execute("stiffness 3000").accepted);
    p.step(2);
    EXPECT_NEAR(mock.lastForce().z, 1.6 + step, 0.01);
    p.step(2);
    EXPECT_NEAR(mock.lastForce().z, 1.6 + 2.0 * step, 0.01);
    p.step(2);
    EXPECT_NEAR(mock.lastForce().z, 3000.0 * 0.002, 0.01);
}

} // namespace
} // namespace depthtouch::cli
