// UnixSocketServer over real sockets in a temporary directory: lines, limits, many clients,
// disconnects, the socket file's mode and removal.
#include "depthtouch/platform/unix_socket_server.h"

#include <cstdlib>
#include <cstring>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::platform {
namespace {

using ClientId = UnixSocketServer::ClientId;
using std::chrono::milliseconds;

class Recorder final : public UnixSocketServer::Handler {
public:
    std::vector<std::pair<ClientId, std::string>> lines;
    std::vector<ClientId> tooLong;
    std::set<ClientId> connected;
    std::vector<ClientId> disconnected;
    std::function<void(ClientId, std::string_view)> onLineHook;

    void onConnect(ClientId c) override { connected.insert(c); }
    void onLine(ClientId c, std::string_view line) override
    {
        lines.emplace_back(c, std::string(line));
        if (onLineHook)
            onLineHook(c, line);
    }
    void onLineTooLong(ClientId c) override { tooLong.push_back(c); }
    void onDisconnect(ClientId c) override
    {
        connected.erase(c);
        disconnected.push_back(c);
    }
};

class UnixSocketServerTest : public ::testing::Test {
protected:
    void TearDown() override { server_.reset(); }

    void start(UnixSocketServerOptions options = {})
    {
        auto r = UnixSocketServer::listen(path_, handler_, options);
        ASSERT_TRUE(r) << r.error().what;
        server_ = std::move(*r);
    }
    /// Starts the server with room for \a maxClients clients, answering each line with
    /// "echo LINE\n" to the client that sent it.
    void startEchoing(std::size_t maxClients)
    {
        UnixSocketServerOptions options;
        options.maxClients = maxClients;
        start(options);
        handler_.onLineHook = [this](ClientId id, std::string_view line) {
            server_->send(id, "echo " + std::string(line) + "\n");
        };
    }

    UniqueFd connectClient()
    {
        UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
        EXPECT_EQ(::connect(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr), 0)
            << std::strerror(errno);
        return fd;
    }

    /// Serves until \a done or \a rounds rounds of at most 10 ms.
    bool pumpUntil(const std::function<bool()> &done, int rounds = 200)
    {
        for (int i = 0; i < rounds && !done(); ++i) {
            if (!server_->poll(milliseconds(10)))
                return false;
        }
        return done();
    }

    static void writeAll(const UniqueFd &fd, std::string_view data)
    {
        ASSERT_EQ(::send(fd.get(), data.data(), data.size(), MSG_NOSIGNAL),
                  static_cast<ssize_t>(data.size()));
    }

    /// Reads what arrives on \a fd within ~1 s until \a want bytes (or EOF).
    static std::string readSome(const UniqueFd &fd, std::size_t want)
    {
        std::string out;
        char buf[4096];
        for (int i = 0; i < 100 && out.size() < want; ++i) {
            const ssize_t n = ::recv(fd.get(), buf, sizeof buf, MSG_DONTWAIT);
            if (n > 0)
                out.append(buf, static_cast<std::size_t>(n));
            else if (n == 0)
                break;
            else
                ::usleep(10000);
        }
        return out;
    }

    testing::TempDir dir_{"dt-sock-"};
    std::string path_ = dir_.path("control.sock");
    Recorder handler_;
    std::unique_ptr<UnixSocketServer> server_;
};

TEST_F(UnixSocketServerTest, socketFileHasModeOwnerOnlyAndIsRemovedAtTheEnd)
{
    start();
    struct stat st {};
    ASSERT_EQ(::lstat(path_.c_str(), &st), 0);
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    server_.reset();
    EXPECT_NE(::lstat(path_.c_str(), &st), 0) << "socket file left behind";
}

TEST_F(UnixSocketServerTest, refusesAPathThatIsNotASocketAndKeepsTheFile)
{
    const int fd = ::open(path_.c_str(), O_CREAT | O_WRONLY | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0);
    ::close(fd);
    auto r = UnixSocketServer::listen(path_, handler_);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::InvalidArgument);
    struct stat st {};
    ASSERT_EQ(::lstat(path_.c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode));
}

TEST_F(UnixSocketServerTest, refusesASocketInUseAndReplacesAStaleOne)
{
    start();
    Recorder other;
    auto busy = UnixSocketServer::listen(path_, other);
    ASSERT_FALSE(busy);
    EXPECT_EQ(busy.error().code, Errc::Busy);

    // A stale socket file: bound, then closed without removing the file.
    server_.reset();
    {
        UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM, 0));
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
        ASSERT_EQ(::bind(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr), 0);
    }
    start();
    UniqueFd c = connectClient();
    EXPECT_TRUE(pumpUntil([&] { return handler_.connected.size() == 1; }));
}

TEST_F(UnixSocketServerTest, rejectsBadPaths)
{
    EXPECT_EQ(UnixSocketServer::listen("", handler_).error().code, Errc::InvalidArgument);
    EXPECT_EQ(UnixSocketServer::listen(std::string(200, 'x'), handler_).error().code,
              Errc::InvalidArgument);
    EXPECT_FALSE(UnixSocketServer::listen("/nonexistent-dir/x.sock", handler_));
}

TEST_F(UnixSocketServerTest, deliversLinesSplitOrBatched)
{
    start();
    UniqueFd c = connectClient();
    writeAll(c, "first\r\nsec");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 1; }));
    writeAll(c, "ond\n\nthird\nfour");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 4; }));
    EXPECT_EQ(handler_.lines[0].second, "first");
    EXPECT_EQ(handler_.lines[1].second, "second");
    EXPECT_EQ(handler_.lines[2].second, "");
    EXPECT_EQ(handler_.lines[3].second, "third");
    // "four" has no newline yet: not delivered.
    EXPECT_FALSE(pumpUntil([&] { return handler_.lines.size() > 4; }, 5));
}

TEST_F(UnixSocketServerTest, overlongLinesAreReportedAndDiscardedConnectionKept)
{
    UnixSocketServerOptions options;
    options.maxLineBytes = 16;
    start(options);
    UniqueFd c = connectClient();
    // Exactly the limit passes, with or without '\r'.
    writeAll(c, std::string(16, 'a') + "\n" + std::string(16, 'b') + "\r\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 2; }));
    // One byte over, in one write and spread over writes.
    writeAll(c, std::string(17, 'c') + "\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.tooLong.size() == 1; }));
    writeAll(c, std::string(10, 'd'));
    writeAll(c, std::string(10, 'd'));
    writeAll(c, std::string(5000, 'd'));
    writeAll(c, "dd\nafter\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 3; }));
    EXPECT_EQ(handler_.tooLong.size(), 2u) << "one report per overlong line";
    EXPECT_EQ(handler_.lines[2].second, "after");
    EXPECT_EQ(server_->clientCount(), 1u);
}

TEST_F(UnixSocketServerTest, binaryBytesArePassedThrough)
{
    start();
    UniqueFd c = connectClient();
    const std::string bytes("\0\x01\xff{\"", 5);
    writeAll(c, bytes + "\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 1; }));
    EXPECT_EQ(handler_.lines[0].second, bytes);
}

TEST_F(UnixSocketServerTest, clientDisconnectMidLineDropsThePartialLine)
{
    start();
    {
        UniqueFd c = connectClient();
        writeAll(c, "complete\nincompl");
        ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 1; }));
    }
    ASSERT_TRUE(pumpUntil([&] { return handler_.disconnected.size() == 1; }));
    EXPECT_EQ(handler_.lines.size(), 1u);
    EXPECT_EQ(server_->clientCount(), 0u);
}

TEST_F(UnixSocketServerTest, manyClientsRepliesAndBroadcast)
{
    startEchoing(8);
    std::vector<UniqueFd> clients;
    for (int i = 0; i < 10; ++i)
        clients.push_back(connectClient());
    ASSERT_TRUE(pumpUntil([&] { return handler_.connected.size() == 8; }));
    EXPECT_FALSE(pumpUntil([&] { return handler_.connected.size() > 8; }, 5));
    EXPECT_EQ(server_->clientCount(), 8u);

    for (std::size_t i = 0; i < 8; ++i)
        writeAll(clients[i], "hello " + std::to_string(i) + "\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 8; }));
    server_->broadcast("news\n");
    for (std::size_t i = 0; i < 8; ++i) {
        const std::string want = "echo hello " + std::to_string(i) + "\nnews\n";
        EXPECT_EQ(readSome(clients[i], want.size()), want) << i;
    }
    // The two refused connections were closed by the server.
    for (std::size_t i = 8; i < 10; ++i)
        EXPECT_EQ(readSome(clients[i], 1), "") << i;
}

// Clients that each hold half a line and send no more do not lock everyone out: a new
// connection takes the place of the one stalled longest, and it is served; clients that wait
// with nothing pending keep theirs.
TEST_F(UnixSocketServerTest, clientsStalledMidLineGiveTheirPlaceToANewOne)
{
    startEchoing(4);
    // GIVEN one quiet subscriber and three clients stuck in the middle of a line
    std::vector<UniqueFd> clients;
    clients.push_back(connectClient());
    ASSERT_TRUE(pumpUntil([&] { return handler_.connected.size() == 1; }));
    for (int i = 0; i < 3; ++i) {
        clients.push_back(connectClient());
        ASSERT_TRUE(pumpUntil([&] { return handler_.connected.size() == clients.size(); }));
        writeAll(clients.back(), "{\"command\": [\"get_pro");
    }
    ASSERT_TRUE(pumpUntil([&] { return server_->clientCount() == 4; }));
    EXPECT_FALSE(pumpUntil([&] { return !handler_.lines.empty(); }, 5));
    // WHEN two more connect and send a line each
    for (int i = 0; i < 2; ++i) {
        clients.push_back(connectClient());
        ASSERT_TRUE(pumpUntil([&] { return handler_.disconnected.size() == std::size_t(i) + 1; }));
        writeAll(clients.back(), "hello " + std::to_string(i) + "\n");
        ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == std::size_t(i) + 1; }));
    }
    // THEN they were served, in the places of the two stalled longest
    EXPECT_EQ(readSome(clients[4], 13), "echo hello 0\n");
    EXPECT_EQ(readSome(clients[5], 13), "echo hello 1\n");
    EXPECT_EQ(handler_.disconnected, (std::vector<ClientId>{2, 3}));
    EXPECT_EQ(readSome(clients[1], 1), "") << "the first stalled client was closed";
    // AND the quiet subscriber and the last stalled client are still connected
    EXPECT_EQ(server_->clientCount(), 4u);
    EXPECT_TRUE(handler_.connected.count(1) == 1 && handler_.connected.count(4) == 1);
    // AND with every place held by clients with nothing pending, a new one is refused
    writeAll(clients[3], "ted\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 3; }));
    clients.push_back(connectClient());
    EXPECT_FALSE(pumpUntil([&] { return handler_.connected.size() > 4; }, 5));
    EXPECT_EQ(readSome(clients.back(), 1), "");
}

TEST_F(UnixSocketServerTest, clientThatDoesNotReadIsDropped)
{
    UnixSocketServerOptions options;
    options.maxQueuedBytes = 64 * 1024;
    start(options);
    UniqueFd c = connectClient();
    ASSERT_TRUE(pumpUntil([&] { return handler_.connected.size() == 1; }));
    const ClientId id = *handler_.connected.begin();
    const std::string chunk(8192, 'x');
    bool dropped = false;
    for (int i = 0; i < 1000 && !dropped; ++i)
        dropped = !server_->send(id, chunk);
    EXPECT_TRUE(dropped);
    ASSERT_TRUE(pumpUntil([&] { return handler_.disconnected.size() == 1; }));
    EXPECT_EQ(server_->clientCount(), 0u);
}

TEST_F(UnixSocketServerTest, handlerMayDisconnectAClient)
{
    start();
    handler_.onLineHook = [&](ClientId id, std::string_view line) {
        if (line == "bye")
            server_->disconnect(id);
    };
    UniqueFd c = connectClient();
    writeAll(c, "bye\nignored\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.disconnected.size() == 1; }));
    EXPECT_EQ(handler_.lines.size(), 1u) << "nothing is read after disconnect()";
    EXPECT_EQ(readSome(c, 1), "");
}

// A client connected before another sent a line is a client when that line is handled: what the
// line broadcasts reaches it (an mpv UI watches on a second connection for the events of the
// command it sends next, as node-mpv does; issue 61).
TEST_F(UnixSocketServerTest, aClientConnectedBeforeALineIsSentGetsWhatTheLineBroadcasts)
{
    start();
    handler_.onLineHook = [this](ClientId, std::string_view line) {
        server_->broadcast("event " + std::string(line) + "\n");
    };
    const UniqueFd sender = connectClient();
    ASSERT_TRUE(pumpUntil([&] { return handler_.connected.size() == 1; }));
    const UniqueFd watcher = connectClient(); // not yet accepted
    writeAll(sender, "go\n");
    ASSERT_TRUE(pumpUntil([&] { return handler_.lines.size() == 1; }));
    pumpUntil([] { return false; }, 3); // writes what is queued
    EXPECT_EQ(readSome(watcher, 9), "event go\n");
}

} // namespace
} // namespace depthtouch::platform
