// The player's playlist and mpv's file events (issue 61): loadfile replace/append/append-play,
// playlist-next/prev, the next entry at the end of a file, and the events an mpv client waits for
// (start-file, file-loaded, end-file with its reason, playback-restart, idle), in mpv's order.
// Reference: mpv's manual, "List of Input Commands" and "List of events".
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/player/state_machine.h"
#include "fake_player_actions.h"

namespace depthtouch::player {
namespace {

using test::FakePlayerActions;
using test::RecordingListener;
using S = PlayerState;

/// An idle player with no file (play --idle), recording every event.
struct IdlePlayer {
    IdlePlayer() : m(fake, PlayerSettings{}) { m.addListener(&listener); }
    /// The value of property \a name (a number), or NaN when refused.
    double number(const char *name)
    {
        const CommandOutcome out = m.execute(std::string("get ") + name);
        return out.accepted && std::holds_alternative<double>(out.data)
                   ? std::get<double>(out.data)
                   : std::numeric_limits<double>::quiet_NaN();
    }
    /// The end-file events' reasons, in order.
    std::vector<std::string> endReasons() const
    {
        std::vector<std::string> out;
        for (const PlayerEvent &e : listener.events)
            if (e.kind == PlayerEventKind::FileEnded)
                out.push_back(e.message);
        return out;
    }
    FakePlayerActions fake;
    StateMachine m;
    RecordingListener listener{true};
};

TEST(PlaylistTest, appendAddsWithoutPlayingAndAppendPlayStartsWhenIdle)
{
    IdlePlayer p;
    EXPECT_EQ(p.m.execute("play").reason, "no file or URL to play");
    ASSERT_TRUE(p.m.execute("loadfile a.mkv append").accepted);
    EXPECT_EQ(p.m.state(), S::Idle) << "append starts nothing";
    EXPECT_TRUE(p.fake.calls.empty());
    EXPECT_EQ(p.number("playlist-count"), 1.0);
    EXPECT_EQ(p.number("playlist-pos"), -1.0);
    ASSERT_TRUE(p.m.execute("loadfile b.mkv append-play").accepted);
    EXPECT_EQ(p.fake.calls, std::vector<std::string>{"open b.mkv"}) << "the entry appended plays";
    EXPECT_EQ(p.number("playlist-pos"), 1.0);
    EXPECT_EQ(p.number("playlist-pos-1"), 2.0);
    ASSERT_FALSE(p.listener.events.empty());
    EXPECT_EQ(p.listener.events.front().kind, PlayerEventKind::StartFile);
    EXPECT_EQ(p.listener.events.front().playlistEntryId, 2);
    // While something plays append-play only appends.
    p.fake.calls.clear();
    ASSERT_TRUE(p.m.execute("loadfile c.mkv append-play").accepted);
    EXPECT_TRUE(p.fake.calls.empty());
    EXPECT_EQ(p.number("playlist-count"), 3.0);
}

TEST(PlaylistTest, theNextEntryPlaysAtTheEndOfAFileAndIdleFollowsTheLast)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv").accepted);
    ASSERT_TRUE(p.m.execute("loadfile b.mkv append").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    p.fake.calls.clear();

    ASSERT_TRUE(p.m.onEndOfStream());
    EXPECT_EQ(p.fake.calls, (std::vector<std::string>{"stop", "open b.mkv"}));
    EXPECT_EQ(p.m.state(), S::Opening);
    EXPECT_EQ(p.m.url(), "b.mkv");
    EXPECT_EQ(p.number("playlist-pos"), 1.0);
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"end-of-stream", "end-file", "state",
                                                            "start-file", "state"}))
        << "mpv: end-file (eof), then start-file of the next; no idle between";
    EXPECT_EQ(p.endReasons(), std::vector<std::string>{"eof"});
    EXPECT_EQ(p.listener.events[1].playlistEntryId, 1);
    EXPECT_EQ(p.listener.events[3].playlistEntryId, 2);

    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    ASSERT_TRUE(p.m.onEndOfStream());
    EXPECT_EQ(p.m.state(), S::Stopped);
    EXPECT_EQ(p.listener.names(),
              (std::vector<std::string>{"end-of-stream", "end-file", "state", "idle"}));
    EXPECT_EQ(p.number("playlist-pos"), -1.0) << "none is current once idle";
    EXPECT_EQ(p.number("playlist-count"), 2.0) << "the playlist stays (mpv --idle)";
}

TEST(PlaylistTest, aFileThatOpensSaysFileLoadedThenPlaybackRestartAndEachSeekRestarts)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv replace").accepted);
    ASSERT_TRUE(p.m.onOpened());
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"start-file", "state", "state",
                                                            "file-loaded", "playback-restart"}));
    p.listener.events.clear();
    ASSERT_TRUE(p.m.execute("pause").accepted);
    ASSERT_TRUE(p.m.execute("play").accepted);
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"state", "state"}))
        << "pause and resume load nothing";
    p.listener.events.clear();
    ASSERT_TRUE(p.m.execute("seek 5").accepted);
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"seek", "playback-restart"}));
}

TEST(PlaylistTest, replaceStopsWhatPlaysAndEndsItWithReasonStop)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv").accepted);
    ASSERT_TRUE(p.m.execute("loadfile x.mkv append").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    p.fake.calls.clear();
    ASSERT_TRUE(p.m.execute("loadfile b.mkv replace").accepted);
    EXPECT_EQ(p.fake.calls, (std::vector<std::string>{"stop", "open b.mkv"}));
    EXPECT_EQ(p.endReasons(), std::vector<std::string>{"stop"});
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"end-file", "start-file", "state"}))
        << "no idle: another file opens";
    EXPECT_EQ(p.number("playlist-count"), 1.0) << "replace makes it the whole playlist";
    EXPECT_EQ(p.listener.events[1].playlistEntryId, 3);
}

TEST(PlaylistTest, playlistNextAndPrevStepWeakRefusesAtTheEndsForceStops)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv").accepted);
    ASSERT_TRUE(p.m.execute("loadfile b.mkv append").accepted);
    ASSERT_TRUE(p.m.onOpened());
    EXPECT_EQ(p.m.execute("playlist-prev").reason, "no previous entry in the playlist");
    p.fake.calls.clear();
    ASSERT_TRUE(p.m.execute("playlist-next").accepted);
    EXPECT_EQ(p.fake.calls, (std::vector<std::string>{"stop", "open b.mkv"}));
    EXPECT_EQ(p.number("playlist-pos"), 1.0);
    ASSERT_TRUE(p.m.onOpened());
    EXPECT_EQ(p.m.execute("playlist-next weak").reason, "no next entry in the playlist");
    EXPECT_EQ(p.m.state(), S::Playing);
    ASSERT_TRUE(p.m.execute("playlist-prev").accepted);
    EXPECT_EQ(p.m.url(), "a.mkv");
    ASSERT_TRUE(p.m.onOpened());
    ASSERT_TRUE(p.m.execute("playlist-prev force").accepted);
    EXPECT_EQ(p.m.state(), S::Stopped);
    EXPECT_EQ(p.listener.events.back().kind, PlayerEventKind::Idle);
}

// mpv's stop with nothing open (node-mpv's stop() on an idle player): success, the playlist
// forgotten, no file event and nothing asked of the player. Before, it was refused ("cannot stop
// while idle").
TEST(PlaylistTest, stopWithNothingOpenSucceedsAndForgetsThePlaylist)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv append").accepted);
    ASSERT_EQ(p.number("playlist-count"), 1.0);
    p.listener.events.clear();
    const CommandOutcome out = p.m.execute("stop");
    EXPECT_TRUE(out.accepted) << out.reason;
    EXPECT_EQ(p.m.state(), S::Idle);
    EXPECT_EQ(p.number("playlist-count"), 0.0);
    EXPECT_TRUE(p.fake.calls.empty());
    EXPECT_TRUE(p.listener.events.empty());
}

TEST(PlaylistTest, stopClearsThePlaylistQuitEndsWithQuitAndNoIdle)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile a.mkv").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    ASSERT_TRUE(p.m.execute("stop").accepted);
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"end-file", "state", "idle"}));
    EXPECT_EQ(p.endReasons(), std::vector<std::string>{"stop"});
    EXPECT_EQ(p.number("playlist-count"), 0.0) << "mpv's stop clears the playlist";

    ASSERT_TRUE(p.m.execute("loadfile b.mkv").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    ASSERT_TRUE(p.m.execute("quit").accepted);
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"end-file", "state", "shutdown"}));
    EXPECT_EQ(p.endReasons(), std::vector<std::string>{"quit"});
}

TEST(PlaylistTest, aFileThatDoesNotOpenEndsWithErrorLoadingFailedThenIdle)
{
    IdlePlayer p;
    ASSERT_TRUE(p.m.execute("loadfile gone.mkv").accepted);
    p.listener.events.clear();
    ASSERT_TRUE(p.m.onOpenFailed("no such file"));
    EXPECT_EQ(p.listener.names(), (std::vector<std::string>{"end-file", "error", "state", "idle"}));
    EXPECT_EQ(p.listener.events[0].message, "error");
    EXPECT_EQ(p.listener.events[0].detail, "loading failed");
    // One that played and then failed: mpv's generic error.
    ASSERT_TRUE(p.m.execute("loadfile b.mkv").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.listener.events.clear();
    ASSERT_TRUE(p.m.onFailure("decoder lost"));
    EXPECT_EQ(p.listener.events[0].kind, PlayerEventKind::FileEnded);
    EXPECT_EQ(p.listener.events[0].detail, "something happened");
}

TEST(PlaylistTest, timeRemainingIsTheDurationLessThePositionUnavailableWithoutOne)
{
    IdlePlayer p;
    EXPECT_EQ(p.m.execute("get time-remaining").reason, "property unavailable");
    ASSERT_TRUE(p.m.execute("loadfile a.mkv").accepted);
    ASSERT_TRUE(p.m.onOpened());
    p.fake.position = {12.5, 50.0};
    EXPECT_EQ(p.number("time-remaining"), 37.5);
    p.fake.position = {12.5, std::numeric_limits<double>::quiet_NaN()}; // a live stream
    EXPECT_EQ(p.m.execute("get time-remaining").reason, "property unavailable");
}

} // namespace
} // namespace depthtouch::player
