// Command table and parsing from text and JSON; remote key bindings.
#include "depthtouch/player/command.h"

#include <set>
#include <string>
#include <string_view>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "depthtouch/player/key_bindings.h"
#include "app/player/fake_player_actions.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::player {
namespace {

using nlohmann::json;

TEST(CommandTableTest, oneRowPerCommandWithUniqueNames)
{
    std::set<std::string> names;
    for (std::size_t i = 0; i < commandTable().size(); ++i) {
        const CommandSpec &spec = commandTable()[i];
        EXPECT_EQ(static_cast<std::size_t>(spec.id), i);
        EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
        EXPECT_NE(spec.validIn, 0) << spec.name;
        EXPECT_EQ(findCommand(spec.name), &spec);
        EXPECT_EQ(&commandSpec(spec.id), &spec);
    }
    EXPECT_EQ(findCommand("warp"), nullptr);
    // Only continuous commands may auto-repeat.
    EXPECT_TRUE(commandSpec(CommandId::Seek).autoRepeat);
    EXPECT_TRUE(commandSpec(CommandId::Stiffness).autoRepeat);
    EXPECT_FALSE(commandSpec(CommandId::TogglePause).autoRepeat);
    EXPECT_FALSE(commandSpec(CommandId::Haptics).autoRepeat);
    EXPECT_FALSE(commandSpec(CommandId::NextStereoMode).autoRepeat);
}

/// The command that \a parsed holds of \a text; a refusal is a test failure (with its reason) and
/// gives a default Command.
Command commandOf(const ParsedCommand &parsed, std::string_view text)
{
    EXPECT_TRUE(parsed) << text << ": " << parsed.error;
    return parsed ? *parsed.command : Command{};
}

/// The command parseCommandText() reads in \a text (commandOf()).
Command fromText(std::string_view text)
{
    return commandOf(parseCommandText(text), text);
}

/// The command parseCommandJson() reads in the JSON \a text (commandOf()).
Command fromJson(std::string_view text)
{
    return commandOf(parseCommandJson(json::parse(text)), text);
}

TEST(CommandParseTest, textCommands)
{
    const Command seek = fromText("  seek   -12.5 ");
    EXPECT_EQ(seek.id, CommandId::Seek);
    EXPECT_EQ(seek.seconds, -12.5);
    EXPECT_EQ(seek.seekMode, SeekMode::Relative);

    const Command absolute = fromText("seek +30 absolute");
    EXPECT_EQ(absolute.seconds, 30.0);
    EXPECT_EQ(absolute.seekMode, SeekMode::Absolute);

    EXPECT_EQ(fromText("play \"my clip.mkv\"").url, "my clip.mkv");
    EXPECT_EQ(fromText("haptics OFF").toggle, Switch::Off);

    const Command stiffness = fromText("stiffness 1200");
    EXPECT_EQ(stiffness.stiffnessChange, StiffnessChange::Set);
    EXPECT_EQ(stiffness.stiffness, 1200.0);

    EXPECT_EQ(fromText("stereo-mode Anaglyph").stereoMode, StereoMode::Anaglyph);
    EXPECT_EQ(fromText("get stereo-mode").property, Property::StereoMode);
}

TEST(CommandParseTest, badTextIsRejectedWithAReason)
{
    const std::pair<const char *, const char *> cases[] = {
        {"", "empty command"},
        {"   ", "empty command"},
        {"warp 9", "unknown command 'warp'"},
        {"pause now", "pause: takes no arguments"},
        {"seek", "seek: needs SECONDS [relative|absolute]"},
        {"seek nan", "seek: 'nan' is not a number of seconds"},
        {"seek inf", "seek: 'inf' is not a number of seconds"},
        {"seek 10s", "seek: '10s' is not a number of seconds"},
        {"seek 1e9", "seek: seconds out of range"},
        {"seek -3 absolute", "seek: an absolute position cannot be negative"},
        {"seek 3 sideways", "seek: 'sideways' is neither relative nor absolute"},
        {"haptics maybe", "haptics: 'maybe' is not on, off or toggle"},
        // Any number parses: the state machine refuses one outside options::kStiffness.
        {"stiffness soft", "stiffness: 'soft' is not +, - or a stiffness in N/m"},
        {"stiffness nan", "stiffness: 'nan' is not +, - or a stiffness in N/m"},
        {"stiffness", "stiffness: needs +, - or a value in N/m"},
        {"stereo-mode 4d", "stereo-mode: unknown stereo mode '4d' (sbs, tab, anaglyph, mono, "
                           "interleaved)"},
        {"get colour",
         "get: unknown property 'colour' (state, stereo-mode, haptics, stiffness, "
         "loop, url, error, time-pos, duration, percent-pos, pause, path, "
         "idle-active, eof-reached, volume, mute, haptic-force, contact, "
         "filename, media-title, playback-time, haptic-device-connected, remote-connected, "
         "playlist-count, playlist-pos, playlist-pos-1, time-remaining)"},
        {"play 'open", "unterminated quote"},
        {"play a b", "play: takes at most one argument (a file or URL)"},
    };
    for (const auto &[text, error] : cases) {
        const ParsedCommand p = parseCommandText(text);
        EXPECT_FALSE(p) << text;
        EXPECT_EQ(p.error, error) << text;
    }
}

TEST(CommandParseTest, errorMessagesStayPrintable)
{
    const ParsedCommand p = parseCommandText(std::string("seek \x01\xff", 7));
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error, "seek: '?"
                       "?' is not a number of seconds");
}

TEST(CommandParseTest, jsonArrays)
{
    EXPECT_EQ(fromJson(R"(["seek", 10])").seconds, 10.0);
    EXPECT_EQ(fromJson(R"(["seek", -2.25, "relative"])").seconds, -2.25);
    EXPECT_EQ(fromJson(R"(["haptics", false])").toggle, Switch::Off);
    EXPECT_EQ(fromJson(R"(["stiffness", "+"])").stiffnessChange, StiffnessChange::Up);
    EXPECT_EQ(fromJson(R"(["toggle-pause"])").id, CommandId::TogglePause);
}

TEST(CommandParseTest, badJsonIsRejectedWithAReason)
{
    const std::pair<const char *, const char *> cases[] = {
        {R"([])", "command must be a non-empty array, e.g. [\"seek\", 10]"},
        {R"("pause")", "command must be a non-empty array, e.g. [\"seek\", 10]"},
        {R"([10])", "the command name must be a string"},
        {R"(["seek", {"s": 1}])", "argument 1 must be a string, a number or a boolean"},
        {R"(["seek", null])", "argument 1 must be a string, a number or a boolean"},
        {R"(["seek", [1]])", "argument 1 must be a string, a number or a boolean"},
        {R"(["fly"])", "unknown command 'fly'"},
        {R"(["seek", "ten"])", "seek: 'ten' is not a number of seconds"},
    };
    for (const auto &[text, error] : cases) {
        const ParsedCommand p = parseCommandJson(json::parse(text));
        EXPECT_FALSE(p) << text;
        EXPECT_EQ(p.error, error) << text;
    }
}

TEST(CommandParseTest, canonicalTextParsesBack)
{
    for (const char *text :
         {"play x.mkv", "seek -10 relative", "seek 5 absolute", "stereo-mode tab", "haptics off",
          "loop on", "stiffness +", "stiffness -", "stiffness 900", "get url", "quit"}) {
        const ParsedCommand p = parseCommandText(text);
        ASSERT_TRUE(p) << text;
        EXPECT_EQ(commandText(*p.command), text);
    }
}

TEST(StereoModeTest, namesRoundTripAndCycle)
{
    StereoMode m = StereoMode::SideBySide;
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(stereoModeFromName(stereoModeName(m)), m);
        m = nextStereoMode(m);
    }
    EXPECT_EQ(m, StereoMode::SideBySide);
    EXPECT_EQ(stereoModeFromName("side-by-side"), StereoMode::SideBySide);
    EXPECT_EQ(stereoModeFromName("3d"), std::nullopt);
    // FFmpeg stereo3d's names of the same packings, left eye first (docs/playing.md)
    EXPECT_EQ(stereoModeFromName("sbsl"), StereoMode::SideBySide);
    EXPECT_EQ(stereoModeFromName("SBS2L"), StereoMode::SideBySide);
    EXPECT_EQ(stereoModeFromName("abl"), StereoMode::TopAndBottom);
    EXPECT_EQ(stereoModeFromName("tb2l"), StereoMode::TopAndBottom);
    EXPECT_EQ(stereoModeFromName("arcc"), StereoMode::Anaglyph);
    EXPECT_EQ(stereoModeFromName("irl"), StereoMode::Interleaved);
    // right-eye-first packings and the other anaglyphs are not drawn: refused, not mistaken
    EXPECT_EQ(stereoModeFromName("sbsr"), std::nullopt);
    EXPECT_EQ(stereoModeFromName("irr"), std::nullopt);
    EXPECT_EQ(stereoModeFromName("arcg"), std::nullopt);
}

hal::KeyEvent key(hal::Key k, hal::KeyAction a)
{
    return {k, a, platform::TimePoint{}};
}

TEST(KeyBindingsTest, everyBindingParses)
{
    std::set<hal::Key> keys;
    for (const KeyBinding &b : defaultKeyBindings()) {
        EXPECT_TRUE(parseCommandText(b.command)) << b.command;
        EXPECT_TRUE(keys.insert(b.key).second) << hal::keyName(b.key) << " bound twice";
    }
}

TEST(KeyBindingsTest, pressSendsRepeatOnlyWhereItMakesSense)
{
    using A = hal::KeyAction;
    const KeyMap defaults;
    const auto commandForKey = [&defaults](const hal::KeyEvent &e) {
        return defaults.commandFor(e);
    };
    auto c = commandForKey(key(hal::Key::PlayPause, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::TogglePause);
    EXPECT_FALSE(commandForKey(key(hal::Key::PlayPause, A::Repeat))) << "a held toggle repeats";
    EXPECT_FALSE(commandForKey(key(hal::Key::PlayPause, A::Release)));

    c = commandForKey(key(hal::Key::FastForward, A::Repeat));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Seek);
    EXPECT_EQ(c->seconds, 10.0);
    c = commandForKey(key(hal::Key::Left, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->seconds, -10.0);
    c = commandForKey(key(hal::Key::ChannelDown, A::Repeat));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Stiffness);
    EXPECT_EQ(c->stiffnessChange, StiffnessChange::Down);
    EXPECT_FALSE(commandForKey(key(hal::Key::Ok, A::Repeat)));

    EXPECT_FALSE(commandForKey(key(hal::Key::Mode3d, A::Repeat)));
    c = commandForKey(key(hal::Key::Mode3d, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::NextStereoMode);
    c = commandForKey(key(hal::Key::Exit, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Quit);
    EXPECT_FALSE(commandForKey(key(hal::Key::Digit7, A::Press))) << "unbound key";
}

// The defaults follow Kodi's full-screen video keymap (system/keymaps/remote.xml, FullscreenVideo
// and global) wherever Kodi's action is one of ours; the table below is that file's, written down
// here key by key, not read from the bindings.
TEST(KeyBindingsTest, theDefaultsFollowKodisFullScreenVideoKeys)
{
    using A = hal::KeyAction;
    struct Kodi {
        hal::Key key;
        const char *kodiAction;
        CommandId id;
        double seconds; // for seeks: the sign says the direction, the size small or big step
    };
    const Kodi kodi[] = {
        {hal::Key::PlayPause, "PlayPause", CommandId::TogglePause, 0.0},
        {hal::Key::Play, "PlayPause", CommandId::TogglePause, 0.0},
        {hal::Key::Pause, "Pause", CommandId::Pause, 0.0},
        {hal::Key::Stop, "Stop", CommandId::Stop, 0.0},
        {hal::Key::FastForward, "FastForward", CommandId::Seek, 10.0},
        {hal::Key::Rewind, "Rewind", CommandId::Seek, -10.0},
        {hal::Key::Right, "StepForward", CommandId::Seek, 10.0},
        {hal::Key::Left, "StepBack", CommandId::Seek, -10.0},
        {hal::Key::Up, "ChapterOrBigStepForward", CommandId::Seek, 60.0},
        {hal::Key::Down, "ChapterOrBigStepBack", CommandId::Seek, -60.0},
        {hal::Key::Ok, "OSD", CommandId::ShowProgress, 0.0},
        {hal::Key::Menu, "OSD", CommandId::ShowProgress, 0.0},
        {hal::Key::Info, "Info", CommandId::ShowProgress, 0.0},
        {hal::Key::Back, "Back", CommandId::Quit, 0.0},
        {hal::Key::Power, "ShutDown()", CommandId::Quit, 0.0},
        {hal::Key::VolumeUp, "VolumeUp", CommandId::Volume, 0.0},
        {hal::Key::VolumeDown, "VolumeDown", CommandId::Volume, 0.0},
        {hal::Key::Mute, "Mute", CommandId::Mute, 0.0},
    };
    const KeyMap defaults;
    for (const Kodi &k : kodi) {
        const auto c = defaults.commandFor(key(k.key, A::Press));
        ASSERT_TRUE(c) << hal::keyName(k.key) << " (Kodi: " << k.kodiAction << ") is unbound";
        EXPECT_EQ(c->id, k.id) << hal::keyName(k.key) << " (Kodi: " << k.kodiAction << ")";
        if (k.id == CommandId::Seek) {
            EXPECT_EQ(c->seconds, k.seconds) << hal::keyName(k.key);
            EXPECT_EQ(c->seekMode, SeekMode::Relative) << hal::keyName(k.key);
        }
    }
    // The volume keys step the volume as mpv's (`add volume ±2`) and MUTE toggles, as Kodi's
    EXPECT_STREQ(defaults.commandText(hal::Key::VolumeUp), "volume +");
    EXPECT_STREQ(defaults.commandText(hal::Key::VolumeDown), "volume -");
    EXPECT_STREQ(defaults.commandText(hal::Key::Mute), "mute toggle");
}

// A key map in mpv's input.conf form rebinds the defaults line by line: comments and blank lines
// are skipped, mpv's and the kernel's key names both read, a later line wins, `ignore` unbinds,
// a new key is bound; a wrong line names its number and changes nothing.
TEST(KeyBindingsTest, aKeyMapRebindsTheDefaultsAsMpvsInputConf)
{
    using A = hal::KeyAction;
    KeyMap keys;
    EXPECT_STREQ(keys.commandText(hal::Key::Up), "seek 60"); // the defaults
    EXPECT_EQ(keys.commandText(hal::Key::Blue), nullptr);
    const std::string conf = "# a remote's key map\n"
                             "\n"
                             "UP        seek 600  # Kodi's big step\n"
                             "KEY_DOWN  seek -600\n"
                             "volume_up stiffness +\n"
                             "BLUE      haptics toggle\n"
                             "BLUE      recenter\n" // a later line wins
                             "EXIT      ignore\n";
    ASSERT_EQ(keys.apply(conf), "");
    auto c = keys.commandFor(key(hal::Key::Up, A::Repeat)); // seek repeats
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Seek);
    EXPECT_EQ(c->seconds, 600.0);
    c = keys.commandFor(key(hal::Key::Down, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->seconds, -600.0);
    c = keys.commandFor(key(hal::Key::VolumeUp, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Stiffness);
    EXPECT_EQ(c->stiffnessChange, StiffnessChange::Up);
    c = keys.commandFor(key(hal::Key::Blue, A::Press));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Recenter);
    EXPECT_FALSE(keys.commandFor(key(hal::Key::Exit, A::Press))) << "ignore unbinds";
    c = keys.commandFor(key(hal::Key::Power, A::Press)); // untouched defaults stay
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, CommandId::Quit);

    const std::pair<std::string, std::string> wrong[] = {
        {"UP seek 5\nFROBNICATE quit\n", "line 2: unknown key 'FROBNICATE'"},
        {"UP\n", "line 1: no command for UP"},
        {"UP seek\n", "line 1: "},
        {"UP jump 5\n", "line 1: "},
        {std::string(300, 'x') + "\n", "line 1: longer than 256 bytes"},
    };
    for (const auto &[text, want] : wrong) {
        KeyMap k;
        const std::string err = k.apply(text);
        EXPECT_EQ(err.rfind(want, 0), 0u) << text << " -> " << err;
        EXPECT_STREQ(k.commandText(hal::Key::Up), "seek 60") << "a wrong file changed a key";
    }
    std::string many;
    for (int i = 0; i < 1001; ++i)
        many += "# a comment\n";
    EXPECT_EQ(KeyMap().apply(many), "line 1001: more than 1000 lines");
}

// mpv's commands (issue 61): loadfile, cycle and add are rows of the one table, parsed into the
// command they mean; a wrong one says why.
TEST(CommandParseTest, mpvsLoadfileCycleAndAddAreTheTablesCommands)
{
    ParsedCommand p = parseCommandText("loadfile clip.mkv replace");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->id, CommandId::LoadFile);
    EXPECT_EQ(p.command->loadMode, LoadMode::Replace);
    EXPECT_EQ(p.command->url, "clip.mkv");
    p = parseCommandText("loadfile b.mkv append");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->loadMode, LoadMode::Append);
    p = parseCommandText("loadfile b.mkv append-play");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(commandText(*p.command), "loadfile b.mkv append-play");
    p = parseCommandText("playlist-prev force");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->id, CommandId::PlaylistNext);
    EXPECT_EQ(p.command->step, -1);
    EXPECT_TRUE(p.command->force);
    p = parseCommandJson(json::array({"seek", 10, "absolute", "exact"})); // node-mpv's seek
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(commandText(*p.command), "seek 10 absolute");
    p = parseCommandJson(json::array({"loadfile", "http://box/a.mkv"}));
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->url, "http://box/a.mkv");
    p = parseCommandText("cycle pause");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->id, CommandId::TogglePause);
    p = parseCommandText("cycle loop-file");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->id, CommandId::Loop);
    EXPECT_EQ(p.command->toggle, Switch::Toggle);
    p = parseCommandText("add volume -2");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(p.command->id, CommandId::Volume);
    EXPECT_EQ(p.command->volumeChange, StiffnessChange::By);
    EXPECT_EQ(p.command->volume, -2.0);
    p = parseCommandText("add playback-time 5");
    ASSERT_TRUE(p) << p.error;
    EXPECT_EQ(commandText(*p.command), "seek 5 relative");
    const std::pair<const char *, const char *> wrong[] = {
        {"loadfile", "loadfile: needs a file or URL and at most one of replace, append, "
                     "append-play"},
        {"loadfile a.mkv insert-next", "loadfile: 'insert-next' is not replace, append or "
                                       "append-play"},
        {"playlist-next later", "playlist-next: takes at most weak or force"},
        {"cycle duration",
         "cycle: 'duration' cannot be cycled (pause, haptics, loop, mute, stereo-mode)"},
        {"add volume x", "add: 'x' is not a number"},
        {"add pause 1",
         "add: 'pause' cannot be added to (time-pos, playback-time, stiffness, volume)"},
        {"cycle colour",
         "cycle: unknown property 'colour' (state, stereo-mode, haptics, "
         "stiffness, loop, url, error, time-pos, duration, percent-pos, pause, "
         "path, idle-active, eof-reached, volume, mute, haptic-force, contact, "
         "filename, media-title, playback-time, haptic-device-connected, remote-connected, "
         "playlist-count, playlist-pos, playlist-pos-1, time-remaining)"},
    };
    for (const auto &[text, error] : wrong)
        EXPECT_EQ(parseCommandText(text).error, error) << text;
}

// The key names of docs/devices.md and mpv's input.conf (issue 61): the kernel's names that the
// evdev backend folds into a key, mpv's names, the terminal's characters; mpv's commands bound
// to them run on the machine.
TEST(KeyBindingsTest, anInputConfTakesMpvsAndTheKernelsKeyNamesAndMpvsCommands)
{
    using hal::Key;
    const std::pair<const char *, Key> names[] = {
        {"KEY_ESC", Key::Exit},
        {"ESC", Key::Exit},
        {"KEY_SELECT", Key::Ok},
        {"KEY_PAGEUP", Key::ChannelUp},
        {"PGUP", Key::ChannelUp},
        {"KEY_PAGEDOWN", Key::ChannelDown},
        {"PGDWN", Key::ChannelDown},
        {"KEY_MODE", Key::Mode3d},
        {"SPACE", Key::PlayPause},
        {"KEY_SPACE", Key::PlayPause},
        {"m", Key::Mute},
        {"q", Key::Exit},
        {"p", Key::PlayPause},
        {"+", Key::ChannelUp},
        {"ENTER", Key::Enter},
        {"KP_ENTER", Key::Enter},
        {"3", Key::Digit3},
        {"VOLUME_UP", Key::VolumeUp},
        {"NOT_A_KEY", Key::Unknown},
        {"", Key::Unknown},
        {"xy", Key::Unknown},
    };
    for (const auto &[name, want] : names)
        EXPECT_EQ(keyFromInputName(name), want) << name;

    KeyMap keys;
    ASSERT_EQ(keys.apply("KEY_ESC    quit\n"
                         "KEY_SELECT cycle pause\n"
                         "KEY_PAGEUP add volume -2\n"
                         "PGDWN      add stiffness 50\n"
                         "KEY_MODE   cycle stereo-mode\n"
                         "SPACE      cycle pause\n"
                         "m          cycle mute\n"),
              "");
    EXPECT_STREQ(keys.commandText(Key::Ok), "cycle pause");
    test::FakePlayerActions fake;
    PlayerSettings settings;
    settings.url = "movie.mkv";
    StateMachine m(fake, settings);
    ASSERT_TRUE(m.execute("play").accepted);
    ASSERT_TRUE(m.onOpened());
    const auto press = [&](Key k) {
        const std::optional<Command> c = keys.commandFor(key(k, hal::KeyAction::Press));
        return c && m.execute(*c).accepted;
    };
    EXPECT_TRUE(press(Key::Ok));
    EXPECT_EQ(m.state(), PlayerState::Paused);
    EXPECT_TRUE(press(Key::PlayPause));
    EXPECT_EQ(m.state(), PlayerState::Playing);
    EXPECT_TRUE(press(Key::ChannelUp));
    EXPECT_EQ(m.volume(), 98.0);
    EXPECT_TRUE(keys.commandFor(key(Key::ChannelUp, hal::KeyAction::Repeat))) << "volume repeats";
    EXPECT_TRUE(press(Key::ChannelDown));
    EXPECT_EQ(m.stiffness(), 850.0);
    EXPECT_TRUE(press(Key::Mode3d));
    EXPECT_EQ(m.stereoMode(), StereoMode::TopAndBottom);
    EXPECT_TRUE(press(Key::Mute));
    EXPECT_TRUE(m.muted());
    EXPECT_TRUE(press(Key::Exit));
    EXPECT_TRUE(m.quitRequested());

    EXPECT_EQ(KeyMap().apply("KEY_FOO quit\n"), "line 1: unknown key 'KEY_FOO'");
    EXPECT_EQ(KeyMap().apply("m cycle duration\n"),
              "line 1: cycle: 'duration' cannot be cycled (pause, haptics, loop, mute, "
              "stereo-mode)");
}

} // namespace
} // namespace depthtouch::player
