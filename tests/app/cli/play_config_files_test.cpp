/// \file
/// \brief Where `play`'s settings come from (app/cli/play_config_files.h): the folders taken from
/// the environment as the XDG Base Directory Specification says, the order system file, user
/// file, `--config`, command line (each later one winning key by key), errors naming the file,
/// and `--show-config`'s TOML read back for its values and the origin each line names.

#include "play_config_files.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "support/temp_dir.h"

namespace depthtouch::cli {
namespace {

namespace fs = std::filesystem;

/// Sets (or unsets, for nullptr) an environment variable for one scope.
class ScopedEnv {
public:
    ScopedEnv(const char *name, const char *value) : name_(name)
    {
        if (const char *old = std::getenv(name))
            old_ = old;
        if (value != nullptr)
            ::setenv(name, value, 1);
        else
            ::unsetenv(name);
    }
    ~ScopedEnv()
    {
        if (old_)
            ::setenv(name_, old_->c_str(), 1);
        else
            ::unsetenv(name_);
    }
    ScopedEnv(const ScopedEnv &) = delete;
    ScopedEnv &operator=(const ScopedEnv &) = delete;

private:
    const char *name_;
    std::optional<std::string> old_;
};

TEST(PlayConfigFilesTest, TheFoldersFollowTheEnvironmentAsXdgSays)
{
    {
        ScopedEnv sys("DT_SYSTEM_CONFIG_DIR", nullptr);
        ScopedEnv xdg("XDG_CONFIG_HOME", "/cfg/home");
        ScopedEnv home("HOME", "/home/viewer");
        const ConfigDirs d = configDirsFromEnvironment();
        EXPECT_EQ(d.system, "/etc/depthtouch"); // the compiled-in default
        EXPECT_EQ(d.user, "/cfg/home/depthtouch");
    }
    for (const char *xdgValue : {static_cast<const char *>(nullptr), "", "relative/cfg"}) {
        // Unset, empty and relative are all "not set": $HOME/.config.
        ScopedEnv sys("DT_SYSTEM_CONFIG_DIR", "/opt/box/etc");
        ScopedEnv xdg("XDG_CONFIG_HOME", xdgValue);
        ScopedEnv home("HOME", "/home/viewer");
        const ConfigDirs d = configDirsFromEnvironment();
        EXPECT_EQ(d.system, "/opt/box/etc");
        EXPECT_EQ(d.user, "/home/viewer/.config/depthtouch") << (xdgValue ? xdgValue : "unset");
    }
    {
        ScopedEnv sys("DT_SYSTEM_CONFIG_DIR", "");
        ScopedEnv xdg("XDG_CONFIG_HOME", nullptr);
        ScopedEnv home("HOME", nullptr);
        const ConfigDirs d = configDirsFromEnvironment();
        EXPECT_EQ(d.system, "");
        EXPECT_EQ(d.user, "");
    }
}

TEST(PlayConfigFilesTest, TheFilesAreSystemThenUserThenConfigAndNoConfigLeavesTheDefaultsOut)
{
    const ConfigDirs dirs{"/etc/depthtouch", "/home/v/.config/depthtouch"};
    PlayOptions o;
    o.config = "box.toml";
    std::vector<PlayConfigFile> f = playConfigFiles(dirs, o);
    ASSERT_EQ(f.size(), 3u);
    EXPECT_EQ(f[0].path, "/etc/depthtouch/play.toml");
    EXPECT_FALSE(f[0].required);
    EXPECT_EQ(f[1].path, "/home/v/.config/depthtouch/play.toml");
    EXPECT_FALSE(f[1].required);
    EXPECT_EQ(f[2].path, "box.toml");
    EXPECT_TRUE(f[2].required);

    o.noConfig = true;
    f = playConfigFiles(dirs, o);
    ASSERT_EQ(f.size(), 1u);
    EXPECT_EQ(f[0].path, "box.toml");
    o.config.clear();
    EXPECT_TRUE(playConfigFiles(dirs, o).empty());
    o.noConfig = false;
    EXPECT_EQ(playConfigFiles(ConfigDirs{"", "/u"}, o).size(), 1u);
}

/// Writes \a text to \a path.
void write(const fs::path &path, const std::string &text)
{
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
}

TEST(PlayConfigFilesTest, LaterFilesWinKeyByKeyAndTheCommandLineWinsOverAll)
{
    testing::TempDir tmp("dt-play-config-files-");
    const fs::path sys = tmp.dir() / "etc" / "play.toml";
    const fs::path user = tmp.dir() / "home" / "play.toml";
    const fs::path given = tmp.dir() / "box.toml";
    write(sys, "display = \"mock\"\nstiffness = 1200\nrate = 500\nloop = true\n");
    write(user, "stiffness = 1500\nstereo = \"tab\"\n");
    write(given, "stereo = \"mono\"\nrecord-crf = 30\n");
    PlayOptions o;
    const auto commandLine = [](const std::string &key) { return key == "rate"; };
    o.rate = 2000.0; // as the command line left it
    const PlayConfigLoad load = loadPlayConfigFiles(
        {{sys.string(), false}, {user.string(), false}, {given.string(), true}}, commandLine, o);
    ASSERT_EQ(load.error, "");
    EXPECT_EQ(o.display, "mock");              // system only
    EXPECT_EQ(o.stiffness, 1500.0);            // user over system
    EXPECT_EQ(o.stereo, "mono");               // --config over user
    EXPECT_EQ(o.recordCrf, 30);                // --config only
    EXPECT_TRUE(o.loop);                       // system only
    EXPECT_EQ(o.rate, 2000.0);                 // the command line over the system file
    EXPECT_EQ(o.haptic, PlayOptions{}.haptic); // nobody: the default
    const std::map<std::string, std::string> expected = {
        {"display", sys.string()},      {"stiffness", user.string()}, {"stereo", given.string()},
        {"record-crf", given.string()}, {"loop", sys.string()},       {"rate", "command line"}};
    EXPECT_EQ(load.origins, (PlayConfigOrigins(expected.begin(), expected.end())));
    EXPECT_EQ(load.read, (std::vector<std::string>{sys.string(), user.string(), given.string()}));
    EXPECT_TRUE(load.absent.empty());
}

TEST(PlayConfigFilesTest, AMissingDefaultFileIsSkippedAMissingConfigIsAnErrorAndErrorsNameTheFile)
{
    testing::TempDir tmp("dt-play-config-files-");
    const fs::path missing = tmp.dir() / "none" / "play.toml";
    const fs::path bad = tmp.dir() / "etc" / "play.toml";
    write(bad, "stiffnes = 900\n");
    PlayOptions o;
    PlayConfigLoad load = loadPlayConfigFiles({{missing.string(), false}}, nullptr, o);
    EXPECT_EQ(load.error, "");
    EXPECT_EQ(load.absent, std::vector<std::string>{missing.string()});
    EXPECT_TRUE(load.read.empty());

    load = loadPlayConfigFiles({{missing.string(), true}}, nullptr, o);
    EXPECT_EQ(load.error.rfind("--config '" + missing.string() + "': ", 0), 0u) << load.error;
    EXPECT_NE(load.error.find("No such file"), std::string::npos) << load.error;

    load = loadPlayConfigFiles({{bad.string(), false}}, nullptr, o);
    EXPECT_EQ(load.error, "config file '" + bad.string() + "': unknown key 'stiffnes'");
    // A default file that is there but a folder is refused, not skipped.
    load = loadPlayConfigFiles({{tmp.dir().string(), false}}, nullptr, o);
    EXPECT_NE(load.error.find("is a directory"), std::string::npos) << load.error;
}

TEST(PlayConfigFilesTest, ShowConfigIsTomlOfTheValuesInEffectEachWithItsOrigin)
{
    testing::TempDir tmp("dt-play-config-files-");
    const fs::path sys = tmp.dir() / "play.toml";
    write(sys, "display = \"mock\"\nstiffness = 1200.5\nidle = true\nsnapshot-every = 7\n");
    PlayOptions o;
    o.rate = 250.0;
    const PlayConfigLoad load = loadPlayConfigFiles(
        {{sys.string(), false}, {"/nonexistent/u/play.toml", false}},
        [](const std::string &key) { return key == "rate"; }, o);
    ASSERT_EQ(load.error, "");
    const std::string text = showPlayConfig(o, load);

    // Read back as TOML: the values are those in effect.
    const toml::table t = toml::parse(text);
    EXPECT_EQ(t["display"].value<std::string>(), "mock");
    EXPECT_EQ(t["stiffness"].value<double>(), 1200.5);
    EXPECT_EQ(t["idle"].value<bool>(), true);
    EXPECT_EQ(t["snapshot-every"].value<std::int64_t>(), 7);
    EXPECT_EQ(t["rate"].value<double>(), 250.0);
    EXPECT_EQ(t["haptic"].value<std::string>(), PlayOptions{}.haptic);
    EXPECT_FALSE(t.contains("config")); // command-line only: not a key
    EXPECT_FALSE(t.contains("url"));

    // Each key's line names where it came from.
    std::map<std::string, std::string> origin;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        const std::size_t eq = line.find(" = ");
        const std::size_t hash = line.rfind("  # ");
        if (line.empty() || line[0] == '#' || eq == std::string::npos || hash == std::string::npos)
            continue;
        origin[line.substr(0, eq)] = line.substr(hash + 4);
    }
    EXPECT_EQ(origin["display"], sys.string());
    EXPECT_EQ(origin["stiffness"], sys.string());
    EXPECT_EQ(origin["snapshot-every"], sys.string());
    EXPECT_EQ(origin["rate"], "command line");
    EXPECT_EQ(origin["haptic"], "default");
    EXPECT_EQ(origin.size(), t.size()); // every key has one line with an origin
    EXPECT_NE(text.find("# read: " + sys.string() + "\n"), std::string::npos);
    EXPECT_NE(text.find("# not found: /nonexistent/u/play.toml\n"), std::string::npos);
}

TEST(PlayConfigFilesTest, ShowConfigStaysTomlWhenAPathHoldsANewline)
{
    testing::TempDir tmp("dt-play-config-files-");
    const fs::path file = tmp.dir() / "a\nstiffness = 1\n\x01play.toml";
    write(file, "stiffness = 900.0\n");
    PlayOptions o;
    const PlayConfigLoad load = loadPlayConfigFiles(
        {{file.string(), true}, {"/nonexistent/b\n[x]/play.toml", false}}, nullptr, o);
    ASSERT_EQ(load.error, "");
    const std::string text = showPlayConfig(o, load);
    toml::table t;
    ASSERT_NO_THROW(t = toml::parse(text)) << text;
    EXPECT_EQ(t["stiffness"].value<double>(), 900.0) << "the file's value, not the path's text";
    EXPECT_FALSE(t.contains("x"));
    EXPECT_NE(text.find("# read: " + (tmp.dir() / "a?stiffness = 1??play.toml").string() + "\n"),
              std::string::npos)
        << text;
}

/// \return what loadPlayConfigFiles() says of the default file \a path, from a child process
/// killed after 5 s: "hang" when it did not return.
std::string defaultFileErrorOrHang(const std::string &path)
{
    int pipeFds[2];
    if (::pipe(pipeFds) != 0)
        return "pipe failed";
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(pipeFds[0]);
        ::alarm(5);
        PlayOptions o;
        const PlayConfigLoad load = loadPlayConfigFiles({{path, false}}, nullptr, o);
        const std::string out = load.error.empty() ? "absent or read" : load.error;
        (void)!::write(pipeFds[1], out.data(), out.size());
        ::_exit(0);
    }
    ::close(pipeFds[1]);
    std::string out;
    char buf[512];
    for (ssize_t n; (n = ::read(pipeFds[0], buf, sizeof buf)) > 0;)
        out.append(buf, static_cast<std::size_t>(n));
    ::close(pipeFds[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFSIGNALED(status) ? "hang" : out;
}

TEST(PlayConfigFilesTest, ADefaultFileThatIsALinkLoopOrADeviceIsAnErrorNamingItNeverAHang)
{
    testing::TempDir tmp("dt-play-config-files-");
    const fs::path loop = tmp.dir() / "play.toml";
    fs::create_symlink(loop, loop);
    const std::string loopError = defaultFileErrorOrHang(loop.string());
    EXPECT_EQ(loopError.rfind("config file '" + loop.string() + "': ", 0), 0u) << loopError;
    EXPECT_EQ(loopError.find('\n'), std::string::npos);

    const fs::path keys = tmp.dir() / "input.conf";
    fs::create_symlink(keys, keys);
    player::KeyMap keyMap;
    const std::string keysError = loadKeyMapFiles({{keys.string(), false}}, keyMap);
    EXPECT_EQ(keysError.rfind("key map '" + keys.string() + "': ", 0), 0u) << keysError;

    const fs::path device = tmp.dir() / "device.toml";
    fs::create_symlink("/dev/ptmx", device);
    const std::string deviceError = defaultFileErrorOrHang(device.string());
    EXPECT_EQ(deviceError.rfind("config file '" + device.string() + "': ", 0), 0u) << deviceError;
    EXPECT_NE(deviceError.find("character device"), std::string::npos) << deviceError;

    // A FIFO is still read, as documented: with a writer its lines count.
    const fs::path fifo = tmp.dir() / "fifo.toml";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::thread writer([&] { write(fifo, "stiffness = 900\n"); });
    PlayOptions o;
    const PlayConfigLoad load = loadPlayConfigFiles({{fifo.string(), true}}, nullptr, o);
    writer.join();
    EXPECT_EQ(load.error, "");
}

} // namespace
} // namespace depthtouch::cli
