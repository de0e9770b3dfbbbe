#include "depthtouch/platform/unix_socket_server.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Socket)

namespace depthtouch::platform {

namespace {

constexpr int kBacklog = 16;
constexpr std::size_t kReadChunk = 4096;
/// Bytes read from one client per poll round, so one busy client cannot starve the others.
constexpr std::size_t kReadBudget = 64 * 1024;
/// How long the listening socket is left out of poll() after accept() failed for want of
/// resources with no spare descriptor to refuse the connection on.
constexpr Duration kAcceptPause = std::chrono::milliseconds(100);

bool fillAddress(std::string_view path, sockaddr_un &addr) noexcept
{
    std::memset(&addr, 0, sizeof addr);
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof addr.sun_path)
        return false;
    std::memcpy(addr.sun_path, path.data(), path.size());
    return true;
}

/// True when a process accepts connections on the socket at \a addr.
bool someoneListens(const sockaddr_un &addr) noexcept
{
    UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (!fd)
        return false;
    return ::connect(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr) == 0;
}

Errc errcOfErrno(int err) noexcept
{
    return err == EACCES || err == EPERM ? Errc::PermissionDenied : Errc::Io;
}

/// \brief Binds \a fd to \a addr with the socket file created with permission bits \a mode.
///
/// The file gets its mode at its creation, from the umask (bind() creates it with 0777 & ~umask):
/// there is never a moment with a wider mode, and the mode is never set later by path, which
/// would follow whatever a user who may write to the folder put there in the meantime. The umask
/// is the process's: files other threads create meanwhile get at most \a mode too.
Result<void> bindWithMode(const UniqueFd &fd, const sockaddr_un &addr, const std::string &path,
                          unsigned mode) noexcept
{
    const mode_t oldMask = ::umask(static_cast<mode_t>(~mode & 0777));
    const int r = ::bind(fd.get(), reinterpret_cast<const sockaddr *>(&addr), sizeof addr);
    const int err = errno;
    ::umask(oldMask);
    if (r != 0) {
        DT_LOG(Socket, Error, "Failed to bind %s: %s", path.c_str(), std::strerror(err));
        return unexpected(errcOfErrno(err), "Failed to bind the Unix socket", err);
    }
    return ok();
}

/// \return a descriptor kept in reserve for accepting, and at once closing, a connection when the
/// process has no descriptor left (EMFILE); invalid if none could be opened.
UniqueFd openSpareFd() noexcept
{
    return UniqueFd(::open("/dev/null", O_RDONLY | O_CLOEXEC));
}

} // namespace

Result<std::unique_ptr<UnixSocketServer>>
UnixSocketServer::listen(std::string_view path, Handler &handler, UnixSocketServerOptions options)
{
    sockaddr_un addr{};
    if (!fillAddress(path, addr))
        return unexpected(Errc::InvalidArgument, "Socket path is empty or too long");
    const std::string pathText(path);

    struct stat st {};
    if (::lstat(pathText.c_str(), &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            DT_LOG(Socket, Error,
                   "Failed to create control socket %s: the path exists and is "
                   "not a socket",
                   pathText.c_str());
            return unexpected(Errc::InvalidArgument, "Socket path exists and is not a socket");
        }
        if (someoneListens(addr)) {
            DT_LOG(Socket, Error,
                   "Failed to create control socket %s: another process listens "
                   "on it",
                   pathText.c_str());
            return unexpected(Errc::Busy, "Another process listens on the socket path");
        }
        DT_LOG(Socket, Info, "Removing stale socket %s", pathText.c_str());
        ::unlink(pathText.c_str());
    }

    UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd)
        return unexpected(Errc::Io, "Failed to create a Unix socket", errno);
    DT_TRY(bindWithMode(fd, addr, pathText, options.mode));
    // Only the socket bind() made may be removed at the end: a file found there now in its place
    // (swapped in by a user who may write to the folder) is refused, and left alone.
    if (::lstat(pathText.c_str(), &st) != 0 || !S_ISSOCK(st.st_mode)) {
        DT_LOG(Socket, Error, "Failed to create control socket %s: the socket file was replaced",
               pathText.c_str());
        return unexpected(Errc::InvalidArgument, "The socket file was replaced after bind()");
    }
    if (::listen(fd.get(), kBacklog) != 0) {
        const int err = errno;
        ::unlink(pathText.c_str());
        return unexpected(Errc::Io, "Failed to listen on the Unix socket", err);
    }
    std::unique_ptr<UnixSocketServer> server(
        new UnixSocketServer(pathText, handler, options, std::move(fd)));
    server->inode_ = static_cast<std::uint64_t>(st.st_ino);
    DT_LOG(Socket, Info, "Listening on %s (mode %03o)", pathText.c_str(), options.mode);
    return server;
}

UnixSocketServer::UnixSocketServer(std::string path, Handler &handler,
                                   UnixSocketServerOptions options, UniqueFd fd) noexcept
    : path_(std::move(path)), handler_(handler), options_(options), listenFd_(std::move(fd)),
      spareFd_(openSpareFd())
{
}

UnixSocketServer::~UnixSocketServer()
{
    clients_.clear();
    listenFd_.reset();
    // Remove the file only if it is still the one this server created.
    struct stat st {};
    if (::lstat(path_.c_str(), &st) == 0 && S_ISSOCK(st.st_mode) &&
        static_cast<std::uint64_t>(st.st_ino) == inode_)
        ::unlink(path_.c_str());
}

std::size_t UnixSocketServer::clientCount() const noexcept
{
    return static_cast<std::size_t>(std::count_if(clients_.begin(), clients_.end(),
                                                  [](const auto &c) { return !c.second.closing; }));
}

Result<void> UnixSocketServer::poll(Duration timeout)
{
    std::vector<pollfd> fds;
    std::vector<ClientId> ids;
    fds.reserve(clients_.size() + 1);
    ids.reserve(clients_.size());
    // While accepting is paused (it failed for want of resources), the listening socket is left
    // out: its pending connections would otherwise wake every poll at once.
    Duration wait = std::max(timeout, Duration{});
    bool listening = true;
    if (acceptPausedUntil_ != TimePoint{}) {
        if (!spareFd_)
            spareFd_ = openSpareFd();
        const TimePoint now = SteadyClock::instance().now();
        listening = now >= acceptPausedUntil_;
        if (listening)
            acceptPausedUntil_ = TimePoint{};
        else
            wait = std::min(wait, acceptPausedUntil_ - now);
    }
    fds.push_back({listening ? listenFd_.get() : -1, POLLIN, 0});
    for (const auto &[id, c] : clients_) {
        short events = POLLIN;
        if (!c.out.empty())
            events = static_cast<short>(events | POLLOUT);
        fds.push_back({c.fd.get(), events, 0});
        ids.push_back(id);
    }
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(wait);
    const int timeoutMs = static_cast<int>(std::min<std::int64_t>(ms.count(), 60'000));
    const int n = ::poll(fds.data(), fds.size(), timeoutMs);
    if (n < 0) {
        if (errno == EINTR)
            return ok();
        return unexpected(Errc::Io, "poll() on the control socket failed", errno);
    }
    // Connections first: a client whose connect() returned before another client sent a command
    // is a client when that command's events go out (an mpv UI connects a second socket to watch
    // for the events of the command it sends next, as node-mpv does).
    if ((fds[0].revents & POLLIN) != 0)
        acceptAll();
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const short re = fds[i + 1].revents;
        if (re == 0)
            continue;
        const auto it = clients_.find(ids[i]);
        if (it == clients_.end() || it->second.closing)
            continue;
        if ((re & (POLLIN | POLLHUP | POLLERR)) != 0)
            readFrom(it->first, it->second);
        if ((re & POLLOUT) != 0 && !it->second.closing)
            flush(it->second);
    }
    removeClosing();
    return ok();
}

void UnixSocketServer::acceptAll()
{
    for (;;) {
        UniqueFd fd(::accept4(listenFd_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
        if (!fd) {
            const int err = errno;
            if (err == EAGAIN || err == EWOULDBLOCK || err == EINTR)
                return;
            if (err == ECONNABORTED)
                continue;
            if ((err == EMFILE || err == ENFILE) && spareFd_) {
                if (!refuseOnSpareFd())
                    return;
                continue;
            }
            DT_LOG(Socket, Warning, "Failed to accept a connection: %s", std::strerror(err));
            pauseAccepting();
            return;
        }
        outOfFds_ = false;
        if (clientCount() >= options_.maxClients && !evictStalled()) {
            DT_LOG(Socket, Warning, "Refused a connection to %s: %zu clients already",
                   path_.c_str(), options_.maxClients);
            continue; // fd closes here
        }
        const ClientId id = nextId_++;
        Client &c = clients_[id];
        c.fd = std::move(fd);
        c.lastLine = ++activity_;
        DT_LOG(Socket, Debug, "Client %llu connected", static_cast<unsigned long long>(id));
        handler_.onConnect(id);
    }
}

bool UnixSocketServer::refuseOnSpareFd()
{
    if (!outOfFds_)
        DT_LOG(Socket, Warning, "Refusing connections to %s: no file descriptor left",
               path_.c_str());
    outOfFds_ = true;
    spareFd_.reset();
    UniqueFd fd(::accept4(listenFd_.get(), nullptr, nullptr, SOCK_CLOEXEC));
    const int err = errno;
    const bool accepted = fd.isValid();
    fd.reset(); // the connection closes at once: its client sees the end of the stream
    spareFd_ = openSpareFd();
    if (accepted || err == ECONNABORTED)
        return true;
    if (err != EAGAIN && err != EWOULDBLOCK && err != EINTR)
        pauseAccepting(); // even the spare descriptor's slot was taken (ENFILE)
    return false;
}

void UnixSocketServer::pauseAccepting() noexcept
{
    acceptPausedUntil_ = SteadyClock::instance().now() + kAcceptPause;
}

bool UnixSocketServer::evictStalled()
{
    // Clients that hold half a line and send no more would otherwise keep every place: the one
    // whose last whole line (or connection) is oldest gives its place to the new connection.
    // Clients that wait with nothing pending (subscribers to the events) keep theirs.
    auto stalled = clients_.end();
    for (auto it = clients_.begin(); it != clients_.end(); ++it) {
        const Client &c = it->second;
        if (!c.closing && (!c.in.empty() || c.discarding) &&
            (stalled == clients_.end() || c.lastLine < stalled->second.lastLine))
            stalled = it;
    }
    if (stalled == clients_.end())
        return false;
    DT_LOG(Socket, Warning,
           "Dropping client %llu of %s: it holds part of a line, and %zu clients "
           "are the most",
           static_cast<unsigned long long>(stalled->first), path_.c_str(), options_.maxClients);
    stalled->second.closing = true;
    return true;
}

void UnixSocketServer::readFrom(ClientId id, Client &client)
{
    char buf[kReadChunk];
    std::size_t budget = kReadBudget;
    while (budget > 0 && !client.closing) {
        const ssize_t n = ::recv(client.fd.get(), buf, sizeof buf, 0);
        if (n > 0) {
            consume(id, client, buf, static_cast<std::size_t>(n));
            budget -= std::min(budget, static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return;
        if (n < 0 && errno == EINTR)
            continue;
        // 0: the peer closed; < 0: a connection error. An incomplete line is dropped.
        client.closing = true;
        return;
    }
}

void UnixSocketServer::consume(ClientId id, Client &client, const char *data, std::size_t size)
{
    std::size_t pos = 0;
    while (pos < size && !client.closing) {
        const char *nl = static_cast<const char *>(std::memchr(data + pos, '\n', size - pos));
        const std::size_t end = nl != nullptr ? static_cast<std::size_t>(nl - data) : size;
        if (client.discarding) {
            if (nl != nullptr)
                client.discarding = false;
            pos = nl != nullptr ? end + 1 : size;
            continue;
        }
        const std::size_t piece = end - pos;
        if (client.in.size() + piece > options_.maxLineBytes + 1) {
            // Over the limit even if the last byte is a '\r' that will be dropped.
            client.in.clear();
            client.discarding = nl == nullptr;
            handler_.onLineTooLong(id);
            pos = nl != nullptr ? end + 1 : size;
            continue;
        }
        client.in.append(data + pos, piece);
        pos = end;
        if (nl == nullptr)
            break;
        ++pos;
        std::string line;
        line.swap(client.in);
        client.lastLine = ++activity_;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.size() > options_.maxLineBytes) {
            handler_.onLineTooLong(id);
            continue;
        }
        handler_.onLine(id, line);
    }
}

bool UnixSocketServer::send(ClientId id, std::string_view data)
{
    const auto it = clients_.find(id);
    if (it == clients_.end() || it->second.closing)
        return false;
    Client &c = it->second;
    if (c.out.size() + data.size() > options_.maxQueuedBytes) {
        DT_LOG(Socket, Warning, "Dropping client %llu: it does not read its replies",
               static_cast<unsigned long long>(id));
        c.closing = true;
        return false;
    }
    c.out.append(data);
    flush(c);
    return !c.closing;
}

void UnixSocketServer::broadcast(std::string_view data)
{
    for (auto &[id, c] : clients_)
        if (!c.closing)
            send(id, data);
}

void UnixSocketServer::disconnect(ClientId id)
{
    const auto it = clients_.find(id);
    if (it != clients_.end())
        it->second.closing = true;
}

void UnixSocketServer::flush(Client &client)
{
    while (!client.out.empty()) {
        const ssize_t n =
            ::send(client.fd.get(), client.out.data(), client.out.size(), MSG_NOSIGNAL);
        if (n > 0) {
            client.out.erase(0, static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return;
        client.closing = true; // EPIPE, ECONNRESET: the peer is gone
        return;
    }
}

void UnixSocketServer::removeClosing()
{
    for (auto it = clients_.begin(); it != clients_.end();) {
        if (it->second.closing) {
            const ClientId id = it->first;
            it = clients_.erase(it);
            DT_LOG(Socket, Debug, "Client %llu disconnected", static_cast<unsigned long long>(id));
            handler_.onDisconnect(id);
        } else {
            ++it;
        }
    }
}

} // namespace depthtouch::platform
