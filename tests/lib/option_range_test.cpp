/// \file
/// \brief One range per option (issue 62): each row of depthtouch/options/option_range.h is the
/// range every entry point of its option checks: `play --NAME`, a play.toml key,
/// dt_set_option_string() and dt_set_property_double() before dt_initialize() refuse a value
/// outside it; the state machine's `NAME N`, the control socket's set_property and
/// dt_set_property_double() on a running player refuse it; mpv's `add` and the remote's steps
/// clamp at its ends; the renderer's and the haptic task's own checks take its bounds. Each is
/// probed at min, max, just outside each end and NaN, so an entry point with a bound of its own
/// (wider, narrower, or clamping where the others refuse) fails here.

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/player/fake_player_actions.h"
#include "command_line.h"
#include "depthtouch/client.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/haptic_task/haptic_controls.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/options/option_range.h"
#include "depthtouch/player/state_machine.h"
#include "option_cli.h"
#include "play_config.h"
#include "play_options.h"

namespace depthtouch {
namespace {

using options::OptionRange;

/// A probe of a row: the value, its text, and whether the row takes it.
struct Probe {
    double value;
    std::string text; ///< "%.17g", or "nan"
    bool inRange;
};

std::string textOf(double v)
{
    if (std::isnan(v))
        return "nan";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// min, max, a millionth of the span beyond each end, and NaN.
std::vector<Probe> probesOf(const OptionRange &r)
{
    const double d = (r.max - r.min) * 1e-6;
    std::vector<Probe> out;
    for (double v : {r.min, r.max, r.min - d, r.max + d, std::nan("")})
        out.push_back({v, textOf(v), r.contains(v)});
    return out;
}

/// The rows that more than one entry point sets.
const OptionRange *const kRows[] = {&options::kStiffness, &options::kVolume, &options::kServoRate};
/// Those that are also properties of a running player (set_property, add).
const OptionRange *const kProperties[] = {&options::kStiffness, &options::kVolume};

/// \return the message of `play x.mkv --NAME TEXT` (parse or check), "" when taken.
std::string commandLineRefusal(const OptionRange &r, const std::string &text)
{
    cli::PlayOptions opt;
    cli::CommandLine line{"play"};
    cli::addOptions(line.root(), cli::playOptionTable(), opt);
    const std::string refused = line.parse({"x.mkv", "--" + std::string(r.name), text});
    return !refused.empty() ? refused : cli::checkPlayOptionValues(opt);
}

/// \return the message of a play.toml with `NAME = TEXT` (load or check), "" when taken.
std::string configRefusal(const OptionRange &r, const std::string &text)
{
    cli::PlayOptions opt;
    opt.url = "x.mkv";
    const std::string err = cli::applyPlayConfigText(
        std::string(r.name) + " = " + text + "\n", "p.toml",
        [](const std::string &) { return false; }, opt);
    return !err.empty() ? err : cli::checkPlayOptionValues(opt);
}

TEST(OptionRangeTest, theRowsAreWellFormed)
{
    for (const OptionRange *r : kRows) {
        EXPECT_LT(r->min, r->max) << r->name;
        EXPECT_FALSE(r->unit.empty()) << r->name;
        EXPECT_TRUE(r->contains(r->min) && r->contains(r->max)) << r->name;
        EXPECT_FALSE(r->contains(std::nan(""))) << r->name;
    }
}

TEST(OptionRangeTest, theCommandLineAndConfigFilesRefuseWhatTheRowRefuses)
{
    for (const OptionRange *r : kRows)
        for (const Probe &p : probesOf(*r)) {
            const std::string cli = commandLineRefusal(*r, p.text);
            EXPECT_EQ(cli.empty(), p.inRange) << "--" << r->name << " " << p.text << ": " << cli;
            const std::string toml = configRefusal(*r, p.text);
            EXPECT_EQ(toml.empty(), p.inRange) << r->name << " = " << p.text << ": " << toml;
        }
    // The message says the row's range.
    EXPECT_EQ(commandLineRefusal(options::kStiffness, "3001"),
              "--stiffness must be in [100, 3000] N/m");
}

TEST(OptionRangeTest, theLibrarysOptionsRefuseWhatTheRowRefuses)
{
    for (const OptionRange *r : kRows) {
        const std::string name(r->name);
        for (const Probe &p : probesOf(*r)) {
            dt_handle *h = dt_create();
            ASSERT_NE(h, nullptr);
            const int want = p.inRange ? DT_ERROR_SUCCESS : DT_ERROR_OPTION_FORMAT;
            EXPECT_EQ(dt_set_option_string(h, name.c_str(), p.text.c_str()), want)
                << name << " " << p.text;
            // Before dt_initialize() a property that is an option sets the option (NaN is no
            // number at all: an invalid parameter).
            const int wantDouble = std::isnan(p.value) ? DT_ERROR_INVALID_PARAMETER : want;
            EXPECT_EQ(dt_set_property_double(h, name.c_str(), p.value), wantDouble)
                << name << " " << p.text;
            dt_terminate_destroy(h);
        }
    }
}

/// A state machine over a recording pipeline, its value of \a r half way up its range.
struct Machine {
    player::test::FakePlayerActions fake;
    player::StateMachine m;
    explicit Machine(const OptionRange &r) : m(fake, settingsFor(r)) {}

    static player::PlayerSettings settingsFor(const OptionRange &r)
    {
        player::PlayerSettings s;
        s.url = "movie.mkv";
        (r.name == "stiffness" ? s.stiffness : s.volume) = (r.min + r.max) / 2;
        return s;
    }

    double valueOf(const OptionRange &r) const
    {
        return r.name == "stiffness" ? m.stiffness() : m.volume();
    }
};

TEST(OptionRangeTest, commandsAndSetPropertyRefuseWhatTheRowRefuses)
{
    for (const OptionRange *r : kProperties) {
        const std::string name(r->name);
        for (const Probe &p : probesOf(*r)) {
            Machine a(*r);
            const player::CommandOutcome out = a.m.execute(name + " " + p.text);
            EXPECT_EQ(out.accepted, p.inRange) << name << " " << p.text << ": " << out.reason;
            EXPECT_EQ(a.valueOf(*r), p.inRange ? p.value : (r->min + r->max) / 2) << p.text;

            Machine b(*r);
            nlohmann::json request = {{"command", {"set_property_string", name, p.text}}};
            if (!std::isnan(p.value)) // JSON has no NaN: that one is mpv's format error
                request = {{"command", {"set_property", name, p.value}}};
            const nlohmann::json reply =
                nlohmann::json::parse(control::handleControlLine(request.dump(), b.m));
            EXPECT_EQ(reply.at("error") == "success", p.inRange) << request.dump() << reply;
            EXPECT_EQ(b.valueOf(*r), p.inRange ? p.value : (r->min + r->max) / 2) << p.text;
        }
    }
    Machine a(options::kStiffness);
    EXPECT_EQ(a.m.execute("stiffness 3001").reason,
              "stiffness 3001 N/m is outside 100 N/m .. 3000 N/m");
}

TEST(OptionRangeTest, addAndTheRemotesStepsClampAtTheRowsEnds)
{
    for (const OptionRange *r : kProperties) {
        const std::string name(r->name);
        const double span = r->max - r->min;
        Machine m(*r);
        // mpv's add clamps: far past either end lands on it, and stays there.
        for (const double by : {span * 10, span * 1e-6, -span * 10, -span * 1e-6}) {
            const std::string add = "add " + name + " " + textOf(by);
            EXPECT_TRUE(m.m.execute(add).accepted) << add;
            EXPECT_EQ(m.valueOf(*r), by > 0 ? r->max : r->min) << add;
        }
        // One step short of an end, two steps land on it and go no further.
        for (const char *dir : {"+", "-"}) {
            const bool up = dir[0] == '+';
            ASSERT_TRUE(
                m.m.execute(name + " " + textOf(up ? r->max - r->step / 2 : r->min + r->step / 2))
                    .accepted);
            (void)m.m.execute(name + " " + dir);
            (void)m.m.execute(name + " " + dir);
            EXPECT_EQ(m.valueOf(*r), up ? r->max : r->min) << name << " " << dir;
        }
    }
}

TEST(OptionRangeTest, aRunningPlayersPropertiesRefuseWhatTheRowRefuses)
{
    dt_handle *h = dt_create();
    for (const char *name : {"display", "haptic", "source", "decoder"})
        ASSERT_EQ(dt_set_option_string(h, name, "mock"), 0) << name;
    ASSERT_EQ(dt_set_option_string(h, "no-audio", ""), 0);
    ASSERT_EQ(dt_initialize(h), 0);
    for (const OptionRange *r : kProperties) {
        const std::string name(r->name);
        for (const Probe &p : probesOf(*r)) {
            const int want = std::isnan(p.value) ? DT_ERROR_INVALID_PARAMETER
                             : p.inRange         ? DT_ERROR_SUCCESS
                                                 : DT_ERROR_PROPERTY_ERROR;
            EXPECT_EQ(dt_set_property_double(h, name.c_str(), p.value), want)
                << name << " " << p.text;
        }
        const std::string past = textOf(r->max - r->min);
        const char *add[] = {"add", name.c_str(), past.c_str(), nullptr};
        EXPECT_EQ(dt_command(h, add), 0) << name;
        double v = 0.0;
        EXPECT_EQ(dt_get_property_double(h, name.c_str(), &v), 0);
        EXPECT_EQ(v, r->max) << "add " << name << " clamps at the end";
    }
    dt_terminate_destroy(h);
}

TEST(OptionRangeTest, theSafetyNetsBelowTakeTheRowsBounds)
{
    for (const Probe &p : probesOf(options::kStiffness)) {
        haptics::RendererConfig c;
        c.stiffness = p.value;
        EXPECT_EQ(c.validate().has_value(), p.inRange) << p.text;
        haptic_task::HapticControls controls(true, 800.0);
        controls.setStiffness(p.value); // ignores a value outside
        EXPECT_EQ(controls.stiffness(), p.inRange ? p.value : 800.0) << p.text;
    }
    for (const Probe &p : probesOf(options::kServoRate)) {
        haptic_task::HapticTaskConfig c;
        c.servoRateHz = p.value;
        EXPECT_EQ(c.validate().has_value(), p.inRange) << p.text;
    }
}

} // namespace
} // namespace depthtouch
