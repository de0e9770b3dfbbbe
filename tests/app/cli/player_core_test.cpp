/// \file
/// \brief The player core (app/cli/player_core.h), the one path of `play`, libdepthtouch and the
/// GStreamer element, on the mock backends: a control socket path that cannot be used is bad input
/// with its one line and loses nothing; a run gathers the figures the stats JSON and the summary
/// read (the backends chosen, the device's maximum force as the device itself reports it), and the
/// socket is gone after the player. On a ManualClock: nothing here waits on the real clock.

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/platform/clock.h"
#include "player_core.h"

namespace depthtouch::cli {
namespace {

namespace fs = std::filesystem;

/// A folder of its own under the temporary one, removed at the end.
class TempDir {
public:
    TempDir()
    {
        char pattern[] = "/tmp/dt_player_core_XXXXXX";
        path_ = ::mkdtemp(pattern) != nullptr ? pattern : "";
    }
    ~TempDir()
    {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;
    [[nodiscard]] const std::string &path() const { return path_; }

private:
    std::string path_;
};

/// play's options on the mock display and device, without sound or remote.
PlayOptions mockOptions(const std::string &url)
{
    PlayOptions o;
    o.url = url;
    o.display = "mock";
    o.haptic = "mock";
    o.hapticOptions = "max_force=6.5";
    o.remote = "none";
    o.noAudio = true;
    return o;
}

TEST(PlayerCoreTest, aControlSocketPathThatIsAFileIsBadInputWithItsLineAndTheFileKept)
{
    TempDir dir;
    ASSERT_FALSE(dir.path().empty());
    const std::string file = dir.path() + "/notes.txt";
    std::ofstream(file) << "keep me\n";
    PlayOptions o = mockOptions(dir.path() + "/clip.mkv");
    o.control = file;
    platform::ManualClock clock;
    std::unique_ptr<PlayerCore> core;
    const std::optional<PlayOpenFailure> bad = PlayerCore::open(o, clock, {}, core);
    ASSERT_TRUE(bad.has_value());
    EXPECT_EQ(core, nullptr);
    EXPECT_EQ(bad->part, PlayPart::ControlSocket);
    EXPECT_TRUE(bad->badInput) << bad->message;
    EXPECT_TRUE(controlSocketBadInput(bad->error));
    EXPECT_EQ(bad->message.rfind("cannot create the control socket '" + file + "': ", 0), 0U)
        << bad->message;
    EXPECT_EQ(bad->message.find('\n'), std::string::npos);
    std::ifstream in(file);
    const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(kept, "keep me\n");
}

TEST(PlayerCoreTest, aSocketThatTheSystemRefusesForWantOfResourcesIsNoFaultOfThePath)
{
    EXPECT_FALSE(controlSocketBadInput(Error(Errc::Io, "socket", EMFILE)));
    EXPECT_FALSE(controlSocketBadInput(Error(Errc::OutOfResources, "socket", ENOBUFS)));
    EXPECT_TRUE(controlSocketBadInput(Error(Errc::Io, "bind", EADDRINUSE)));
    EXPECT_TRUE(controlSocketBadInput(Error(Errc::Io, "bind", ENAMETOOLONG)));
    EXPECT_TRUE(controlSocketBadInput(Error(Errc::Busy, "another player listens")));
}

TEST(PlayerCoreTest, aStoppedRunGathersTheBackendsAndTheDevicesMaximumForce)
{
    TempDir dir;
    ASSERT_FALSE(dir.path().empty());
    PlayOptions o = mockOptions(dir.path() + "/missing.mkv");
    o.control = dir.path() + "/player.sock";
    platform::ManualClock clock(platform::ManualClock::Mode::AutoAdvance);
    std::unique_ptr<PlayerCore> core;
    const std::optional<PlayOpenFailure> bad = PlayerCore::open(o, clock, {}, core);
    ASSERT_FALSE(bad.has_value()) << bad->message;
    ASSERT_NE(core, nullptr);
    EXPECT_TRUE(fs::is_socket(o.control)) << "the control socket is up once opened";

    // Stopped before its first turn ends: "play" was sent, then "quit". A turn of zero serves the
    // socket without waiting (simulated time does not pass while the socket is polled).
    const std::atomic<bool> stop{true};
    control::PlayLimits limits;
    limits.turn = platform::Duration::zero();
    int turns = 0;
    const control::LoopOutcome out = core->run([&turns] { ++turns; }, stop, limits);
    EXPECT_EQ(turns, 1);
    EXPECT_TRUE(out.stopped);
    EXPECT_TRUE(core->machine().quitRequested());
    const playback::PlayRunFigures run = core->finish(out);
    EXPECT_EQ(run.display, "mock");
    EXPECT_EQ(run.hapticDevice, "mock");
    EXPECT_EQ(run.audioDevice, "") << "no sound output with --no-audio";

    // The device's own report of its maximum, from a device made apart from the player.
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList(o.hapticOptions);
    auto device = drivers::createHapticDevice("mock", cfg);
    ASSERT_TRUE(device);
    EXPECT_DOUBLE_EQ(run.deviceMaxForce, (*device)->capabilities().maxForce);
    EXPECT_DOUBLE_EQ(run.deviceMaxForce, 6.5);
    core.reset();
    EXPECT_FALSE(fs::exists(o.control)) << "the socket is removed with the player";
}

} // namespace
} // namespace depthtouch::cli
