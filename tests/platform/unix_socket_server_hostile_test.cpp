// UnixSocketServer against a hostile system: a socket file swapped for a symlink right after bind()
// (the control socket in a world-writable folder) and accept() failing with EMFILE. bind() and
// accept4() are interposed in this program (its own, so no other test sees them): the swap happens
// at a fixed point, not by a race, and the accept4() calls are counted, not timed.
#include "depthtouch/platform/unix_socket_server.h"

#include <cerrno>
#include <cstring>
#include <functional>
#include <string>

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace {

/// Called with the path right after each successful bind() of a Unix socket to a path.
std::function<void(const char *)> gAfterBind;
/// Counts the accept4() calls.
int gAccepts = 0;

template <class F> F realFunction(const char *name)
{
    return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}

} // namespace

extern "C" int bind(int fd, const sockaddr *addr, socklen_t len)
{
    static const auto real = realFunction<int (*)(int, const sockaddr *, socklen_t)>("bind");
    const int r = real(fd, addr, len);
    if (r == 0 && addr->sa_family == AF_UNIX && gAfterBind) {
        const auto *un = reinterpret_cast<const sockaddr_un *>(addr);
        const int saved = errno;
        gAfterBind(un->sun_path);
        errno = saved;
    }
    return r;
}

extern "C" int accept4(int fd, sockaddr *addr, socklen_t *len, int flags)
{
    static const auto real = realFunction<int (*)(int, sockaddr *, socklen_t *, int)>("accept4");
    ++gAccepts;
    return real(fd, addr, len, flags);
}

namespace depthtouch::platform {
namespace {

class NullHandler final : public UnixSocketServer::Handler {
public:
    int connects = 0;
    void onConnect(UnixSocketServer::ClientId) override { ++connects; }
    void onLine(UnixSocketServer::ClientId, std::string_view) override {}
    void onLineTooLong(UnixSocketServer::ClientId) override {}
};

class UnixSocketServerHostileTest : public ::testing::Test {
protected:
    void TearDown() override
    {
        gAfterBind = nullptr;
        server_.reset();
    }

    UniqueFd connectClient() const
    {
        UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
        EXPECT_EQ(::connect(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr), 0)
            << std::strerror(errno);
        return fd;
    }

    testing::TempDir dir_{"dt-sock-hostile-"};
    std::string path_ = dir_.path("control.sock");
    NullHandler handler_;
    std::unique_ptr<UnixSocketServer> server_;
};

/// Restores the soft RLIMIT_NOFILE at the end of a scope.
class FdLimit {
public:
    FdLimit() { ::getrlimit(RLIMIT_NOFILE, &saved_); }
    ~FdLimit() { ::setrlimit(RLIMIT_NOFILE, &saved_); }
    FdLimit(const FdLimit &) = delete;
    FdLimit &operator=(const FdLimit &) = delete;

    /// Lowers the soft limit so that the next file descriptor fails with EMFILE.
    static bool exhaust()
    {
        const int probe = ::dup(0);
        if (probe < 0)
            return false;
        ::close(probe);
        rlimit lowered{};
        ::getrlimit(RLIMIT_NOFILE, &lowered);
        lowered.rlim_cur = static_cast<rlim_t>(probe);
        return ::setrlimit(RLIMIT_NOFILE, &lowered) == 0 && ::dup(0) < 0 && errno == EMFILE;
    }

private:
    rlimit saved_{};
};

TEST_F(UnixSocketServerHostileTest, socketFileIsBornWithItsModeUnderAWideUmask)
{
    const mode_t oldMask = ::umask(0);
    mode_t modeAtBind = 0;
    gAfterBind = [&](const char *path) {
        struct stat st {};
        if (::lstat(path, &st) == 0)
            modeAtBind = st.st_mode & 07777;
    };
    auto r = UnixSocketServer::listen(path_, handler_);
    gAfterBind = nullptr;
    EXPECT_EQ(::umask(oldMask), 0u) << "the process's umask is restored";
    ASSERT_TRUE(r) << r.error().what;
    server_ = std::move(*r);
    EXPECT_EQ(modeAtBind, 0600u) << "no moment with a wider mode";
}

TEST_F(UnixSocketServerHostileTest, socketSwappedForASymlinkAfterBindIsNotFollowed)
{
    const std::string victim = dir_.path("victim");
    {
        const UniqueFd f(::open(victim.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644));
        ASSERT_TRUE(f);
    }
    ASSERT_EQ(::chmod(victim.c_str(), 0644), 0);
    gAfterBind = [&](const char *path) {
        // What a racing user does in a world-writable, non-sticky folder.
        const std::string moved = std::string(path) + ".moved";
        ASSERT_EQ(::rename(path, moved.c_str()), 0);
        ASSERT_EQ(::symlink(victim.c_str(), path), 0);
    };
    auto r = UnixSocketServer::listen(path_, handler_);
    gAfterBind = nullptr;
    struct stat st {};
    ASSERT_EQ(::stat(victim.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, 0644u) << "the victim's mode was changed through the symlink";
    EXPECT_FALSE(r) << "a socket path that no longer holds the socket is refused";
    server_.reset();
    EXPECT_EQ(::lstat(path_.c_str(), &st), 0)
        << "the planted symlink is not this server's to remove";
    EXPECT_EQ(::stat(victim.c_str(), &st), 0);
}

TEST_F(UnixSocketServerHostileTest, acceptFailingWithEmfileDoesNotSpin)
{
    auto r = UnixSocketServer::listen(path_, handler_);
    ASSERT_TRUE(r) << r.error().what;
    server_ = std::move(*r);
    const UniqueFd client = connectClient();
    int acceptsInPolls = 0;
    {
        FdLimit limit;
        ASSERT_TRUE(FdLimit::exhaust());
        gAccepts = 0;
        // Each poll that still finds the listening socket readable would call accept4() again:
        // that is the loop waking up at once, round after round.
        for (int i = 0; i < 50; ++i)
            ASSERT_TRUE(server_->poll(std::chrono::milliseconds(0)));
        acceptsInPolls = gAccepts;
    }
    EXPECT_LE(acceptsInPolls, 5) << "accept4() called on every poll round: the loop spins";
    EXPECT_EQ(handler_.connects, 0);
    char c = 0;
    EXPECT_EQ(::recv(client.get(), &c, 1, MSG_DONTWAIT), 0)
        << "the connection that could not be served is closed, not left pending";
    // Descriptors again: the next connection is served.
    const UniqueFd next = connectClient();
    for (int i = 0; i < 100 && handler_.connects == 0; ++i)
        ASSERT_TRUE(server_->poll(std::chrono::milliseconds(10)));
    EXPECT_EQ(handler_.connects, 1);
}

} // namespace
} // namespace depthtouch::platform
