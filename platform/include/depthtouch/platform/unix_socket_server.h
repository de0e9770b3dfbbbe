#pragma once
/// \file
/// \brief UnixSocketServer: a line-oriented Unix-domain stream socket server driven by poll(), for
/// local control protocols (one request per line, replies and pushed events as lines).
///
/// The socket file is created with the given mode (default 0600: the owner only; set through the
/// umask around bind(), never by a chmod by path that a symlink swapped in could redirect) and
/// removed when the server is destroyed. A stale socket file left by a dead process is replaced; a
/// socket some live process still listens on, or a path that is not a socket, is refused.
///
/// Lines: bytes up to '\n' (a trailing '\r' is dropped). A line longer than maxLineBytes is not
/// delivered: the handler's onLineTooLong() is called once and the rest of that line, up to its
/// '\n', is discarded; the connection stays open. Partial lines of a client that disconnects are
/// dropped. Output is queued per client and written without blocking; a client that lets more
/// than maxQueuedBytes pile up (it does not read) is disconnected. When the process has no file
/// descriptor left, new connections are accepted on a spare one kept for that and closed at once
/// (their clients see the end of the stream) rather than left pending to wake every poll.
///
/// Thread-safety: thread-bound (create, poll, send and destroy on one thread). Handler callbacks
/// run inside poll() on that thread; they may call send(), broadcast() and disconnect().
/// Not real-time safe. The header is C++17-clean.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/unique_fd.h"

namespace depthtouch::platform {

/// Limits and file mode of a UnixSocketServer.
struct UnixSocketServerOptions {
    std::size_t maxLineBytes = 4096; ///< Longest line accepted, without its '\n'.
    /// Further connections are closed at once, unless a client that holds part of a line gives
    /// its place (the one whose last whole line is oldest is dropped).
    std::size_t maxClients = 16;
    std::size_t maxQueuedBytes = 256 * 1024; ///< Unsent output per client before it is dropped.
    unsigned mode = 0600;                    ///< Permission bits of the socket file.
};

/// \brief A Unix-domain socket server speaking lines (see the file comment).
class UnixSocketServer {
public:
    /// Identifies one connection; never reused within a server.
    using ClientId = std::uint64_t;

    /// \brief Receives connections and lines (inside poll()).
    class Handler {
    public:
        virtual ~Handler() = default;
        /// A client connected.
        virtual void onConnect(ClientId client) { (void)client; }
        /// A complete line arrived (without '\n' or '\r'); may contain any byte but '\n'.
        virtual void onLine(ClientId client, std::string_view line) = 0;
        /// A line exceeded maxLineBytes; it is being discarded up to its '\n'.
        virtual void onLineTooLong(ClientId client) = 0;
        /// A client went away (closed, error, dropped for not reading, or disconnect()).
        virtual void onDisconnect(ClientId client) { (void)client; }

    protected:
        Handler() = default;
        DT_DISABLE_COPY_AND_MOVE(Handler)
    };

    /// \brief Creates the socket file at \a path and listens.
    /// \param[in] path File system path (at most 107 bytes).
    /// \param[in] handler Receives the callbacks; must outlive the server.
    /// \return the server. Errors: InvalidArgument (empty or too long path, or the path exists
    /// and is not a socket, or the socket file was replaced right after bind()), Busy (another
    /// process listens there), Io or PermissionDenied (the socket could not be created or bound).
    static Result<std::unique_ptr<UnixSocketServer>> listen(std::string_view path, Handler &handler,
                                                            UnixSocketServerOptions options = {});

    /// Closes every connection and removes the socket file.
    ~UnixSocketServer();

    /// \brief Waits up to \a timeout (real time; zero: do not wait) for activity, then accepts
    /// connections, reads lines (calling the handler) and writes queued output.
    /// \return ok, also when interrupted by a signal. Errors: Io (poll itself failed).
    Result<void> poll(Duration timeout);

    /// \brief Queues \a data for \a client and writes what the socket takes now.
    /// \return false when the client is unknown or was dropped (its queue overflowed).
    bool send(ClientId client, std::string_view data);
    /// Queues \a data for every connected client.
    void broadcast(std::string_view data);
    /// Closes \a client's connection (after the current callback returns).
    void disconnect(ClientId client);

    /// \return the number of connected clients.
    [[nodiscard]] std::size_t clientCount() const noexcept;
    /// \return the socket's path.
    [[nodiscard]] const std::string &path() const noexcept { return path_; }

private:
    struct Client {
        UniqueFd fd;
        std::string in;             ///< Bytes of the current, incomplete line.
        std::string out;            ///< Queued output not yet written.
        bool discarding = false;    ///< Skipping the rest of an over-long line.
        bool closing = false;       ///< Remove at the end of this poll round.
        std::uint64_t lastLine = 0; ///< activity_ at its connection or its last whole line.
    };

    UnixSocketServer(std::string path, Handler &handler, UnixSocketServerOptions options,
                     UniqueFd fd) noexcept;
    void acceptAll();
    /// With no descriptor left (EMFILE): accepts the next pending connection on the spare
    /// descriptor's slot and closes it at once, so it does not stay pending and wake every poll.
    /// \return whether one was refused (more may be pending).
    bool refuseOnSpareFd();
    /// Leaves the listening socket out of poll() for a while (accept() failed for want of
    /// resources and nothing could be refused).
    void pauseAccepting() noexcept;
    /// With every place taken: drops the client that holds part of a line and has sent no whole
    /// line for longest. \return whether a place was freed.
    bool evictStalled();
    void readFrom(ClientId id, Client &client);
    void consume(ClientId id, Client &client, const char *data, std::size_t size);
    void flush(Client &client);
    void removeClosing();

    std::string path_;
    Handler &handler_;
    UnixSocketServerOptions options_;
    UniqueFd listenFd_;
    UniqueFd spareFd_; ///< Kept open to be closed when the process runs out of descriptors.
    TimePoint acceptPausedUntil_{}; ///< Listening socket left out of poll() until then.
    bool outOfFds_ = false;         ///< Connections are being refused (logged once).
    std::uint64_t inode_ = 0; ///< Inode of the socket file created, so only that file is removed.
    std::map<ClientId, Client> clients_;
    ClientId nextId_ = 1;
    std::uint64_t activity_ = 0; ///< Counts connections and whole lines (Client::lastLine).
};

} // namespace depthtouch::platform
