// The player state machine beyond its specification table (state_machine_spec_test.cpp):
// failures, end of stream, silent streams, settings, queries.
#include "depthtouch/player/state_machine.h"

#include <set>
#include <limits>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/player/state_machine_rig.h"

namespace depthtouch::player {
namespace {

using namespace test;
using S = PlayerState;

TEST(StateMachineTest, refusalsGiveAReason)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    EXPECT_EQ(m.execute("pause").reason, "cannot pause while idle");
    reach(m, fake, S::Playing);
    EXPECT_EQ(m.execute("play").reason, "already playing");
    ASSERT_TRUE(m.execute("pause").accepted);
    fake.calls.clear();
    EXPECT_EQ(m.execute("pause").reason, "already paused");
    EXPECT_EQ(m.execute("warp 9").reason, "unknown command 'warp'");
    EXPECT_EQ(m.execute("seek fast").reason, "seek: 'fast' is not a number of seconds");
    EXPECT_TRUE(fake.calls.empty());
}

TEST(StateMachineTest, seekWhilePausedStaysPaused)
{
    Rig rig(S::Paused);
    auto &[fake, m, listener] = rig;

    EXPECT_TRUE(m.execute("seek -5").accepted);
    EXPECT_TRUE(m.execute("seek 42 absolute").accepted);

    EXPECT_EQ(m.state(), S::Paused);
    EXPECT_EQ(fake.calls, (std::vector<std::string>{"seek -5 relative", "seek 42 absolute"}));
    EXPECT_EQ(listener.names(), (std::vector<std::string>{"seek", "seek"}));
}

TEST(StateMachineTest, failingActionMovesToErrorWithTheReason)
{
    struct Case {
        PlayerState from;
        const char *command;
        const char *action;
        const char *reason;
    };
    const Case cases[] = {
        {S::Playing, "pause", "pause", "pause failed: USB stalled"},
        {S::Paused, "toggle-pause", "resume", "resume failed: USB stalled"},
        {S::Playing, "seek 10", "seek", "seek failed: USB stalled"},
        {S::Playing, "stop", "stop", "stop failed: USB stalled"},
        {S::Playing, "haptics toggle", "setHapticsEnabled", "haptics failed: USB stalled"},
        {S::Playing, "recenter", "recenter", "recenter failed: USB stalled"},
        {S::Idle, "play", "open", "open failed: USB stalled"},
        {S::Paused, "stiffness -", "setStiffness", "stiffness failed: USB stalled"},
        {S::Playing, "next-stereo-mode", "setStereoMode", "stereo mode failed: USB stalled"},
    };
    for (const Case &c : cases) {
        SCOPED_TRACE(c.command);
        Rig rig(c.from);
        auto &[fake, m, listener] = rig;
        const SettingsSnapshot before(m);
        fake.failures[c.action] = Error(Errc::Io, "USB stalled");

        const CommandOutcome out = m.execute(c.command);

        EXPECT_FALSE(out.accepted);
        EXPECT_EQ(out.reason, c.reason);
        EXPECT_EQ(m.state(), S::Error);
        EXPECT_EQ(m.errorReason(), c.reason);
        EXPECT_EQ(listener.names(), (std::vector<std::string>{"error", "state"}));
        EXPECT_EQ(listener.events.front().message, c.reason);
        // The setting the failed action was meant to change is not taken.
        before.expectUnchanged(m, false);
        EXPECT_EQ(m.execute("get error").data, Value(std::string(c.reason)));
    }
}

TEST(StateMachineTest, actionRefusalRefusesTheCommandAndChangesNothing)
{
    Rig rig(S::Playing);
    auto &[fake, m, listener] = rig;
    fake.failures["setStereoMode"] = Error(Errc::NotSupported, "display cannot interleave");

    const CommandOutcome out = m.execute("stereo-mode interleaved");

    EXPECT_FALSE(out.accepted);
    EXPECT_EQ(out.reason, "stereo mode refused: display cannot interleave");
    EXPECT_EQ(m.state(), S::Playing);
    EXPECT_EQ(m.stereoMode(), StereoMode::SideBySide);
    EXPECT_TRUE(listener.events.empty());
}

TEST(StateMachineTest, openingCompletesOrFails)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    EXPECT_FALSE(m.onOpened()) << "not opening";
    EXPECT_TRUE(fake.calls.empty());

    ASSERT_TRUE(m.execute("play other.mkv").accepted);
    EXPECT_EQ(m.url(), "other.mkv");
    EXPECT_TRUE(m.onOpened());
    EXPECT_EQ(m.state(), S::Playing);
    EXPECT_EQ(fake.calls, (std::vector<std::string>{"open other.mkv", "startPlayback"}));

    // A second file while paused must be stopped first.
    ASSERT_TRUE(m.execute("pause").accepted);
    EXPECT_EQ(m.execute("play third.mkv").reason, "stop before opening another file");
    EXPECT_EQ(m.state(), S::Paused);

    FakePlayerActions fake2;
    StateMachine failing(fake2, defaultSettings());
    ASSERT_TRUE(failing.execute("play").accepted);
    EXPECT_TRUE(failing.onOpenFailed("no depth stream"));
    EXPECT_EQ(failing.state(), S::Error);
    EXPECT_EQ(failing.errorReason(), "open failed: no depth stream");
    EXPECT_EQ(failing.errorKind(), Errc::InvalidArgument) << "an input that does not open";
    EXPECT_FALSE(failing.onOpenFailed("late")) << "not opening any more";
    // A thread the system would not start: the system's failure (play exits 1, not 2).
    ASSERT_TRUE(failing.execute("play").accepted);
    EXPECT_TRUE(failing.onOpenFailed("cannot start the decode thread", Errc::OutOfResources));
    EXPECT_EQ(failing.errorKind(), Errc::OutOfResources);

    FakePlayerActions fake3;
    StateMachine noStart(fake3, defaultSettings());
    ASSERT_TRUE(noStart.execute("play").accepted);
    fake3.failures["startPlayback"] = Error(Errc::Busy, "display busy");
    EXPECT_TRUE(noStart.onOpened());
    EXPECT_EQ(noStart.state(), S::Error) << "a refused start cannot leave it opening for ever";
    EXPECT_EQ(noStart.errorKind(), Errc::Busy) << "the failed action's own code";
}

TEST(StateMachineTest, playWithoutUrlIsRefused)
{
    FakePlayerActions fake;
    StateMachine m(fake, PlayerSettings{});
    EXPECT_EQ(m.execute("play").reason, "no file or URL to play");
    EXPECT_EQ(m.execute("toggle-pause").reason, "no file or URL to play");
    EXPECT_EQ(m.state(), S::Idle);
    EXPECT_TRUE(fake.calls.empty());
}

TEST(StateMachineTest, endOfStreamWithoutLoopStops)
{
    Rig rig(S::Playing);
    // It stops with the reason "eof"; a late second notification changes nothing.
    expectStopsOnce(rig, &StateMachine::onEndOfStream, "eof");
}

TEST(StateMachineTest, endOfStreamWithLoopSeeksToTheStart)
{
    Rig rig(S::Playing, loopSettings());
    auto &[fake, m, listener] = rig;

    EXPECT_TRUE(m.onEndOfStream());
    EXPECT_TRUE(m.onEndOfStream());

    EXPECT_EQ(m.state(), S::Playing);
    // the loop's own restart, not a viewer's seek (which brings the OSD up)
    EXPECT_EQ(fake.calls, (std::vector<std::string>{"restart-for-loop", "restart-for-loop"}));
    // As mpv's --loop-file: a client is told of a seek to the start, not of an ended file
    EXPECT_EQ(listener.names(), (std::vector<std::string>{"seek", "seek"}));
    EXPECT_EQ(listener.events.front().message, "loop");

    // WHEN looping is switched off at run time THEN the next end stops
    ASSERT_TRUE(m.execute("loop off").accepted);
    EXPECT_TRUE(m.onEndOfStream());
    EXPECT_EQ(m.state(), S::Stopped);
}

TEST(StateMachineTest, endOfStreamIsIgnoredWhenNotPlaying)
{
    for (PlayerState s : {S::Idle, S::Opening, S::Stopped, S::Error}) {
        FakePlayerActions fake;
        StateMachine m(fake, defaultSettings());
        reach(m, fake, s);
        EXPECT_FALSE(m.onEndOfStream()) << playerStateName(s);
        EXPECT_EQ(m.state(), s);
        EXPECT_TRUE(fake.calls.empty());
    }
}
TEST(StateMachineTest, silentLiveStreamStopsEvenWithLoop)
{
    // GIVEN a player looping a live stream
    Rig rig(S::Playing, loopSettings());
    // WHEN the pipeline reports that the stream went silent
    // THEN it stops (no seek: a live stream cannot loop) and says why on the socket
    // AND a late second report changes nothing, nor one while not playing
    expectStopsOnce(rig, &StateMachine::onStreamSilent, "silent");
    for (PlayerState s : {S::Idle, S::Opening, S::Stopped, S::Error}) {
        FakePlayerActions other;
        StateMachine idle(other, defaultSettings());
        reach(idle, other, s);
        EXPECT_FALSE(idle.onStreamSilent()) << playerStateName(s);
        EXPECT_TRUE(other.calls.empty());
    }
}

TEST(StateMachineTest, aPlayerThatStaysWaitsForTheNextSenderOfASilentStream)
{
    // GIVEN a player that stays up (--idle) playing a live address
    Rig rig(S::Playing, reopenSettings());
    auto &[fake, m, listener] = rig;
    // WHEN its stream goes silent
    EXPECT_TRUE(m.onStreamSilent());
    // THEN it says so, stops, and opens the same address again to wait for the next sender
    EXPECT_EQ(fake.calls,
              (std::vector<std::string>{"stop", "awaitNextSender " + std::string(kUrl)}));
    EXPECT_EQ(listener.names(), (std::vector<std::string>{"end-of-stream", "state", "state"}));
    EXPECT_EQ(listener.events.front().message, "silent");
    EXPECT_EQ(listener.events[1].state, S::Stopped);
    EXPECT_EQ(m.state(), S::Opening);
    // AND when the next sender comes, it plays without a command
    EXPECT_TRUE(m.onOpened());
    EXPECT_EQ(m.state(), S::Playing);
    // AND a stop while it waits ends the waiting
    EXPECT_TRUE(m.onStreamSilent());
    EXPECT_EQ(m.state(), S::Opening);
    EXPECT_TRUE(m.execute("stop").accepted);
    EXPECT_EQ(m.state(), S::Stopped);
    EXPECT_EQ(fake.calls.back(), "stop");
}

TEST(StateMachineTest, aFailedWaitForTheNextSenderIsAnError)
{
    // GIVEN a player that stays up, whose pipeline cannot start waiting (no thread)
    Rig rig(S::Playing, reopenSettings());
    auto &[fake, m, listener] = rig;
    fake.failures["awaitNextSender"] = Error(Errc::OutOfResources, "no thread");
    // WHEN its stream goes silent
    EXPECT_TRUE(m.onStreamSilent());
    // THEN the machine says why in Error, not "opening" for ever
    EXPECT_EQ(m.state(), S::Error);
    EXPECT_NE(m.errorReason().find("no thread"), std::string::npos) << m.errorReason();
}

TEST(StateMachineTest, loopSeekFailureIsAnError)
{
    FakePlayerActions fake;
    StateMachine m(fake, loopSettings());
    reach(m, fake, S::Playing);
    fake.failures["seek"] = Error(Errc::Io, "demuxer cannot seek");
    EXPECT_TRUE(m.onEndOfStream());
    EXPECT_EQ(m.state(), S::Error);
    EXPECT_EQ(m.errorReason(), "loop seek failed: demuxer cannot seek");
}

TEST(StateMachineTest, failureNotificationOnlyWhileActive)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    EXPECT_FALSE(m.onFailure("haptic device unplugged"));
    EXPECT_EQ(m.state(), S::Idle);
    reach(m, fake, S::Paused);
    EXPECT_TRUE(m.onFailure("haptic device unplugged"));
    EXPECT_EQ(m.state(), S::Error);
    EXPECT_EQ(m.errorReason(), "haptic device unplugged");
}

TEST(StateMachineTest, stereoModeCyclesThroughEveryMode)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    RecordingListener listener;
    m.addListener(&listener);
    std::vector<std::string> seen;
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(m.execute("next-stereo-mode").accepted);
        seen.emplace_back(stereoModeName(m.stereoMode()));
    }
    EXPECT_EQ(seen, (std::vector<std::string>{"tab", "anaglyph", "mono", "interleaved", "sbs"}));
    EXPECT_EQ(listener.events.size(), 5u);
    EXPECT_EQ(listener.events.back().stereoMode, StereoMode::SideBySide);
    // Setting the current mode is accepted and does nothing.
    fake.calls.clear();
    EXPECT_TRUE(m.execute("stereo-mode sbs").accepted);
    EXPECT_TRUE(fake.calls.empty());
}

// The one range of every stiffness entry point (scene/stiffness.h): 100..3000 N/m, 100 a step.
TEST(StateMachineTest, stiffnessStepsAreClampedToTheOneRange)
{
    FakePlayerActions fake;
    StateMachine m(fake, stiffnessSettings(2950.0));

    EXPECT_TRUE(m.execute("stiffness +").accepted);
    EXPECT_EQ(m.stiffness(), 3000.0) << "2950 + 100 clamps to the maximum";
    const CommandOutcome atMax = m.execute("stiffness +");
    EXPECT_FALSE(atMax.accepted);
    EXPECT_EQ(atMax.reason, "stiffness already at its maximum, 3000 N/m");
    const CommandOutcome over = m.execute("stiffness 3001");
    EXPECT_FALSE(over.accepted);
    EXPECT_EQ(over.reason, "stiffness 3001 N/m is outside 100 N/m .. 3000 N/m");
    EXPECT_FALSE(m.execute("stiffness 99").accepted);
    EXPECT_TRUE(m.execute("stiffness 250").accepted);
    EXPECT_TRUE(m.execute("stiffness -").accepted);
    EXPECT_TRUE(m.execute("stiffness -").accepted);
    EXPECT_EQ(m.stiffness(), 100.0) << "150 - 100 clamps to the minimum";
    const CommandOutcome atMin = m.execute("stiffness -");
    EXPECT_FALSE(atMin.accepted);
    EXPECT_EQ(atMin.reason, "stiffness already at its minimum, 100 N/m");
    EXPECT_FALSE(m.execute("stiffness down").accepted);
    EXPECT_TRUE(m.execute("stiffness 3000").accepted) << "the ends are in the range";
    EXPECT_EQ(fake.calls,
              (std::vector<std::string>{"setStiffness 3000", "setStiffness 250", "setStiffness 150",
                                        "setStiffness 100", "setStiffness 3000"}));
    EXPECT_EQ(m.execute("get stiffness").data, Value(3000.0));
}

TEST(StateMachineTest, initialStiffnessIsClampedToTheOneRange)
{
    FakePlayerActions fake;
    EXPECT_EQ(StateMachine(fake, stiffnessSettings(9000.0)).stiffness(), 3000.0);
    EXPECT_EQ(StateMachine(fake, stiffnessSettings(20.0)).stiffness(), 100.0);
    EXPECT_EQ(StateMachine(fake, stiffnessSettings(std::nan(""))).stiffness(), 800.0);
}

TEST(StateMachineTest, hapticsSwitch)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    EXPECT_TRUE(m.execute("haptics on").accepted) << "already on: accepted, nothing to do";
    EXPECT_TRUE(fake.calls.empty());
    EXPECT_TRUE(m.execute("haptics toggle").accepted);
    EXPECT_FALSE(m.hapticsEnabled());
    EXPECT_TRUE(m.execute("haptics").accepted);
    EXPECT_TRUE(m.hapticsEnabled());
    EXPECT_EQ(fake.calls,
              (std::vector<std::string>{"setHapticsEnabled off", "setHapticsEnabled on"}));
}

TEST(StateMachineTest, afterQuitEveryCommandIsRefused)
{
    Rig rig(S::Playing);
    auto &[fake, m, listener] = rig;
    ASSERT_TRUE(m.execute("quit").accepted);
    EXPECT_TRUE(m.quitRequested());
    EXPECT_EQ(listener.names(), (std::vector<std::string>{"state", "shutdown"}));
    fake.calls.clear();
    for (const CommandSpec &spec : commandTable()) {
        EXPECT_FALSE(m.isValid(spec.id)) << spec.name;
        Command command;
        command.id = spec.id;
        EXPECT_EQ(m.execute(command).reason, "the player is quitting") << spec.name;
    }
    EXPECT_TRUE(fake.calls.empty());
}

TEST(StateMachineTest, quitStillQuitsWhenStopFails)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    reach(m, fake, S::Playing);
    fake.failures["stop"] = Error(Errc::Io, "device gone");
    EXPECT_TRUE(m.execute("quit").accepted);
    EXPECT_TRUE(m.quitRequested());
    EXPECT_EQ(m.state(), S::Error);
    EXPECT_EQ(m.errorReason(), "stop failed: device gone");
}

TEST(StateMachineTest, listenerCannotSendCommands)
{
    struct Reentrant final : PlayerListener {
        StateMachine *machine = nullptr;
        std::vector<CommandOutcome> outcomes;
        void onPlayerEvent(const PlayerEvent &) override
        {
            outcomes.push_back(machine->execute("stop"));
        }
    };
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    reach(m, fake, S::Playing);
    Reentrant listener;
    listener.machine = &m;
    m.addListener(&listener);
    ASSERT_TRUE(m.execute("pause").accepted);
    ASSERT_EQ(listener.outcomes.size(), 1u);
    EXPECT_FALSE(listener.outcomes.front().accepted);
    EXPECT_EQ(m.state(), S::Paused);
    EXPECT_EQ(fake.calls, std::vector<std::string>{"pause"});
    m.removeListener(&listener);
    ASSERT_TRUE(m.execute("play").accepted);
    EXPECT_EQ(listener.outcomes.size(), 1u) << "removed listeners hear nothing";
}

TEST(StateMachineTest, queriesReturnTheSettings)
{
    FakePlayerActions fake;
    StateMachine m(fake, defaultSettings());
    ASSERT_TRUE(m.execute("stereo-mode tab").accepted);
    EXPECT_EQ(m.execute("get state").data, Value(std::string("idle")));
    EXPECT_EQ(m.execute("get stereo-mode").data, Value(std::string("tab")));
    EXPECT_EQ(m.execute("get haptics").data, Value(true));
    EXPECT_EQ(m.execute("get stiffness").data, Value(800.0));
    EXPECT_EQ(m.execute("get loop").data, Value(false));
    EXPECT_EQ(m.execute("get url").data, Value(std::string(kUrl)));
}

// The properties a UI draws from (mpv's names, read with "get" and get_property): each against
// the value the fake pipeline was given, and "property unavailable" where mpv says so.
TEST(StateMachineTest, mediaPropertiesFollowThePipelineAndTheState)
{
    Rig rig(S::Idle);
    auto &[fake, m, listener] = rig;
    const auto get = [&](const char *name) { return m.execute(std::string("get ") + name); };
    fake.position = {12.5, 50.0};
    fake.force = 1.25;
    // nothing open: no position, no force; idle-active
    EXPECT_EQ(get("time-pos").reason, "property unavailable");
    EXPECT_EQ(get("haptic-force").reason, "property unavailable");
    EXPECT_EQ(get("path").reason, "property unavailable");
    EXPECT_EQ(get("idle-active").data, Value(true));
    EXPECT_EQ(get("eof-reached").data, Value(false));
    reach(m, fake, S::Playing);
    EXPECT_EQ(get("time-pos").data, Value(12.5));
    EXPECT_EQ(get("duration").data, Value(50.0));
    EXPECT_EQ(get("percent-pos").data, Value(25.0));
    EXPECT_EQ(get("pause").data, Value(false));
    EXPECT_EQ(get("path").data, Value(m.url()));
    EXPECT_EQ(get("idle-active").data, Value(false));
    EXPECT_EQ(get("haptic-force").data, Value(1.25));
    EXPECT_EQ(get("contact").data, Value(true));
    fake.force = 0.0;
    EXPECT_EQ(get("contact").data, Value(false));
    // the haptic device: unavailable without a haptic task, else what the task says (a player
    // that stays up waits for a Falcon plugged in later: false until then)
    EXPECT_EQ(get("haptic-device-connected").reason, "property unavailable");
    fake.connected = false;
    EXPECT_EQ(get("haptic-device-connected").data, Value(false));
    fake.connected = true;
    EXPECT_EQ(get("haptic-device-connected").data, Value(true));
    EXPECT_EQ(get("volume").data, Value(100.0));
    EXPECT_EQ(get("mute").data, Value(false));
    ASSERT_TRUE(m.execute("pause").accepted);
    EXPECT_EQ(get("pause").data, Value(true));
    // a live stream has no length: duration and percent-pos are unavailable, time-pos is not
    fake.position = {3.0, std::numeric_limits<double>::quiet_NaN()};
    EXPECT_EQ(get("duration").reason, "property unavailable");
    EXPECT_EQ(get("percent-pos").reason, "property unavailable");
    EXPECT_EQ(get("time-pos").data, Value(3.0));
    // the end without loop: eof-reached until the next play
    ASSERT_TRUE(m.execute("play").accepted);
    EXPECT_TRUE(m.onEndOfStream());
    EXPECT_EQ(get("eof-reached").data, Value(true));
    EXPECT_EQ(get("idle-active").data, Value(true));
    ASSERT_TRUE(m.execute("play").accepted);
    EXPECT_EQ(get("eof-reached").data, Value(false));
}

} // namespace
} // namespace depthtouch::player
