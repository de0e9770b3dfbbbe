/// \file
/// \brief The player pipeline (playback::Playback) driven by the real StateMachine on the mock HAL:
/// mock media source and decoders, the mock display (no GL) and the simulated hand, in real time:
/// lateness after a stall, the haptics switch, flat playback without depth, and clean errors. What
/// else depends on time (frames on time, the haptic rate, pause, seek, loop, a scene cut,
/// stiffness) runs on simulated time in playback_sim_test.cpp.

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

/// These two tests run on the real clock (the render thread's stall is real time): a loaded machine
/// can add a stall of its own. A run that misses the expectation is played again, up to three times
/// in all; a player that does not catch up fails every time.
constexpr int kAttempts = 3;

/// Plays a 2 s clip at 30 fps on a 60 Hz display and stalls the render thread for 120 ms (3.6 frame
/// periods) in one present, 0.5 s in. \return the stats at the end.
playback::PlaybackStats playWithAStall(double maxLateness)
{
    Rig rig(false, false, maxLateness);
    auto &display = static_cast<drivers::MockDisplay &>(*rig.display);
    EXPECT_TRUE(
        rig.machine->execute("play mock://clip?frames=60&fps=30&width=64&height=48").accepted);
    EXPECT_TRUE(rig.runUntil([&] { return rig.playback->position() > 0.5; }));
    display.stallNextPresent(0.12);
    EXPECT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    return rig.playback->stats();
}

TEST(Playback, AStallDelaysFramesWithinTheMaxLatenessAndDropsThemBeyondIt)
{
    for (const double maxLateness : {0.25, 0.0}) {
        SCOPED_TRACE(maxLateness);
        // THEN within 0.25 s of lateness every frame is shown, late, and the next catch up (the
        // frame after the stalled one is taken at least 120 − 33 ms after its time); with none
        // allowed the frames whose successors are due are skipped
        auto meets = [maxLateness](const playback::PlaybackStats &s) {
            const bool complete =
                s.framesReceived == 60u && s.framesPresented + s.framesDropped == 60u;
            if (maxLateness > 0.0)
                return complete && s.framesDropped == 0u && s.lateMsMax >= 80.0 &&
                       s.framesLate >= 1u && s.lateMsMax <= 1e3 * maxLateness;
            return complete && s.framesDropped >= 1u;
        };
        playback::PlaybackStats s;
        int attempt = 1;
        for (; attempt <= kAttempts; ++attempt) {
            s = playWithAStall(maxLateness);
            if (meets(s))
                break;
        }
        std::printf("max lateness %.2f s: %d play(s); presented %llu, dropped %llu, late %llu, "
                    "late max %.1f ms\n",
                    maxLateness, std::min(attempt, kAttempts),
                    static_cast<unsigned long long>(s.framesPresented),
                    static_cast<unsigned long long>(s.framesDropped),
                    static_cast<unsigned long long>(s.framesLate), s.lateMsMax);
        EXPECT_TRUE(meets(s)) << "missed in " << kAttempts << " plays";
        EXPECT_EQ(s.framesReceived, 60u);
        EXPECT_EQ(s.framesPresented + s.framesDropped, 60u);
    }
}

TEST(Playback, FramesThatCannotCatchUpAreSkippedAfterThreeTimesTheMaxLateness)
{
    // GIVEN 30 fps on a 30 Hz display: every refresh needs a new frame, so a late player cannot
    // catch up by showing frames for one refresh instead of two
    // WHEN the render thread stalls for 80 ms (more than two frame periods behind, under the
    // 0.1 s of lateness allowed)
    // THEN frames are skipped once the player has been late for 0.3 s (about 9 frames), and it is
    // back in time: it does not stay a frame period late to the end (3.5 s, over 100 frames)
    auto meets = [](const playback::PlaybackStats &s) {
        return s.framesPresented + s.framesDropped == 120u && s.framesDropped >= 1u &&
               s.framesLate < 50u;
    };
    playback::PlaybackStats s;
    for (int attempt = 1; attempt <= kAttempts; ++attempt) {
        Rig rig(false, false, 0.1, "refresh=30");
        auto &display = static_cast<drivers::MockDisplay &>(*rig.display);
        ASSERT_TRUE(
            rig.machine->execute("play mock://clip?frames=120&fps=30&width=64&height=48").accepted);
        ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > 0.5; }));
        display.stallNextPresent(0.08);
        ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
        s = rig.playback->stats();
        if (meets(s))
            break;
    }
    EXPECT_EQ(s.framesPresented + s.framesDropped, 120u);
    EXPECT_GE(s.framesDropped, 1u);
    EXPECT_LT(s.framesLate, 50u) << "late frames: the player stayed behind";
}

// (The stiffness's effect on the force:
// PlaybackSim.TheStiffnessCommandScalesTheForceTheFingerFeels.)
TEST(Playback, TheHapticsSwitchRampsTheForceOut)
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

TEST(Playback, ColorOnlyPlaysFlatWithoutHaptics)
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

TEST(Playback, AnUnopenableUrlIsAnErrorAndPlayCanStartAgain)
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

TEST(Playback, AnUnopenableUrlAfterAPlayedClipIsAnErrorNotAPlay)
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

TEST(Playback, WithoutADeviceItPlaysWithoutHaptics)
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
