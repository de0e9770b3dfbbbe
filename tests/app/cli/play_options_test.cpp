/// \file
/// \brief `play`'s option table (app/cli/play_options.h) drives the command line, the `--config`
/// TOML file, the checks and `--help` alike: every row set on the command line and in TOML gives
/// the same value, every value out of range gives the same one-line error on both paths, every row
/// lands in the player's config, and `--help` lists every row.

#include "play_options.h"

#include <cstdio>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "command_line.h"
#include "option_cli.h"
#include "depthtouch/options/option_range.h"
#include "play_config.h"

namespace depthtouch::cli {
namespace {

using Row = OptionRow<PlayOptions>;

bool noneGiven(const std::string &)
{
    return false;
}

/// \return \a opt after parsing `play URL` + \a args on a command made of the table, or the
/// CLI11 error text in \a error.
PlayOptions fromCommandLine(const std::vector<std::string> &args, std::string *error = nullptr)
{
    PlayOptions opt;
    CommandLine line{"play"};
    addOptions(line.root(), playOptionTable(), opt);
    std::vector<std::string> argv = {"x.mkv"};
    argv.insert(argv.end(), args.begin(), args.end());
    const std::string refused = line.parse(argv);
    if (error != nullptr && !refused.empty())
        *error = refused;
    return opt;
}

/// \return \a opt after applying `url = ...` less TOML \a text, or the error in \a error.
PlayOptions fromConfig(const std::string &text, std::string *error = nullptr)
{
    PlayOptions opt;
    opt.url = "x.mkv";
    const std::string err = applyPlayConfigText(text, "p.toml", noneGiven, opt);
    if (error != nullptr)
        *error = err;
    return opt;
}

/// A value of a row's type as command-line text and as TOML text (a flag: given / true).
struct Sample {
    std::string cli;
    std::string toml;
};

Sample sampleOf(const Row &row, bool outOfRange)
{
    return std::visit(
        [&](auto field) -> Sample {
            using T = std::remove_cvref_t<decltype(PlayOptions{}.*field)>;
            if constexpr (std::is_same_v<T, bool>) {
                return {"", "true"};
            } else if constexpr (std::is_same_v<T, std::string>) {
                const std::string v = outOfRange ? "nonsense" : "value-1";
                return {v, "\"" + v + "\""};
            } else {
                // In range: a quarter of the way up; out of range: past the upper end.
                const OptionCheck &c = row.check;
                double v = 7.0;
                if (outOfRange)
                    v = c.max + 1.0;
                else if (c.kind == OptionCheck::Kind::Range)
                    v = c.min + (c.max - c.min) / 4;
                char buf[32];
                std::snprintf(buf, sizeof buf, std::is_integral_v<T> ? "%.0f" : "%.1f", v);
                return {buf, buf};
            }
        },
        row.field);
}

/// \return the command-line arguments that give \a row the value \a s.
std::vector<std::string> argsOf(const Row &row, const Sample &s)
{
    std::vector<std::string> args = {"--" + std::string(row.name)};
    if (!s.cli.empty())
        args.push_back(s.cli);
    return args;
}

bool sameField(const Row &row, const PlayOptions &a, const PlayOptions &b)
{
    return std::visit([&](auto field) { return a.*field == b.*field; }, row.field);
}

/// The rows of the config file (all but the url argument and --config).
std::vector<Row> configRows()
{
    std::vector<Row> rows;
    for (const Row &row : playOptionTable())
        if ((row.flags & kCommandLineOnly) == 0)
            rows.push_back(row);
    return rows;
}

TEST(PlayOptionTableTest, EachRowGivesTheSameValueOnTheCommandLineAndInTheConfigFile)
{
    for (const Row &row : configRows()) {
        const Sample s = sampleOf(row, false);
        std::string cliError;
        std::string tomlError;
        const PlayOptions cli = fromCommandLine(argsOf(row, s), &cliError);
        const PlayOptions toml =
            fromConfig(std::string(row.name) + " = " + s.toml + "\n", &tomlError);
        EXPECT_EQ(cliError, "") << row.name;
        EXPECT_EQ(tomlError, "") << row.name;
        EXPECT_TRUE(sameField(row, cli, toml)) << row.name;
        EXPECT_FALSE(sameField(row, cli, PlayOptions{})) << row.name << ": the value was stored";
    }
}

TEST(PlayOptionTableTest, AValueOutOfRangeGivesTheSameErrorOnBothPaths)
{
    int checked = 0;
    for (const Row &row : configRows()) {
        if (row.check.kind == OptionCheck::Kind::None)
            continue;
        const Sample s = sampleOf(row, true);
        const std::string cli = checkPlayOptionValues(fromCommandLine(argsOf(row, s)));
        const std::string toml =
            checkPlayOptionValues(fromConfig(std::string(row.name) + " = " + s.toml + "\n"));
        EXPECT_EQ(cli, checkMessage(row)) << row.name;
        EXPECT_EQ(toml, cli) << row.name;
        EXPECT_EQ(cli.rfind("--" + std::string(row.name) + " must be ", 0), 0u) << cli;
        // A value within the range passes, on both paths.
        const Sample low = sampleOf(row, false);
        if (row.check.kind == OptionCheck::Kind::Range) {
            EXPECT_EQ(checkPlayOptionValues(fromCommandLine(argsOf(row, low))), "") << row.name;
            EXPECT_EQ(
                checkPlayOptionValues(fromConfig(std::string(row.name) + " = " + low.toml + "\n")),
                "")
                << row.name;
        }
        ++checked;
    }
    EXPECT_EQ(checked, 15) << "volume, stereo, stiffness, static-friction, dynamic-friction, "
                              "rate, reengage, method, duration, record-crf, size, osd-seconds, "
                              "lod-target, max-lateness, snapshot-every";
}

TEST(PlayOptionTableTest, TheMessagesOfBadValuesStayAsTheyWere)
{
    const std::pair<std::vector<std::string>, std::string> cases[] = {
        {{"--stereo", "3d"}, "--stereo must be sbs, tab, anaglyph, mono or interleaved"},
        {{"--rate", "50"}, "--rate must be in [100, 10000] Hz"},
        {{"--stiffness", "0"}, "--stiffness must be in [100, 3000] N/m"},
        {{"--stiffness", "3001"}, "--stiffness must be in [100, 3000] N/m"},
        {{"--duration", "-1"}, "--duration must be >= 0 s"},
        {{"--osd-seconds", "1e9"}, "--osd-seconds must be in [0, 86400] s"},
        {{"--lod-target", "5"}, "--lod-target must be in [0, 4] refresh periods"},
        {{"--max-lateness", "-1"}, "--max-lateness must be in [0, 10] seconds"},
        {{"--reengage", "snap"}, "--reengage must be ramp or release"},
        {{"--method", "god-object"},
         "--method must be finger, ball, modified, proxy-graph or mesh-bvh"},
        {{"--size", "8x8"}, "--size must be WxH, 16..8192 pixels each"},
        {{"--record-crf", "52"}, "--record-crf must be in [0, 51]"},
        {{"--static-friction", "-0.1"}, "--static-friction must be in [0, 2]"},
        {{"--dynamic-friction", "3"}, "--dynamic-friction must be in [0, 2]"},
        {{"--snapshot-every", "-1"}, "--snapshot-every must be in [0, 1000000]"},
        {{"--volume", "131"}, "--volume must be in [0, 130] %"},
    };
    for (const auto &[args, message] : cases)
        EXPECT_EQ(checkPlayOptionValues(fromCommandLine(args)), message) << args[0];
    EXPECT_EQ(checkPlayOptionValues(PlayOptions{}), "") << "the defaults pass";
    EXPECT_EQ(checkPlayOptionValues(fromCommandLine({"--stereo", "Side-By-Side"})), "")
        << "the player's own names of the layouts";
}

// A number given as "" or as nan / inf is refused when the command line is read: CLI11 gave ""
// the value 0 (for most rows the default: `--duration ''` played for ever) and nan passed every
// range check.
TEST(PlayOptionTableTest, AnEmptyOrNonFiniteNumberIsRefused)
{
    const std::pair<std::vector<std::string>, std::string> cases[] = {
        {{"--duration", ""}, "--duration: a value is needed, not an empty text"},
        {{"--stiffness", ""}, "--stiffness: a value is needed, not an empty text"},
        {{"--rate", "nan"}, "--rate: a finite number is needed, not 'nan'"},
        {{"--duration", "inf"}, "--duration: a finite number is needed, not 'inf'"},
        {{"--osd-seconds", "-Infinity"},
         "--osd-seconds: a finite number is needed, not '-Infinity'"},
    };
    for (const auto &[args, message] : cases) {
        std::string error;
        (void)fromCommandLine(args, &error);
        EXPECT_NE(error.find(message), std::string::npos)
            << args[0] << " '" << args[1] << "': " << error;
    }
    // AND numbers and text options are read as before (an empty text option is its own value)
    std::string error;
    const PlayOptions o = fromCommandLine({"--duration", "2.5", "--stats", ""}, &error);
    EXPECT_EQ(error, "");
    EXPECT_DOUBLE_EQ(o.duration, 2.5);
}

TEST(PlayOptionTableTest, ArgumentAndConfigPathAreNotConfigKeys)
{
    for (const char *key : {"url", "config"}) {
        std::string error;
        fromConfig(std::string(key) + " = \"a\"\n", &error);
        EXPECT_EQ(error, "--config 'p.toml': unknown key '" + std::string(key) + "'");
    }
}

TEST(PlayOptionTableTest, OptionsLandInThePlayersConfig)
{
    const playback::PlaybackConfig defaults = landPlayOptions(PlayOptions{});
    EXPECT_EQ(defaults.haptics.servoRateHz, playbackDefaults().haptics.servoRateHz);
    EXPECT_EQ(defaults.haptics.method, haptics::Method::Finger) << "the renderer table's first row";
    EXPECT_TRUE(defaults.haptics.renderer.safety);
    // --method picks a row of the renderer table, with the paper's fixes as the row says.
    const playback::PlaybackConfig paper =
        landPlayOptions(fromCommandLine({"--method", "modified"}));
    EXPECT_EQ(paper.haptics.method, haptics::Method::Modified);
    EXPECT_TRUE(paper.haptics.renderer.correction && paper.haptics.renderer.interpolation &&
                paper.haptics.renderer.safety);
    const playback::PlaybackConfig baseline =
        landPlayOptions(fromConfig("method = \"proxy-graph\"\n"));
    EXPECT_EQ(baseline.haptics.method, haptics::Method::ProxyGraph);
    EXPECT_FALSE(baseline.haptics.renderer.correction || baseline.haptics.renderer.interpolation ||
                 baseline.haptics.renderer.safety);
    EXPECT_EQ(defaults.haptics.renderer.reengage, haptics::Reengage::Ramp) << "play's own default";
    EXPECT_FALSE(defaults.frameCompatible);

    const PlayOptions o = fromCommandLine(
        {"--stereo",     "tab",       "--stiffness",    "1200", "--rate",           "2000",
         "--reengage",   "release",   "--snapshot-dir", "s",    "--snapshot-every", "30",
         "--record",     "r.mkv",     "--record-crf",   "30",   "--force-log",      "f.csv",
         "--size",       "1920x1080", "--mesh-step",    "4",    "--osd-seconds",    "0",
         "--lod-target", "0.5",       "--max-lateness", "0.1",  "--require-rt"});
    ASSERT_EQ(checkPlayOptionValues(o), "");
    const playback::PlaybackConfig c = landPlayOptions(o);
    EXPECT_EQ(c.stereoMode, player::StereoMode::TopAndBottom);
    EXPECT_EQ(c.haptics.renderer.stiffness, 1200.0);
    EXPECT_EQ(c.haptics.servoRateHz, 2000.0);
    EXPECT_EQ(c.haptics.renderer.reengage, haptics::Reengage::Release);
    EXPECT_EQ(c.snapshotDir, "s");
    EXPECT_EQ(c.snapshotEvery, 30u);
    EXPECT_EQ(c.recordPath, "r.mkv");
    EXPECT_EQ(c.recordCrf, 30);
    EXPECT_EQ(c.haptics.forceLogPath, "f.csv");
    EXPECT_EQ(c.outputWidth, 1920);
    EXPECT_EQ(c.outputHeight, 1080);
    EXPECT_TRUE(c.frameCompatible);
    EXPECT_EQ(c.meshStep, 4);
    EXPECT_EQ(c.osdSeconds, 0.0);
    EXPECT_EQ(c.lodTarget, 0.5);
    EXPECT_EQ(c.maxLateness, 0.1);
    EXPECT_TRUE(c.haptics.requireRt);
    // FFmpeg stereo3d's names say half (sbs2l, ab2l) or full-size eyes (sbsl) whatever --size says
    const playback::PlaybackConfig full =
        landPlayOptions(fromCommandLine({"--stereo", "sbsl", "--size", "1920x1080"}));
    EXPECT_EQ(full.stereoMode, player::StereoMode::SideBySide);
    EXPECT_FALSE(full.frameCompatible);
    const playback::PlaybackConfig half = landPlayOptions(fromCommandLine({"--stereo", "ab2l"}));
    EXPECT_EQ(half.stereoMode, player::StereoMode::TopAndBottom);
    EXPECT_TRUE(half.frameCompatible);
    EXPECT_EQ(landPlayOptions(fromCommandLine({"--stereo", "irl"})).stereoMode,
              player::StereoMode::Interleaved);
    EXPECT_EQ(defaults.haptics.renderer.staticFriction, 0.0) << "frictionless by default";
    const playback::PlaybackConfig f =
        landPlayOptions(fromCommandLine({"--static-friction", "0.5", "--dynamic-friction", "0.3"}));
    EXPECT_EQ(f.haptics.renderer.staticFriction, 0.5);
    EXPECT_EQ(f.haptics.renderer.dynamicFriction, 0.3);
}

/// \return whether \a help names \a row (an argument by its placeholder, an option as --name).
bool helpNames(const std::string &help, const Row &row)
{
    return help.find(optionLabel(row)) != std::string::npos &&
           help.find(std::string(row.help).substr(0, 30)) != std::string::npos;
}

TEST(PlayOptionTableTest, HelpListsEveryRow)
{
    PlayOptions opt;
    CommandLine line{"play"};
    addOptions(line.root(), playOptionTable(), opt);
    const std::string help = line.help();
    for (const Row &row : playOptionTable())
        EXPECT_TRUE(helpNames(help, row)) << row.name << "\n" << help;
}

// The ranges in --help are the checks' own: the shared options' from their one row
// (depthtouch/options/option_range.h), read here from that header, not from the table.
TEST(PlayOptionTableTest, HelpGivesTheRangeTheCheckHolds)
{
    PlayOptions opt;
    CommandLine line{"play"};
    addOptions(line.root(), playOptionTable(), opt);
    const std::string help = line.help();
    for (const options::OptionRange &r :
         {options::kStiffness, options::kVolume, options::kServoRate}) {
        const std::string range = "(in [" + options::OptionRange::number(r.min) + ", " +
                                  options::OptionRange::number(r.max) + "] " + std::string(r.unit) +
                                  ")";
        const std::size_t at = help.find("--" + std::string(r.name) + " ");
        ASSERT_NE(at, std::string::npos) << r.name;
        const std::string row = help.substr(at, help.find('\n', at) - at);
        EXPECT_NE(row.find(range), std::string::npos) << row << " lacks " << range;
    }
    // A range check with its own message (--duration: ">= 0 s") adds nothing.
    const std::size_t at = help.find("--duration ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(help.substr(at, help.find('\n', at) - at).find("(in ["), std::string::npos);
}

#ifdef DEPTHTOUCH
TEST(PlayOptionTableTest, PlayHelpOfTheExecutableListsEveryRow)
{
    std::unique_ptr<FILE, int (*)(FILE *)> p(::popen(DEPTHTOUCH " play --help 2>&1", "r"),
                                             &::pclose);
    ASSERT_NE(p, nullptr);
    std::string help;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p.get())) > 0;)
        help.append(buf, n);
    for (const Row &row : playOptionTable())
        EXPECT_TRUE(helpNames(help, row)) << row.name << "\n" << help;
}
#endif

} // namespace
} // namespace depthtouch::cli
