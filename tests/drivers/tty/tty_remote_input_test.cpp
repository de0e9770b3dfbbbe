// The terminal keyboard backend on a pseudo-terminal (openpty): key decoding, raw mode and its
// restoration on destruction and on signals, hang-up, and "not a terminal".
#include "depthtouch/drivers/tty/tty_remote_input.h"

#include <csignal>
#include <string>
#include <vector>

#include <fcntl.h>
#include <pty.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using depthtouch::testing::errcOf;
using hal::Key;
using hal::KeyAction;
using std::chrono::milliseconds;
using std::chrono::seconds;

std::vector<Key> decode(std::string_view bytes, std::size_t *used = nullptr)
{
    std::vector<Key> keys;
    const std::size_t n = decodeTerminalKeys(bytes, keys);
    if (used != nullptr)
        *used = n;
    return keys;
}

TEST(TerminalKeysTest, decodesLettersAndArrows)
{
    EXPECT_EQ(decode(" sS3hrcqQpx"),
              (std::vector<Key>{Key::PlayPause, Key::Stop, Key::Stop, Key::Mode3d, Key::Red,
                                Key::Green, Key::Yellow, Key::Exit, Key::Exit, Key::PlayPause}));
    EXPECT_EQ(decode("\x1b[A\x1b[B\x1b[C\x1b[D\x1bOA\x1bOD"),
              (std::vector<Key>{Key::Up, Key::Down, Key::Right, Key::Left, Key::Up, Key::Left}));
    // + (or =) and - set the stiffness (CH+/CH−), o brings up the on-screen display (mpv's key)
    EXPECT_EQ(decode("+=-oO"), (std::vector<Key>{Key::ChannelUp, Key::ChannelUp, Key::ChannelDown,
                                                 Key::Info, Key::Info}));
    // mpv's volume and mute keys
    EXPECT_EQ(decode("0*9/mM"), (std::vector<Key>{Key::VolumeUp, Key::VolumeUp, Key::VolumeDown,
                                                  Key::VolumeDown, Key::Mute, Key::Mute}));
    // Other sequences (F5, Delete, a cursor report) are skipped whole.
    EXPECT_EQ(decode("\x1b[15~\x1b[3~\x1b[12;40Rq"), std::vector<Key>{Key::Exit});
}

TEST(TerminalKeysTest, incompleteEscapeIsLeftForTheNextRead)
{
    std::size_t used = 0;
    EXPECT_EQ(decode("s\x1b[", &used), std::vector<Key>{Key::Stop});
    EXPECT_EQ(used, 1u);
    EXPECT_TRUE(decode("\x1b", &used).empty());
    EXPECT_EQ(used, 0u);
    EXPECT_TRUE(decode("\x1bO", &used).empty());
    EXPECT_EQ(used, 0u);
}

class TtyRemoteInputTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        int master = -1;
        int slave = -1;
        ASSERT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
        master_.reset(master);
        slave_.reset(slave);
        path_ = ::ttyname(slave);
        ASSERT_EQ(::tcgetattr(slave, &original_), 0);
        ASSERT_NE(original_.c_lflag & ICANON, 0u);
        ASSERT_NE(original_.c_lflag & ECHO, 0u);
    }

    Result<std::unique_ptr<hal::RemoteInput>> create()
    {
        hal::BackendConfig cfg;
        cfg.device = path_;
        return TtyRemoteInput::create(cfg);
    }

    termios current() const
    {
        termios t{};
        EXPECT_EQ(::tcgetattr(slave_.get(), &t), 0);
        return t;
    }

    void type(std::string_view bytes) const
    {
        ASSERT_EQ(::write(master_.get(), bytes.data(), bytes.size()),
                  static_cast<ssize_t>(bytes.size()));
    }

    platform::UniqueFd master_;
    platform::UniqueFd slave_;
    std::string path_;
    termios original_{};
};

TEST_F(TtyRemoteInputTest, keysArriveAsPressAndRelease)
{
    auto r = create();
    ASSERT_TRUE(r) << r.error().what;
    auto &remote = **r;
    type(" \x1b[C");
    type("3q");
    std::vector<std::pair<Key, KeyAction>> got;
    platform::Clock &clock = platform::SteadyClock::instance();
    for (int i = 0; i < 8; ++i) {
        auto e = remote.poll(clock.now() + seconds(2));
        ASSERT_TRUE(e) << e.error().what;
        got.emplace_back(e->key, e->action);
    }
    const std::vector<std::pair<Key, KeyAction>> expected = {
        {Key::PlayPause, KeyAction::Press}, {Key::PlayPause, KeyAction::Release},
        {Key::Right, KeyAction::Press},     {Key::Right, KeyAction::Release},
        {Key::Mode3d, KeyAction::Press},    {Key::Mode3d, KeyAction::Release},
        {Key::Exit, KeyAction::Press},      {Key::Exit, KeyAction::Release}};
    EXPECT_EQ(got, expected);
    auto quiet = remote.poll(clock.now() + milliseconds(20));
    ASSERT_FALSE(quiet);
    EXPECT_EQ(quiet.error().code, Errc::Timeout);
}

TEST_F(TtyRemoteInputTest, rawWhileOpenRestoredOnDestruction)
{
    {
        auto r = create();
        ASSERT_TRUE(r) << r.error().what;
        const termios raw = current();
        EXPECT_EQ(raw.c_lflag & ICANON, 0u);
        EXPECT_EQ(raw.c_lflag & ECHO, 0u);
        EXPECT_NE(raw.c_lflag & ISIG, 0u) << "Ctrl-C must keep working";
        // Only one terminal keyboard at a time.
        auto second = create();
        ASSERT_FALSE(second);
        EXPECT_EQ(second.error().code, Errc::Busy);
    }
    const termios after = current();
    EXPECT_EQ(after.c_lflag, original_.c_lflag);
    EXPECT_EQ(after.c_cc[VMIN], original_.c_cc[VMIN]);
    struct sigaction sa{};
    ASSERT_EQ(::sigaction(SIGTERM, nullptr, &sa), 0);
    EXPECT_EQ(sa.sa_handler, SIG_DFL) << "the previous SIGTERM disposition is back";
    // And a new one may be created again.
    EXPECT_TRUE(create());
}

TEST_F(TtyRemoteInputTest, signalRestoresTheTerminalThenTerminates)
{
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        auto r = create();
        if (!r)
            ::_exit(3);
        termios t{};
        ::tcgetattr(slave_.get(), &t);
        if ((t.c_lflag & ICANON) != 0)
            ::_exit(4);
        ::raise(SIGTERM);
        ::_exit(5); // not reached: the default action terminates
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit code " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    const termios after = current();
    EXPECT_NE(after.c_lflag & ICANON, 0u);
    EXPECT_NE(after.c_lflag & ECHO, 0u);
}

TEST_F(TtyRemoteInputTest, hangUpIsNoDevice)
{
    auto r = create();
    ASSERT_TRUE(r) << r.error().what;
    master_.reset();
    auto e = (*r)->poll(platform::SteadyClock::instance().now() + seconds(2));
    ASSERT_FALSE(e);
    EXPECT_EQ(e.error().code, Errc::NoDevice);
}

TEST(TtyRemoteInputFactoryTest, notATerminalIsNoDevice)
{
    hal::BackendConfig cfg;
    cfg.device = "/dev/null";
    EXPECT_EQ(errcOf(TtyRemoteInput::create(cfg)), Errc::NoDevice);
    cfg.device = "/nonexistent/tty";
    EXPECT_EQ(errcOf(TtyRemoteInput::create(cfg)), Errc::NoDevice);
    cfg.device = "";
    cfg.options = hal::OptionList("speed=9600");
    EXPECT_EQ(errcOf(TtyRemoteInput::create(cfg)), Errc::InvalidArgument);
}

} // namespace
} // namespace depthtouch::drivers
