/// \file
/// \brief The player pipeline (playback::Playback) driven by the real StateMachine on the mock HAL:
/// mock media source and decoders, the mock display (no GL) and the simulated hand, in real time.
/// Checks what a viewer would notice: every frame shown once and in order, the haptic surface
/// fed and touched, pause freezing the media clock, seeks re-seating the proxy with the force
/// ramped in, loop, stiffness, flat playback without depth, and clean errors.

#include <chrono>
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
        playback::PlaybackHal ph;
        ph.makeSource = [this]() {
            hal::BackendConfig c;
            c.clock = &clock;
            return drivers::MockMediaSource::create(c);
        };
        ph.makeDecoder = [this](const hal::StreamInfo &) {
            hal::BackendConfig c;
            c.clock = &clock;
            return drivers::MockVideoDecoder::create(c);
        };
        ph.display = display.get();
        ph.device = device.get();
        ph.clock = &clock;
        auto p = playback::Playback::create(pc, ph);
        EXPECT_TRUE(p) << (p ? "" : p.error().what);
        playback = std::move(*p);
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

TEST(Playback, PlaysEveryFrameOnceAndFeedsTheHapticTask)
{
    Rig rig;
    auto out = rig.machine->execute("play mock://clip?frames=30&fps=30&width=64&height=48");
    ASSERT_TRUE(out.accepted) << out.reason;
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Playing; }));
    EXPECT_EQ(rig.playback->info().mode, "color+depth");
    EXPECT_TRUE(rig.playback->info().haptics);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));

    const playback::PlaybackStats s = rig.playback->stats();
    EXPECT_EQ(s.framesReceived, 30u);
    EXPECT_EQ(s.framesPresented + s.framesDropped, 30u);
    EXPECT_GE(s.framesPresented, 24u) << "a mock display at 60 Hz keeps up with 30 fps";
    EXPECT_EQ(s.depthPairsPublished, s.framesPresented);
    EXPECT_EQ(s.endsOfStream, 1u);
    // One second of video: the haptic task ran at 1 kHz on the pairs and the hand pressed.
    const auto hs = rig.playback->hapticStats();
    ASSERT_TRUE(hs.has_value());
    EXPECT_GT(hs->updates, 500u); // ~1000 at 1 kHz; the host may stall the thread for ms
    EXPECT_GT(hs->contactUpdates, 0u);
    EXPECT_LE(hs->maxForce, 8.5 + 1e-9);
}

TEST(Playback, AStallDelaysFramesWithinTheMaxLatenessAndDropsThemBeyondIt)
{
    for (const double maxLateness : {0.25, 0.0}) {
        SCOPED_TRACE(maxLateness);
        // GIVEN a 2 s clip at 30 fps on a 60 Hz display
        Rig rig(false, false, maxLateness);
        auto &display = static_cast<drivers::MockDisplay &>(*rig.display);
        ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=60&fps=30&width=64&height=48")
                        .accepted);
        ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > 0.5; }));
        // WHEN the render thread stalls for 120 ms (3.6 frame periods) in one present
        display.stallNextPresent(0.12);
        ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
        const playback::PlaybackStats s = rig.playback->stats();
        EXPECT_EQ(s.framesReceived, 60u);
        EXPECT_EQ(s.framesPresented + s.framesDropped, 60u);
        if (maxLateness > 0.0) {
            // THEN within 0.25 s of lateness every frame is shown, late, and the next catch up:
            // the frame after the stalled one is taken at least 120 - 33 ms after its time
            EXPECT_EQ(s.framesDropped, 0u);
            EXPECT_GE(s.lateMsMax, 80.0);
            EXPECT_GE(s.framesLate, 1u);
            EXPECT_LE(s.lateMsMax, 1e3 * maxLateness);
        } else {
            // THEN with none allowed the frames whose successors are due are skipped
            EXPECT_GE(s.framesDropped, 1u);
        }
    }
}

TEST(Playback, FramesThatCannotCatchUpAreSkippedAfterThreeTimesTheMaxLateness)
{
    // GIVEN 30 fps on a 30 Hz display: every refresh needs a new frame, so a late player cannot
    // catch up by showing frames for one refresh instead of two
    Rig rig(false, false, 0.1, "refresh=30");
    auto &display = static_cast<drivers::MockDisplay &>(*rig.display);
    ASSERT_TRUE(
        rig.machine->execute("play mock://clip?frames=120&fps=30&width=64&height=48").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > 0.5; }));
    // WHEN the render thread stalls for 80 ms (more than two frame periods behind, under the
    // 0.1 s of lateness allowed)
    display.stallNextPresent(0.08);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Stopped; }));
    const playback::PlaybackStats s = rig.playback->stats();
    EXPECT_EQ(s.framesPresented + s.framesDropped, 120u);
    // THEN frames are skipped once the player has been late for 0.3 s (about 9 frames), and it is
    // back in time: it does not stay a frame period late to the end (3.5 s, over 100 frames)
    EXPECT_GE(s.framesDropped, 1u);
    EXPECT_LT(s.framesLate, 50u) << "late frames: the player stayed behind";
}

TEST(Playback, PauseFreezesThePositionAndResumeGoesOn)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=150&fps=30").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > 0.3; }));
    ASSERT_TRUE(rig.machine->execute("pause").accepted);
    EXPECT_EQ(rig.machine->state(), PlayerState::Paused);
    rig.runFor(100ms); // a frame due when pause came may still go on screen
    const double frozen = rig.playback->position();
    const auto presented = rig.playback->stats().framesPresented;
    rig.runFor(400ms);
    EXPECT_DOUBLE_EQ(rig.playback->position(), frozen);
    EXPECT_EQ(rig.playback->stats().framesPresented, presented);
    ASSERT_TRUE(rig.machine->execute("toggle-pause").accepted);
    EXPECT_EQ(rig.machine->state(), PlayerState::Playing);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > frozen + 0.2; }));
    ASSERT_TRUE(rig.machine->execute("stop").accepted);
    EXPECT_EQ(rig.machine->state(), PlayerState::Stopped);
}

TEST(Playback, SeekRestartsAtTheTargetAndKeepsTheForce)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=300&fps=30").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() > 1.0; }));
    haptic_task::HapticTask *task = rig.playback->hapticTask();
    ASSERT_NE(task, nullptr);
    ASSERT_TRUE(rig.runUntil([&] { return task->gain() > 0.99; }));

    const auto seekedAt = std::chrono::steady_clock::now();
    ASSERT_TRUE(rig.machine->execute("seek 5 absolute").accepted);
    // The first frame shown after the seek is at 5 s (an old frame may still go on screen before
    // the render thread sees the seek)...
    ASSERT_TRUE(rig.runUntil(
        [&] {
            const double p = rig.playback->position();
            return p >= 4.9 && p < 5.5 && rig.playback->stats().seeks == 1;
        },
        2000ms));
    // ...and the haptic clock restarted with the proxy and the force kept: the task's gain is
    // not ramped from zero (a surface that changed under the proxy is the renderer's cut).
    double leastGain = 1.0;
    rig.runUntil(
        [&] {
            leastGain = std::min(leastGain, task->gain());
            return false;
        },
        300ms);
    EXPECT_GT(leastGain, 0.99);
    // Playing on from the target (frames of the new position only), at most as far as the time
    // since the seek.
    const double played =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - seekedAt).count();
    const double before = rig.playback->position();
    EXPECT_GE(before, 5.0);
    EXPECT_LE(before, 5.0 + played + 0.1);

    // A relative seek goes back from where it is, and playing goes on from there.
    ASSERT_TRUE(rig.machine->execute("seek -4").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->position() <= before - 3.5; }, 2000ms));
    rig.runFor(300ms);
    EXPECT_LE(rig.playback->position(), before - 2.5);
    EXPECT_GE(rig.playback->position(), before - 4.5);
    EXPECT_EQ(rig.playback->stats().seeks, 2u);
    EXPECT_EQ(rig.machine->state(), PlayerState::Playing);
}

TEST(Playback, LoopSeeksToTheStartAtTheEnd)
{
    Rig rig(true, /*loop=*/true);
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=10&fps=30").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.playback->stats().endsOfStream >= 2; }, 5000ms));
    EXPECT_EQ(rig.machine->state(), PlayerState::Playing);
    EXPECT_GE(rig.playback->stats().framesReceived, 20u);
}

TEST(Playback, StiffnessAndHapticsSwitchReachTheTask)
{
    Rig rig;
    ASSERT_TRUE(rig.machine->execute("play mock://clip?frames=100&fps=30").accepted);
    ASSERT_TRUE(rig.runUntil([&] { return rig.machine->state() == PlayerState::Playing; }));
    haptic_task::HapticTask *task = rig.playback->hapticTask();
    ASSERT_NE(task, nullptr);
    ASSERT_TRUE(rig.machine->execute("stiffness 1200").accepted);
    EXPECT_DOUBLE_EQ(task->stiffness(), 1200.0);
    ASSERT_TRUE(rig.machine->execute("stiffness -").accepted);
    EXPECT_DOUBLE_EQ(task->stiffness(), 1100.0);
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
