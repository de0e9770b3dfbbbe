// The input loop: scripted remote keys (mock backend, manual clock) and the control socket feed
// the one command table.
#include "depthtouch/control/control_loop.h"

#include <atomic>

#include <gtest/gtest.h>

#include "control_test_support.h"
#include "depthtouch/control/play_loop.h"
#include "depthtouch/drivers/mock/mock_remote_input.h"
#include "support/temp_dir.h"

namespace depthtouch::control {
namespace {

using hal::Key;
using hal::KeyAction;
using platform::ManualClock;
using platform::TimePoint;
using std::chrono::milliseconds;
using std::chrono::seconds;

TEST(ControlLoopTest, remoteKeysDriveTheMachineUntilQuit)
{
    // GIVEN a playing machine and a remote with a scripted key sequence
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(100)));
    drivers::MockRemoteInput remote(clock);
    FakePlayer p;
    ASSERT_TRUE(p.m.execute("play").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.fake.calls.clear();
    const TimePoint t0 = clock.now();
    remote.pushKey(Key::Right, t0 + seconds(1));
    remote.push({Key::ChannelUp, KeyAction::Press, t0 + seconds(2)});
    remote.push({Key::ChannelUp, KeyAction::Repeat, t0 + milliseconds(2250)});
    remote.push({Key::ChannelUp, KeyAction::Release, t0 + milliseconds(2300)});
    remote.pushKey(Key::Mode3d, t0 + seconds(3));
    remote.pushKey(Key::PlayPause, t0 + seconds(4));
    remote.push({Key::PlayPause, KeyAction::Repeat, t0 + milliseconds(4050)});
    remote.pushKey(Key::Pause, t0 + seconds(5));  // refused: already paused
    remote.pushKey(Key::Digit7, t0 + seconds(6)); // unbound
    remote.pushKey(Key::Exit, t0 + seconds(7));
    remote.pushKey(Key::Play, t0 + seconds(8)); // after quit: never read

    // WHEN the loop runs
    ControlLoop loop(p.m, &remote, nullptr, clock);
    ASSERT_TRUE(loop.runUntil(t0 + seconds(60)));

    // THEN each key's command ran in order, repeats only where allowed, and quit ended the loop
    EXPECT_TRUE(p.m.quitRequested());
    EXPECT_EQ(p.m.state(), player::PlayerState::Stopped);
    EXPECT_EQ(p.fake.calls,
              (std::vector<std::string>{"seek 10 relative", "setStiffness 900", "setStiffness 1000",
                                        "setStereoMode tab", "pause", "stop"}));
    EXPECT_GE(clock.now(), t0 + seconds(7));
    EXPECT_LT(clock.now(), t0 + seconds(8));
    EXPECT_EQ(loop.stats().keyCommands, 7u);
    EXPECT_EQ(loop.stats().refused, 1u);
    EXPECT_EQ(remote.pending(), 3u) << "Exit's release and the Play key stay unread";
}

TEST(ControlLoopTest, quietInputReturnsAtTheDeadline)
{
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(5)));
    drivers::MockRemoteInput remote(clock);
    FakePlayer p;
    ControlLoop loop(p.m, &remote, nullptr, clock);
    ASSERT_TRUE(loop.runUntil(clock.now() + seconds(2)));
    EXPECT_EQ(clock.now(), TimePoint(seconds(7)));
    EXPECT_FALSE(p.m.quitRequested());
    EXPECT_TRUE(p.fake.calls.empty());
}

TEST(ControlLoopTest, runControlLoopReadsTheRemoteUntilQuit)
{
    // GIVEN a remote alone (no control socket) whose Exit key comes 2.5 s after the start
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(5)));
    drivers::MockRemoteInput remote(clock);
    remote.pushKey(Key::Exit, TimePoint(milliseconds(7500)));
    FakePlayer p;
    // WHEN the main loop runs  THEN it reads the key and returns once quit is asked, at that time
    ASSERT_TRUE(runControlLoop(p.m, &remote, nullptr, clock));
    EXPECT_TRUE(p.m.quitRequested());
    EXPECT_EQ(clock.now(), TimePoint(milliseconds(7500)));
}

TEST(ControlLoopTest, lostRemoteIsLeftAloneUntilTheDeadline)
{
    // GIVEN a remote unplugged before the loop starts, and no control socket
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(5)));
    drivers::MockRemoteInput remote(clock);
    remote.unplug();
    FakePlayer p;
    ControlLoop loop(p.m, &remote, nullptr, clock);

    // WHEN the loop runs for 2 s, and the remote comes back with a key while it runs again
    ASSERT_TRUE(loop.runUntil(clock.now() + seconds(2)));
    const bool lostAfterFirst = loop.stats().remoteLost;
    const TimePoint firstEnd = clock.now();
    remote.replug();
    remote.pushKey(Key::Exit, TimePoint(seconds(8)));
    ASSERT_TRUE(loop.runUntil(clock.now() + seconds(2)));

    // THEN the loss is counted once, the loop sleeps out its slices (a lost remote that is polled
    // again returns at once: the loop would spin), and the lost remote is never read again
    EXPECT_TRUE(lostAfterFirst);
    EXPECT_EQ(firstEnd, TimePoint(seconds(7)));
    EXPECT_EQ(clock.now(), TimePoint(seconds(9)));
    EXPECT_FALSE(p.m.quitRequested()) << "a remote reported lost is not read again";
    EXPECT_EQ(remote.pending(), 2u) << "the Exit key's press and release stay unread";
    EXPECT_EQ(loop.stats().keys, 0u);
}

/// A remote whose input device is plugged in at a time (hal::BackendConfig::awaitDevice): it
/// waits until then and says so.
class AwaitedRemote final : public hal::RemoteInput {
public:
    AwaitedRemote(platform::Clock &clock, TimePoint pluggedAt) : clock_(clock), at_(pluggedAt) {}
    Result<hal::KeyEvent> poll(hal::Deadline until) override
    {
        clock_.sleepUntil(until);
        return unexpected(Errc::Timeout, "No key");
    }
    bool awaitingDevice() const noexcept override { return clock_.now() < at_; }

private:
    platform::Clock &clock_;
    TimePoint at_;
};

TEST(ControlLoopTest, theRemotesStateIsTheMachinesRemoteConnected)
{
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(5)));
    FakePlayer p;
    const auto get = [&] { return p.m.execute("get remote-connected"); };
    // no remote: unavailable
    EXPECT_EQ(get().reason, "property unavailable");
    // a remote not yet plugged in: false, then true once it is (within the loop's run)
    AwaitedRemote remote(clock, TimePoint(seconds(6)));
    ControlLoop loop(p.m, &remote, nullptr, clock);
    EXPECT_EQ(get().data, player::Value(false));
    ASSERT_TRUE(loop.runUntil(TimePoint(milliseconds(5500))));
    EXPECT_EQ(get().data, player::Value(false));
    ASSERT_TRUE(loop.runUntil(TimePoint(seconds(7))));
    EXPECT_EQ(get().data, player::Value(true));
    // a remote lost (NoDevice, without awaitDevice): false
    drivers::MockRemoteInput lost(clock);
    lost.unplug();
    ControlLoop lostLoop(p.m, &lost, nullptr, clock);
    ASSERT_TRUE(lostLoop.runUntil(clock.now() + seconds(1)));
    EXPECT_EQ(get().data, player::Value(false));
    // and each change, once, to the player's on-screen display (REMOTE: NO DEVICE): waited
    // for, plugged in, lost (the polls that change nothing pass nothing on)
    EXPECT_EQ(p.fake.remoteShown, (std::vector<std::string>{"false", "true", "false"}));
}

TEST(ControlLoopTest, lostRemoteLeavesTheSocketWorking)
{
    testing::TempDir dir("dt-loop-");
    const std::string path = dir.path("dt.sock");

    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(1)));
    drivers::MockRemoteInput remote(clock);
    remote.unplug();
    FakePlayer p;
    {
        auto server = ControlServer::create(path, p.m);
        ASSERT_TRUE(server) << server.error().what;

        const platform::UniqueFd client = connectClient(path);
        ASSERT_NO_FATAL_FAILURE(
            sendAll(client, "{\"command\":[\"play\"]}\n{\"command\":[\"quit\"]}\n"));

        ASSERT_TRUE(runControlLoop(p.m, &remote, server->get(), clock));

        EXPECT_TRUE(p.m.quitRequested());
        EXPECT_EQ(p.fake.calls, (std::vector<std::string>{"open movie.mkv", "stop"}));
    }
}

/// Plays, on \a clock, a player started with no file (play --idle) through playUntilDone(): a
/// client's loadfile of two entries at turn 5, each opening one turn later, each ending 4 turns
/// after that, and quit at turn 50. \return the turns run.
int runPlaylistScript(bool idle, ManualClock &clock, player::test::FakePlayerActions &fake)
{
    player::StateMachine m(fake, player::PlayerSettings{});
    ControlLoop loop(m, nullptr, nullptr, clock, milliseconds(10));
    std::unique_ptr<ControlServer> server;
    int turn = 0;
    const auto eachTurn = [&] {
        ++turn;
        if (turn == 5) {
            EXPECT_TRUE(m.execute("loadfile a.mkv").accepted);
            EXPECT_TRUE(m.execute("loadfile b.mkv append").accepted);
        }
        if (turn == 6 || turn == 11) {
            EXPECT_TRUE(m.onOpened());
        }
        if (turn == 10 || turn == 15) {
            EXPECT_TRUE(m.onEndOfStream());
        }
        if (turn == 50) {
            EXPECT_TRUE(m.execute("quit").accepted);
        }
    };
    const std::atomic<bool> stop{false};
    const LoopOutcome out = playUntilDone(m, loop, server, eachTurn, stop, {0.0, idle}, clock);
    EXPECT_TRUE(out.opened);
    EXPECT_TRUE(out.failure.empty()) << out.failure;
    EXPECT_FALSE(out.stopped);
    return turn;
}

// Issue 61: `play --idle` with no file waits (idle) for a client's loadfile, plays the playlist's
// entries one after the other, and stays up after the last until quit; without --idle the player
// ends after the last entry, not the first.
TEST(ControlLoopTest, anIdlePlayerWaitsForLoadfileAndPlaysThePlaylistToItsEnd)
{
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(5)));
    player::test::FakePlayerActions fake;
    EXPECT_EQ(runPlaylistScript(true, clock, fake), 50) << "stayed up, idle, until quit";
    EXPECT_EQ(fake.calls, (std::vector<std::string>{"open a.mkv", "startPlayback", "stop",
                                                    "open b.mkv", "startPlayback", "stop"}));
    player::test::FakePlayerActions once;
    EXPECT_EQ(runPlaylistScript(false, clock, once), 15) << "ends at the last entry's end";
}

} // namespace
} // namespace depthtouch::control
