/// \file
/// \brief The player on simulated time (sim_player.h): exact frame and haptic-update counts,
/// a stalled render thread's late and skipped frames, pause freezing the haptic time, and a scene
/// cut in a played clip felt through the player's haptic task and the device's force.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "app/playback/sim_player.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"

namespace depthtouch::playback_test {
namespace {

using player::PlayerState;

std::unique_ptr<hal::HapticDevice> pressingHand(platform::Clock &clock)
{
    hal::BackendConfig c;
    c.clock = &clock;
    c.options = hal::OptionList("intent=press");
    return std::move(*drivers::SimHapticDevice::create(c));
}

TEST(PlaybackSimTest, PlaysEveryFrameOnceOnTimeAndTheHapticTaskAtItsRate)
{
    // GIVEN one second of video at 30 fps on the mock display (60 Hz) and the pressing hand
    SimPlayer p(playback::PlaybackConfig{}, &pressingHand);
    p.play("mock://clip?frames=30&fps=30&width=64&height=48", 30);
    EXPECT_EQ(p.playback().info().mode, "color+depth");
    EXPECT_TRUE(p.playback().info().haptics);
    haptic_task::HapticTask *task = p.playback().hapticTask();
    ASSERT_NE(task, nullptr);
    // WHEN one second of simulated time passes  THEN the haptic task ran once a millisecond
    const std::uint64_t u0 = task->updates();
    p.step(1000);
    EXPECT_EQ(task->updates() - u0, 1000u);
    p.stepUntil([&] { return p.machine().state() == PlayerState::Stopped; });
    // AND every frame was shown once, on time (nothing in the pipeline takes simulated time),
    // each with its depth pair handed to the haptic task, and the hand pressed the surface
    const playback::PlaybackStats s = p.playback().stats();
    EXPECT_EQ(s.framesReceived, 30u);
    EXPECT_EQ(s.framesPresented, 30u);
    EXPECT_EQ(s.framesDropped, 0u);
    EXPECT_EQ(s.framesLate, 0u);
    EXPECT_EQ(s.lateMsMax, 0.0);
    EXPECT_EQ(s.depthPairsPublished, 30u);
    EXPECT_EQ(s.endsOfStream, 1u);
    const auto hs = p.playback().hapticStats();
    ASSERT_TRUE(hs.has_value());
    EXPECT_GT(hs->contactUpdates, 0u);
    EXPECT_EQ(hs->overruns, 0u);
    EXPECT_LE(hs->maxForce, 8.5 + 1e-9);
}

/// The mock fingertip, held still at (0, 0, −13) mm (scene box: no mapping).
std::unique_ptr<hal::HapticDevice> stillFinger(platform::Clock &clock)
{
    auto mock = std::make_unique<drivers::MockHapticDevice>(clock);
    mock->setWaypoints({{clock.now(), {0.0, 0.0, -0.013}, 0}});
    return mock;
}

/// Largest change between consecutive entries of \a f, N.
double largestStep(const std::vector<double> &f)
{
    double step = 0.0;
    for (std::size_t i = 1; i < f.size(); ++i)
        step = std::max(step, std::fabs(f[i] - f[i - 1]));
    return step;
}

// The clip of the cut tests: flat surfaces rising 0.1 mm a frame from −11 mm (interpolated
// between frames, fix (b)), then at frame 30 (1 s) a cut to +12 mm: the still finger at −13 mm,
// 4.9 mm in before, is 25 mm behind the new surface, more than the cut threshold (10 mm, a
// quarter of the box depth), so the spring force would step by 16 N, far over the 2 N limit.
constexpr std::uint64_t kCutFrames = 60;
constexpr std::uint32_t kCutFrame = 30;
constexpr double kFinger = -0.013;
constexpr double kAfterCut = 0.012;
double cutClip(std::uint32_t i)
{
    return i < kCutFrame ? -0.011 + 0.0001 * i : kAfterCut;
}
const char *const kCutUrl = "mock://clip?frames=60&fps=30&width=64&height=48&depth_bits=16";

struct CutRun {
    double before = 0.0;        ///< Force when frame 27 (0.9 s) goes on screen, N.
    std::vector<double> force;  ///< Device output after each update from there, 400 updates.
    std::vector<double> proxyZ; ///< The proxy's height after each of them, m.
    double reengaged = 0.0;     ///< Force once the finger left and pressed 3 mm in again, N.
    double maxOutput = 0.0;     ///< Largest force the device output over the whole run, N.
    std::uint64_t releases = 0; ///< Safety releases of the haptic task.
};

/// Plays the cut clip with the player's haptic settings and \a reengage, the finger still.
CutRun playCut(haptics::Reengage reengage)
{
    playback::PlaybackConfig config; // the player's renderer: the fingertip (method finger)
    config.haptics.renderer.reengage = reengage;
    SimPlayer p(config, &stillFinger, &cutClip);
    auto &mock = static_cast<drivers::MockHapticDevice &>(*p.device());
    CutRun run;
    p.play(kCutUrl, kCutFrames);
    haptic_task::HapticTask *task = p.playback().hapticTask();
    EXPECT_NE(task, nullptr);
    if (task == nullptr)
        return run;
    p.stepUntil([&] { return p.playback().position() >= 0.9 - 1e-9; });
    run.before = mock.lastForce().z;
    for (int i = 0; i < 400; ++i) {
        p.step(1);
        run.force.push_back(mock.lastForce().z);
        glm::dvec3 hip, proxy;
        EXPECT_TRUE(task->lastPose(hip, proxy));
        run.proxyZ.push_back(proxy.z);
    }
    // The finger leaves (20 mm over the new surface) and presses 3 mm into it again.
    const platform::TimePoint now = p.clock().now();
    mock.setWaypoints({{now, {0.0, 0.0, kFinger}, 0},
                       {now + 100ms, {0.0, 0.0, kAfterCut + 0.02}, 0},
                       {now + 200ms, {0.0, 0.0, kAfterCut + 0.02}, 0},
                       {now + 300ms, {0.0, 0.0, kAfterCut - 0.003}, 0}});
    p.step(400);
    run.reengaged = mock.lastForce().z;

    run.maxOutput = mock.maxForceMagnitude();
    run.releases = task->stats().safetyReleases;
    return run;
}

// Fix (b) through the player: before the cut the surface rises 0.1 mm a frame under the still
// finger; interpolated, the force rises by k·0.1 mm / 33 updates = 2.4 mN an update (a held
// frame would step it by 80 mN at each frame).
void expectSmoothBeforeTheCut(const CutRun &run)
{
    // Frame 27 is at −8.3 mm: 4.7 mm in, 3.76 N, within one frame's rise (80 mN).
    EXPECT_NEAR(run.before, 800.0 * (cutClip(27) - kFinger), 0.08);
    // The 60 updates after frame 27 went on screen: the cut is 100 ms after its time.
    const std::vector<double> beforeCut(run.force.begin(), run.force.begin() + 60);
    EXPECT_LE(largestStep(beforeCut), 0.01) << "the surface's motion is felt in steps";
}

TEST(PlaybackSimTest, ASceneCutInAPlayedClipReseatsTheProxyAndRampsTheForceIn)
{
    // GIVEN the player re-engaging by a ramp (the `play` default) and the fingertip renderer
    const CutRun run = playCut(haptics::Reengage::Ramp);
    expectSmoothBeforeTheCut(run);
    // THEN the force-jump safety trips at the cut; the proxy is re-seated on the new surface
    // (within 1 mm of it 100 ms after the cut) and the force ramps in over the renderer's 0.25 s
    // ramp from the press before the cut (3.9 N) toward the device's 8.5 N: (8.5 − 3.9) N / 250
    // updates = 18 mN an update, at most 30 mN (without safety: a step of the task's 2 N rate
    // limit). The new surface is deeper over the finger than the device can push it out of: once
    // the ramp has held the maximum 3 ms the finger is let go (a second release; at most 5
    // updates at the maximum), and the force unloads at the rate limit.
    EXPECT_EQ(run.releases, 2u);
    EXPECT_NEAR(run.proxyZ[200], kAfterCut, 0.001);
    std::size_t atMax = 0;
    std::size_t firstMax = run.force.size();
    for (std::size_t i = 0; i < run.force.size(); ++i) {
        if (run.force[i] >= 8.5 - 1e-6) {
            ++atMax;
            firstMax = std::min(firstMax, i);
        }
    }
    ASSERT_LT(firstMax, run.force.size()) << "the ramp never reached the new contact's force";
    const std::vector<double> ramp(run.force.begin(),
                                   run.force.begin() + static_cast<long>(firstMax) + 1);
    EXPECT_LE(largestStep(ramp), 0.03) << "the cut was felt as a force step";
    EXPECT_LE(atMax, 5u);
    EXPECT_LE(largestStep(run.force), 2.0 + 1e-9);
    EXPECT_EQ(run.force.back(), 0.0);
    // AND once the finger left and pressed 3 mm into the new surface, it feels k·3 mm = 2.4 N
    EXPECT_NEAR(run.reengaged, 800.0 * 0.003, 0.01);
}

TEST(PlaybackSimTest, ASceneCutInAPlayedClipReleasesTheForceUntilTheFingerComesOut)
{
    // GIVEN the player releasing at a cut (paper IV.C, the renderer's default)
    const CutRun run = playCut(haptics::Reengage::Release);
    expectSmoothBeforeTheCut(run);
    // THEN the safety trips once and the force goes to zero instead of up: the device never
    // output more than the press before the cut (3.92 N at frame 29), and 300 ms after the cut
    // the finger, still behind the new surface, feels nothing
    EXPECT_EQ(run.releases, 1u);
    EXPECT_LE(run.maxOutput, 800.0 * (cutClip(kCutFrame - 1) - kFinger) + 0.01);
    EXPECT_EQ(run.force.back(), 0.0);
    EXPECT_NEAR(run.proxyZ.back(), kFinger, 1e-12) << "released: the proxy is at the finger";
    // AND once the finger left and pressed 3 mm into the new surface, it feels k·3 mm = 2.4 N
    EXPECT_NEAR(run.reengaged, 800.0 * 0.003, 0.01);
}

/// The t column (haptic time) of every row of the force log \a path.
std::vector<double> loggedTimes(const std::string &path)
{
    std::vector<double> t;
    std::ifstream in(path);
    std::string line;
    std::getline(in, line); // header
    while (std::getline(in, line))
        t.push_back(std::stod(line.substr(0, line.find(','))));
    return t;
}

TEST(PlaybackSimTest, PauseFreezesTheHapticTimeAndTheSurfaceUnderTheFinger)
{
    // GIVEN the rising surface under the still finger, the force logged
    char dir[] = "/tmp/dt-playback-sim-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    playback::PlaybackConfig config;
    config.haptics.forceLogPath = std::string(dir) + "/force-log.csv";
    SimPlayer p(config, &stillFinger, &cutClip);
    auto &mock = static_cast<drivers::MockHapticDevice &>(*p.device());
    p.play(kCutUrl, kCutFrames);
    haptic_task::HapticTask *task = p.playback().hapticTask();
    ASSERT_NE(task, nullptr);
    p.stepUntil([&] { return p.playback().position() >= 0.5 - 1e-9; });
    // WHEN paused (the render thread takes it at its next wake-up, within 5 ms)
    ASSERT_TRUE(p.machine().execute("pause").accepted);
    p.step(10);
    const double position = p.playback().position();
    const double force = mock.lastForce().z;
    glm::dvec3 hip, proxy0, proxy;
    ASSERT_TRUE(task->lastPose(hip, proxy0));
    const std::uint64_t rendered0 = task->stats().renderedUpdates;
    // THEN for half a second the picture, the surface under the finger and its force stand still
    for (int i = 0; i < 500; ++i) {
        p.step(1);
        ASSERT_EQ(p.playback().position(), position) << i;
        ASSERT_EQ(mock.lastForce().z, force) << i;
        ASSERT_TRUE(task->lastPose(hip, proxy));
        ASSERT_EQ(proxy.z, proxy0.z) << i;
    }
    const std::uint64_t rendered1 = task->stats().renderedUpdates;
    // AND resumed, the surface rises on: 0.1 mm a frame, 80 mN a frame, 0.48 N over 0.2 s
    // (within one frame's 80 mN)
    ASSERT_TRUE(p.machine().execute("toggle-pause").accepted);
    p.step(200);
    EXPECT_NEAR(p.playback().position() - position, 0.2, 1.0 / 30.0 + 1e-9);
    EXPECT_NEAR(mock.lastForce().z - force, 0.48, 0.08);
    // AND the haptic time of every update while paused was the same
    task->drainTelemetry();
    // (the log is under its temporary name, PATH.tmp.PID, until the task stops and renames it)
    const std::string writing = config.haptics.forceLogPath + ".tmp." + std::to_string(::getpid());
    const std::vector<double> t = loggedTimes(writing);
    ASSERT_GE(t.size(), rendered1);
    ASSERT_LT(rendered0, rendered1);
    for (std::uint64_t i = rendered0; i < rendered1; ++i)
        ASSERT_EQ(t[i], t[rendered0]) << "the haptic time moved while paused, row " << i;
    EXPECT_GT(t.back(), t[rendered0] + 0.15) << "and it moves again once resumed";
    std::remove(writing.c_str());
    rmdir(dir);
}

TEST(PlaybackSimTest, ALoopRestartsTheHapticClockAndTheSurfaceIsInterpolatedAgain)
{
    // GIVEN one second of the rising surface played in a loop under the still finger
    SimPlayer p(playback::PlaybackConfig{}, &stillFinger, &cutClip);
    auto &mock = static_cast<drivers::MockHapticDevice &>(*p.device());
    ASSERT_TRUE(p.machine().execute("loop on").accepted);
    p.play("mock://clip?frames=30&fps=30&width=64&height=48&depth_bits=16", kCutFrame);
    p.stepUntil([&] { return p.playback().stats().endsOfStream >= 1; });
    // WHEN it starts again (the surface back 2.9 mm down, a step ramped over 0.25 s)
    p.step(300);
    std::vector<double> f;
    for (int i = 0; i < 500; ++i) {
        p.step(1);
        f.push_back(mock.lastForce().z);
    }
    // THEN the second pass is interpolated as the first: the force rises 2.4 mN an update, not in
    // 80 mN steps at each frame (a haptic time held at the end of the first pass)
    EXPECT_EQ(p.machine().state(), PlayerState::Playing);
    EXPECT_LE(largestStep(f), 0.01);
    EXPECT_NEAR(f.back() - f.front(), 800.0 * 0.0001 * 30.0 * 0.5, 0.08) << "0.5 s of rise";
}

TEST(PlaybackSimTest, SeekRestartsAtTheTargetAndKeepsTheForce)
{
    SimPlayer p(playback::PlaybackConfig{}, &pressingHand);
    p.play("mock://clip?frames=300&fps=30", 300);
    haptic_task::HapticTask *task = p.playback().hapticTask();
    ASSERT_NE(task, nullptr);
    p.stepUntil([&] { return p.playback().position() > 1.0 && task->gain() > 0.99; });
    ASSERT_EQ(task->gain(), 1.0);
    // WHEN seeking to 5 s
    ASSERT_TRUE(p.machine().execute("seek 5 absolute").accepted);
    double leastGain = 1.0;
    p.stepUntil([&] {
        leastGain = std::min(leastGain, task->gain());
        const double pos = p.playback().position();
        return pos >= 5.0 - 1e-9 && pos < 5.5;
    });
    const platform::TimePoint shownAt = p.clock().now(); // the target frame is on screen
    // THEN the haptic clock restarted with the proxy and the force kept: the gain never ramped
    // from zero over the next 300 ms
    for (int i = 0; i < 300; ++i) {
        p.step(1);
        leastGain = std::min(leastGain, task->gain());
    }
    EXPECT_EQ(leastGain, 1.0);
    // AND it plays on from the target, never ahead of the simulated time since the target frame
    // went on screen (the decode thread restarts in real time after a seek, so a frame may come
    // a little late: the position is not pinned from below beyond the target)
    const double since = platform::toSeconds(p.clock().now() - shownAt);
    EXPECT_GE(p.playback().position(), 5.0);
    EXPECT_LE(p.playback().position(), 5.0 + since + 1e-9);
    EXPECT_EQ(p.playback().stats().seeks, 1u);
}

/// The mock source with every timestamp moved \a offset later: a stream whose first frame is not
/// at 0 (an MPEG-TS capture's timestamps start where its clock was). Seeks take the same timeline.
class OffsetSource final : public hal::MediaSource {
public:
    OffsetSource(std::unique_ptr<hal::MediaSource> inner, hal::Pts offset)
        : inner_(std::move(inner)), offset_(offset)
    {
    }
    [[nodiscard]] State state() const noexcept override { return inner_->state(); }
    [[nodiscard]] Result<void> open(const char *url) override { return inner_->open(url); }
    void close() noexcept override { inner_->close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return inner_->info(); }
    [[nodiscard]] Result<hal::Packet> readPacket() override
    {
        auto p = inner_->readPacket();
        if (p && !p->isEndOfStream()) {
            p->pts += offset_;
            p->dts += offset_;
        }
        return p;
    }
    [[nodiscard]] Result<void> seek(hal::Pts position) override
    {
        return inner_->seek(position - offset_);
    }

private:
    std::unique_ptr<hal::MediaSource> inner_;
    hal::Pts offset_;
};

TEST(PlaybackSimTest, ThePositionCountsFromTheFirstFramesTimestamp)
{
    // GIVEN a clip of 60 frames at 30 fps whose timestamps start at 10 s
    SimPlayer p(playback::PlaybackConfig{}, nullptr, {}, 30.0, "",
                [](std::unique_ptr<hal::MediaSource> mock) -> std::unique_ptr<hal::MediaSource> {
                    return std::make_unique<OffsetSource>(std::move(mock), 10s);
                });
    p.play("mock://clip?frames=60&fps=30&width=64&height=48", 60);
    // WHEN ten frames have gone on screen (none dropped)
    p.stepUntil([&] { return p.playback().stats().framesPresented >= 10; });
    ASSERT_EQ(p.playback().stats().framesPresented, 10u);
    ASSERT_EQ(p.playback().stats().framesDropped, 0u);
    // THEN the position is the tenth frame's time from the first: 9/30 s (Playback::position())
    EXPECT_NEAR(p.playback().position(), 9.0 / 30.0, 1e-9);
    // and the control socket's time-pos (mpv's) says the same; the duration is the clip's 2 s
    EXPECT_EQ(p.machine().execute("get time-pos").data, player::Value(p.playback().position()));
    const player::CommandOutcome duration = p.machine().execute("get duration");
    ASSERT_TRUE(duration.accepted) << duration.reason;
    EXPECT_NEAR(std::get<double>(duration.data), 2.0, 1e-9);
    // WHEN seeking to 1 s from the first frame
    ASSERT_TRUE(p.machine().execute("seek 1 absolute").accepted);
    p.stepUntil([&] { return p.playback().position() >= 1.0 - 1e-9; });
    const platform::TimePoint shownAt = p.clock().now();
    p.step(100);
    // THEN it plays on from 1 s after the first frame (the stream's 11 s), never ahead of the
    // simulated time since it went on screen
    const double since = platform::toSeconds(p.clock().now() - shownAt);
    EXPECT_GE(p.playback().position(), 1.0 - 1e-9);
    EXPECT_LE(p.playback().position(), 1.0 + since + 1e-9);
}

TEST(PlaybackSimTest, TheTuneInTimeCountsFromTheOpenToItsFirstFrameOnScreen)
{
    // GIVEN a player that idled 250 ms before its open
    SimPlayer p(playback::PlaybackConfig{}, nullptr);
    p.step(250);
    EXPECT_EQ(p.playback().stats().tuneInSeconds, 0.0); // nothing on screen yet
    // WHEN the clip is opened and its first frame goes on screen
    const platform::TimePoint opened = p.clock().now();
    p.play("mock://clip?frames=60&fps=30&width=64&height=48", 60);
    p.stepUntil([&] { return p.playback().stats().framesPresented >= 1; });
    const platform::TimePoint shown = p.clock().now();
    // THEN the tune-in time is from that open to that frame (the idle time is not in it)
    EXPECT_NEAR(p.playback().stats().tuneInSeconds, platform::toSeconds(shown - opened), 1e-3);
    EXPECT_LT(p.playback().stats().tuneInSeconds, 0.25);
    // and it stays that of the open while the clip plays on
    p.step(100);
    EXPECT_NEAR(p.playback().stats().tuneInSeconds, platform::toSeconds(shown - opened), 1e-3);
}

TEST(PlaybackSimTest, TheStiffnessCommandScalesTheForceTheFingerFeels)
{
    // GIVEN the still finger 2 mm into a still surface: k·2 mm = 1.6 N at the default 800 N/m
    SimPlayer p(playback::PlaybackConfig{}, &stillFinger, [](std::uint32_t) { return -0.011; });
    auto &mock = static_cast<drivers::MockHapticDevice &>(*p.device());
    p.play(kCutUrl, kCutFrames);
    p.step(500);
    ASSERT_NEAR(mock.lastForce().z, 1.6, 0.01);
    // WHEN the viewer sets 1200 N/m, then steps it down  THEN the force follows k within 0.01 N
    ASSERT_TRUE(p.machine().execute("stiffness 1200").accepted);
    p.step(20);
    EXPECT_NEAR(mock.lastForce().z, 1200.0 * 0.002, 0.01);
    ASSERT_TRUE(p.machine().execute("stiffness -").accepted);
    p.step(20);
    EXPECT_NEAR(mock.lastForce().z, p.playback().hapticTask()->stiffness() * 0.002, 0.01);
    EXPECT_LT(p.playback().hapticTask()->stiffness(), 1200.0);
}

/// Plays \a frames frames at 30 fps on the mock display (\a displayOptions) with \a maxLateness s
/// allowed, and stalls the render thread for \a stall s of simulated time in one present, 0.5 s
/// in. \return the stats at the end.
playback::PlaybackStats playWithAStall(double maxLateness, double stall, std::uint64_t frames,
                                       const char *displayOptions)
{
    playback::PlaybackConfig config;
    config.maxLateness = maxLateness;
    SimPlayer p(config, nullptr, {}, 30.0, displayOptions);
    p.play("mock://clip?frames=" + std::to_string(frames) + "&fps=30&width=64&height=48", frames);
    p.stepUntil([&] { return p.playback().position() > 0.5; });
    p.display().stallNextPresent(stall);
    p.stepUntil([&] { return p.machine().state() == PlayerState::Stopped; });
    const playback::PlaybackStats s = p.playback().stats();
    std::printf("max lateness %.2f s, stall %.0f ms: presented %llu, dropped %llu, late %llu, "
                "late max %.1f ms\n",
                maxLateness, stall * 1e3, static_cast<unsigned long long>(s.framesPresented),
                static_cast<unsigned long long>(s.framesDropped),
                static_cast<unsigned long long>(s.framesLate), s.lateMsMax);
    return s;
}

TEST(PlaybackSimTest, AStallDelaysFramesWithinTheMaxLatenessAndDropsThemBeyondIt)
{
    // GIVEN 2 s at 30 fps on a 60 Hz display, the render thread stalled 120 ms (3.6 frame
    // periods) in one present
    // WHEN 0.25 s of lateness is allowed  THEN every frame is shown, late (the frame after the
    // stalled one at least 120 - 33 ms after its time), none later than allowed
    const playback::PlaybackStats late = playWithAStall(0.25, 0.12, 60, "");
    EXPECT_EQ(late.framesReceived, 60u);
    EXPECT_EQ(late.framesPresented, 60u);
    EXPECT_EQ(late.framesDropped, 0u);
    EXPECT_GE(late.framesLate, 1u);
    EXPECT_GE(late.lateMsMax, 80.0);
    EXPECT_LE(late.lateMsMax, 250.0);
    // WHEN none is allowed  THEN the frames whose successors are due are skipped
    const playback::PlaybackStats strict = playWithAStall(0.0, 0.12, 60, "");
    EXPECT_EQ(strict.framesReceived, 60u);
    EXPECT_EQ(strict.framesPresented + strict.framesDropped, 60u);
    EXPECT_GE(strict.framesDropped, 1u);
}

TEST(PlaybackSimTest, FramesThatCannotCatchUpAreSkippedAfterThreeTimesTheMaxLateness)
{
    // GIVEN 30 fps on a 30 Hz display: every refresh needs a new frame, so a late player cannot
    // catch up by showing frames for one refresh instead of two
    // WHEN the render thread stalls for 80 ms (more than two frame periods behind, under the
    // 0.1 s of lateness allowed)
    const playback::PlaybackStats s = playWithAStall(0.1, 0.08, 120, "refresh=30");
    // THEN frames are skipped once the player has been late for 0.3 s (about 9 frames), and it is
    // back in time: it does not stay a frame period late to the end (3.5 s, over 100 frames)
    EXPECT_EQ(s.framesPresented + s.framesDropped, 120u);
    EXPECT_GE(s.framesDropped, 1u);
    EXPECT_LT(s.framesLate, 50u) << "late frames: the player stayed behind";
}

} // namespace
} // namespace depthtouch::playback_test
