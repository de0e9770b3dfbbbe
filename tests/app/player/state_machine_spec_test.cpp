// The player state machine's specification: every command in every state (table-driven), each
// row the acceptance, the state after it and the one action it asks of the player.
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/player/state_machine_rig.h"

namespace depthtouch::player {
namespace {

using namespace test;
using S = PlayerState;

struct Row {
    PlayerState from;
    const char *command;
    bool accepted;
    PlayerState to;
    const char *call; ///< The one PlayerActions call expected, or "" for none.
};

// The specification: every command (one representative text per table row) in every state.
const std::vector<Row> kRows = {
    // Idle
    {S::Idle, "play", true, S::Opening, "open movie.mkv"},
    {S::Idle, "pause", false, S::Idle, ""},
    {S::Idle, "toggle-pause", true, S::Opening, "open movie.mkv"},
    {S::Idle, "stop", true, S::Idle, ""}, // mpv: success, the playlist forgotten
    {S::Idle, "seek 10", false, S::Idle, ""},
    {S::Idle, "next-stereo-mode", true, S::Idle, "setStereoMode tab"},
    {S::Idle, "stereo-mode anaglyph", true, S::Idle, "setStereoMode anaglyph"},
    {S::Idle, "haptics off", true, S::Idle, "setHapticsEnabled off"},
    {S::Idle, "stiffness +", true, S::Idle, "setStiffness 900"},
    {S::Idle, "recenter", false, S::Idle, ""},
    {S::Idle, "loop on", true, S::Idle, ""},
    {S::Idle, "quit", true, S::Idle, ""},
    {S::Idle, "get state", true, S::Idle, ""},
    {S::Idle, "snapshot", false, S::Idle, ""},
    {S::Idle, "show-progress", true, S::Idle, "showProgress"},
    {S::Idle, "volume +", true, S::Idle, "setVolume 102"},
    {S::Idle, "mute toggle", true, S::Idle, "setMute on"},
    {S::Idle, "loadfile b.mkv append", true, S::Idle, ""},
    {S::Idle, "playlist-next force", false, S::Idle, ""},
    // Opening
    {S::Opening, "play", false, S::Opening, ""},
    {S::Opening, "pause", false, S::Opening, ""},
    {S::Opening, "toggle-pause", false, S::Opening, ""},
    {S::Opening, "stop", true, S::Stopped, "stop"},
    {S::Opening, "seek 10", false, S::Opening, ""},
    {S::Opening, "next-stereo-mode", true, S::Opening, "setStereoMode tab"},
    {S::Opening, "stereo-mode anaglyph", true, S::Opening, "setStereoMode anaglyph"},
    {S::Opening, "haptics off", true, S::Opening, "setHapticsEnabled off"},
    {S::Opening, "stiffness +", true, S::Opening, "setStiffness 900"},
    {S::Opening, "recenter", false, S::Opening, ""},
    {S::Opening, "loop on", true, S::Opening, ""},
    {S::Opening, "quit", true, S::Stopped, "stop"},
    {S::Opening, "get state", true, S::Opening, ""},
    {S::Opening, "snapshot", false, S::Opening, ""},
    {S::Opening, "show-progress", true, S::Opening, "showProgress"},
    {S::Opening, "volume +", true, S::Opening, "setVolume 102"},
    {S::Opening, "mute toggle", true, S::Opening, "setMute on"},
    {S::Opening, "loadfile b.mkv append", true, S::Opening, ""},
    {S::Opening, "playlist-next force", true, S::Stopped, "stop"},
    // Playing
    {S::Playing, "play", false, S::Playing, ""},
    {S::Playing, "pause", true, S::Paused, "pause"},
    {S::Playing, "toggle-pause", true, S::Paused, "pause"},
    {S::Playing, "stop", true, S::Stopped, "stop"},
    {S::Playing, "seek 10", true, S::Playing, "seek 10 relative"},
    {S::Playing, "next-stereo-mode", true, S::Playing, "setStereoMode tab"},
    {S::Playing, "stereo-mode anaglyph", true, S::Playing, "setStereoMode anaglyph"},
    {S::Playing, "haptics off", true, S::Playing, "setHapticsEnabled off"},
    {S::Playing, "stiffness +", true, S::Playing, "setStiffness 900"},
    {S::Playing, "recenter", true, S::Playing, "recenter"},
    {S::Playing, "loop on", true, S::Playing, ""},
    {S::Playing, "quit", true, S::Stopped, "stop"},
    {S::Playing, "get state", true, S::Playing, ""},
    {S::Playing, "snapshot", true, S::Playing, "snapshot"},
    {S::Playing, "show-progress", true, S::Playing, "showProgress"},
    {S::Playing, "volume +", true, S::Playing, "setVolume 102"},
    {S::Playing, "mute toggle", true, S::Playing, "setMute on"},
    {S::Playing, "loadfile b.mkv append", true, S::Playing, ""},
    {S::Playing, "playlist-next force", true, S::Stopped, "stop"},
    // Paused
    {S::Paused, "play", true, S::Playing, "resume"},
    {S::Paused, "pause", false, S::Paused, ""},
    {S::Paused, "toggle-pause", true, S::Playing, "resume"},
    {S::Paused, "stop", true, S::Stopped, "stop"},
    {S::Paused, "seek 10", true, S::Paused, "seek 10 relative"},
    {S::Paused, "next-stereo-mode", true, S::Paused, "setStereoMode tab"},
    {S::Paused, "stereo-mode anaglyph", true, S::Paused, "setStereoMode anaglyph"},
    {S::Paused, "haptics off", true, S::Paused, "setHapticsEnabled off"},
    {S::Paused, "stiffness +", true, S::Paused, "setStiffness 900"},
    {S::Paused, "recenter", true, S::Paused, "recenter"},
    {S::Paused, "loop on", true, S::Paused, ""},
    {S::Paused, "quit", true, S::Stopped, "stop"},
    {S::Paused, "get state", true, S::Paused, ""},
    {S::Paused, "snapshot", true, S::Paused, "snapshot"},
    {S::Paused, "show-progress", true, S::Paused, "showProgress"},
    {S::Paused, "volume +", true, S::Paused, "setVolume 102"},
    {S::Paused, "mute toggle", true, S::Paused, "setMute on"},
    {S::Paused, "loadfile b.mkv append", true, S::Paused, ""},
    {S::Paused, "playlist-next force", true, S::Stopped, "stop"},
    // Stopped
    {S::Stopped, "play", true, S::Opening, "open movie.mkv"},
    {S::Stopped, "pause", false, S::Stopped, ""},
    {S::Stopped, "toggle-pause", true, S::Opening, "open movie.mkv"},
    {S::Stopped, "stop", true, S::Stopped, ""},
    {S::Stopped, "seek 10", false, S::Stopped, ""},
    {S::Stopped, "next-stereo-mode", true, S::Stopped, "setStereoMode tab"},
    {S::Stopped, "stereo-mode anaglyph", true, S::Stopped, "setStereoMode anaglyph"},
    {S::Stopped, "haptics off", true, S::Stopped, "setHapticsEnabled off"},
    {S::Stopped, "stiffness +", true, S::Stopped, "setStiffness 900"},
    {S::Stopped, "recenter", false, S::Stopped, ""},
    {S::Stopped, "loop on", true, S::Stopped, ""},
    {S::Stopped, "quit", true, S::Stopped, ""},
    {S::Stopped, "get state", true, S::Stopped, ""},
    {S::Stopped, "snapshot", false, S::Stopped, ""},
    {S::Stopped, "show-progress", true, S::Stopped, "showProgress"},
    {S::Stopped, "volume +", true, S::Stopped, "setVolume 102"},
    {S::Stopped, "mute toggle", true, S::Stopped, "setMute on"},
    {S::Stopped, "loadfile b.mkv append", true, S::Stopped, ""},
    {S::Stopped, "playlist-next force", false, S::Stopped, ""},
    // Error
    {S::Error, "play", true, S::Opening, "open movie.mkv"},
    {S::Error, "pause", false, S::Error, ""},
    {S::Error, "toggle-pause", true, S::Opening, "open movie.mkv"},
    {S::Error, "stop", true, S::Stopped, "stop"},
    {S::Error, "seek 10", false, S::Error, ""},
    {S::Error, "next-stereo-mode", false, S::Error, ""},
    {S::Error, "stereo-mode anaglyph", false, S::Error, ""},
    {S::Error, "haptics off", false, S::Error, ""},
    {S::Error, "stiffness +", false, S::Error, ""},
    {S::Error, "recenter", false, S::Error, ""},
    {S::Error, "loop on", true, S::Error, ""},
    {S::Error, "quit", true, S::Error, ""},
    {S::Error, "get state", true, S::Error, ""},
    {S::Error, "snapshot", false, S::Error, ""},
    {S::Error, "show-progress", true, S::Error, "showProgress"},
    {S::Error, "volume +", true, S::Error, "setVolume 102"},
    {S::Error, "mute toggle", true, S::Error, "setMute on"},
    {S::Error, "loadfile b.mkv append", true, S::Error, ""},
    {S::Error, "playlist-next force", false, S::Error, ""},
};

std::string rowName(const Row &r)
{
    return std::string(playerStateName(r.from)) + " + '" + r.command + "'";
}

TEST(StateMachineTest, specificationCoversEveryCommandInEveryState)
{
    std::set<std::pair<int, int>> covered;
    for (const Row &r : kRows) {
        const ParsedCommand p = parseCommandText(r.command);
        ASSERT_TRUE(p) << r.command << ": " << p.error;
        covered.insert({static_cast<int>(r.from), static_cast<int>(p.command->id)});
    }
    EXPECT_EQ(covered.size(), kPlayerStateCount * commandTable().size());
    EXPECT_EQ(kRows.size(), covered.size()) << "a (state, command) pair is listed twice";
}

TEST(StateMachineTest, everyCommandInEveryStateFollowsTheSpecification)
{
    for (const Row &r : kRows) {
        SCOPED_TRACE(rowName(r));
        // GIVEN a machine in the row's state
        Rig rig(r.from);
        auto &[fake, m, listener] = rig;
        const SettingsSnapshot before(m);
        EXPECT_EQ(m.isValid(parseCommandText(r.command).command->id), r.accepted);

        // WHEN the command is executed
        const CommandOutcome out = m.execute(r.command);

        // THEN it is accepted or refused as specified, with the specified effect
        EXPECT_EQ(out.accepted, r.accepted) << out.reason;
        EXPECT_EQ(m.state(), r.to);
        if (std::string(r.call).empty()) {
            EXPECT_TRUE(fake.calls.empty()) << fake.calls.front();
        } else {
            EXPECT_EQ(fake.calls, std::vector<std::string>{r.call});
        }
        if (!r.accepted) {
            EXPECT_FALSE(out.reason.empty());
            EXPECT_TRUE(listener.events.empty()) << "a refused command emitted an event";
            before.expectUnchanged(m, true);
            EXPECT_FALSE(m.quitRequested());
        } else {
            EXPECT_TRUE(out.reason.empty());
        }
        if (r.to != r.from) {
            ASSERT_FALSE(listener.events.empty());
            bool sawState = false;
            for (const PlayerEvent &e : listener.events)
                sawState |= e.kind == PlayerEventKind::StateChanged && e.state == r.to;
            EXPECT_TRUE(sawState);
        }
    }
}

} // namespace
} // namespace depthtouch::player
