#pragma once
// The player state machine's test rig, shared by state_machine_test.cpp and
// state_machine_spec_test.cpp: settings, a machine driven into each state on a fake, and the
// settings a refused command must leave as they were.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/player/fake_player_actions.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::player::test {

using S = PlayerState;

inline constexpr const char *kUrl = "movie.mkv";

inline PlayerSettings defaultSettings()
{
    PlayerSettings s;
    s.url = kUrl;
    s.stiffness = 800.0;
    return s;
}

/// The default settings with the initial \a stiffness.
inline PlayerSettings stiffnessSettings(double stiffness)
{
    PlayerSettings s = defaultSettings();
    s.stiffness = stiffness;
    return s;
}

/// The default settings with looping on (--loop).
inline PlayerSettings loopSettings()
{
    PlayerSettings s = defaultSettings();
    s.loop = true;
    return s;
}

/// The default settings of a player that stays up and waits for the next sender of a silent
/// stream (--idle).
inline PlayerSettings reopenSettings()
{
    PlayerSettings s = defaultSettings();
    s.reopenWhenSilent = true;
    return s;
}

/// Drives \a m (on \a fake) into \a target through the public API, then clears the record.
inline void reach(StateMachine &m, FakePlayerActions &fake, PlayerState target)
{
    switch (target) {
    case S::Idle:
        break;
    case S::Opening:
        ASSERT_TRUE(m.execute("play").accepted);
        break;
    case S::Playing:
        ASSERT_TRUE(m.execute("play").accepted);
        ASSERT_TRUE(m.onOpened());
        break;
    case S::Paused:
        reach(m, fake, S::Playing);
        ASSERT_TRUE(m.execute("pause").accepted);
        break;
    case S::Stopped:
        reach(m, fake, S::Playing);
        ASSERT_TRUE(m.execute("stop").accepted);
        break;
    case S::Error:
        reach(m, fake, S::Playing);
        ASSERT_TRUE(m.onFailure("decoder lost"));
        break;
    }
    ASSERT_EQ(m.state(), target);
    fake.calls.clear();
}

/// A machine on a fake, driven into a state, with a listener attached from then on.
struct Rig {
    explicit Rig(PlayerState from, const PlayerSettings &settings = defaultSettings())
        : m(fake, settings)
    {
        reach(m, fake, from);
        m.addListener(&listener);
    }
    FakePlayerActions fake;
    StateMachine m;
    RecordingListener listener;
};

/// Expects \a rig's playing machine to take the pipeline's report \a notify (onEndOfStream,
/// onStreamSilent) by stopping, with an "end-file" event that gives \a reason, and a second report
/// to change nothing.
inline void expectStopsOnce(Rig &rig, bool (StateMachine::*notify)(), const std::string &reason)
{
    auto &[fake, m, listener] = rig;
    EXPECT_TRUE((m.*notify)());
    EXPECT_EQ(m.state(), S::Stopped);
    EXPECT_EQ(fake.calls, std::vector<std::string>{"stop"});
    EXPECT_EQ(listener.names(), (std::vector<std::string>{"end-of-stream", "state"}));
    EXPECT_EQ(listener.events.front().message, reason);
    EXPECT_FALSE((m.*notify)());
    EXPECT_EQ(fake.calls.size(), 1u);
}

/// The settings a refused or failed command must leave as they were.
struct SettingsSnapshot {
    explicit SettingsSnapshot(const StateMachine &m)
        : stereoMode(m.stereoMode()), hapticsEnabled(m.hapticsEnabled()), stiffness(m.stiffness()),
          loop(m.loop())
    {
    }
    /// Checks that \a m still has the settings of the snapshot (the loop flag only if \a withLoop).
    void expectUnchanged(const StateMachine &m, bool withLoop) const
    {
        EXPECT_EQ(m.stereoMode(), stereoMode);
        EXPECT_EQ(m.hapticsEnabled(), hapticsEnabled);
        EXPECT_EQ(m.stiffness(), stiffness);
        if (withLoop) {
            EXPECT_EQ(m.loop(), loop);
        }
    }
    StereoMode stereoMode;
    bool hapticsEnabled;
    double stiffness;
    bool loop;
};

} // namespace depthtouch::player::test
