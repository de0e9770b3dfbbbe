/// \file
/// \brief The player pipeline (playback::Playback) driven by the real StateMachine on the mock HAL:
/// mock media source and decoders, the mock display (no GL) and the simulated hand, in real time:
/// the haptics switch, flat playback without depth, and clean errors. What depends on time (frames
/// on time, late and skipped frames after a stall, the haptic rate, pause, seek, loop, a scene
/// cut, stiffness) runs on simulated time in playback_sim_test.cpp.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "sim_player.h"

namespace depthtouch {
namespace {

using namespace std::chrono_literals;
using player::PlayerState;

struct Rig {
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    std::unique_ptr<hal::Display> display;
    std::unique_ptr<hal::HapticDevice> device;
    std::unique_ptr<playback::Playback> playback;
    std::unique_ptr<player::StateMachine> machine;

    explicit Rig(bool haptics = true, bool loop = false, double maxLateness = 0.0,
                 const char *displayOptions = "")
    {
        hal::BackendConfig cfg;
        cfg.clock = &clock;
        hal::BackendConfig dc = cfg;
        dc.options = hal::OptionList(displayOptions);
        display = std::move(*drivers::MockDisplay::create(dc));
        if (haptics) {
            hal::BackendConfig hc = cfg;
            hc.options = hal::OptionList("intent=press");
            device = std::move(*drivers::SimHapticDevice::create(hc));
        }
        playback::PlaybackConfig pc;
        pc.haptics.lockMemory = false;
        pc.haptics.renderer.reengage = haptics::Reengage::Ramp;
        pc.maxLateness = maxLateness;
        playback = playback_test::mockPlayback(pc, clock, display.get(), device.get());
        player::PlayerSettings settings;
        settings.loop = loop;
        machine = std::make_unique<player::StateMachine>(*playback, settings);
    }

    /// Runs the main loop (report()) until \a pred or \a timeout. \return pred().
    template <class P> bool runUntil(P pred, std::chrono::milliseconds timeout = 10s)
    {
        const auto end = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < end) {
            playback->report(*machine);
            if (pred())
                return true;
            std::this_thread::sleep_for(2ms);
        }
        playback->report(*machine);
        return pred();
    }
    void runFor(std::chrono::milliseconds d)
    {
        runUntil([] { return false; }, d);
    }
};

// (The stiffness's effect on the force:
// PlaybackSimTest.TheStiffnessCommandScalesTheForceTheFingerFeels.)
TEST(PlaybackTest, TheHapticsSwitchRampsTheForceOut)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=100&fps=30").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Playing; }));
    haptic_task::HapticTask *task = rig.playback->hapticTask();
    ASSERT_NE(task, nullptr);
    ASSERT_TRUE(rig.machine->execute("haptics off").accepted);
    EXPECT_FALSE(task->enabled());
    ASSERT_TRUE(rig.runUntil([&] { return task->gain() == 0.0; }, 2000ms));
    ASSERT_TRUE(rig.machine->execute("recenter").accepted);
}

TEST(PlaybackTest, ColorOnlyPlaysFlatWithoutHaptics)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=10&depth=0").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    EXPECT_EQ(rig.playback->info().mode, "color-only");
    EXPECT_FALSE(rig.playback->info().haptics);
    bool said = false;
    for (const std::string &n : rig.playback->info().notes)
        said = said || n.find("no depth stream") != std::string::npos;
    EXPECT_TRUE(said);
    EXPECT_EQ(rig.playback->stats().framesReceived, 10u);
    EXPECT_EQ(rig.playback->hapticTask(), nullptr);
}

TEST(PlaybackTest, AnUnopenableUrlIsAnErrorAndPlayCanStartAgain)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=0").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Error; }));
    EXPECT_NE(rig.machine->errorReason().find("cannot open"), std::string::npos)
        << rig.machine->errorReason();
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=5").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    EXPECT_EQ(rig.playback->stats().opens, 1u);
}

TEST(PlaybackTest, AnUnopenableUrlAfterAPlayedClipIsAnErrorNotAPlay)
{
    // GIVEN a clip played to its end
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=5").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    // WHEN an input that cannot be opened is played next
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=0").accepted);
    // THEN it fails as an open failure: the first clip's open is not taken for this one's
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Error; }));
    EXPECT_NE(rig.machine->errorReason().find("cannot open"), std::string::npos)
        << rig.machine->errorReason();
    EXPECT_EQ(rig.playback->stats().opens, 1u);
}

TEST(PlaybackTest, WithoutADeviceItPlaysWithoutHaptics)
{
    Rig rig(/*haptics=*/false);
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=5").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    EXPECT_FALSE(rig.playback->info().haptics);
    EXPECT_EQ(rig.playback->stats().depthPairsPublished, 0u);
    EXPECT_FALSE(rig.machine->execute("recenter").accepted);
}

} // namespace
} // namespace depthtouch
