#pragma once
/// \file
/// \brief The player's control socket: JSON lines over a Unix-domain socket, in the spirit of
/// mpv's JSON IPC, so integrators can drive the player from any language.
///
/// Protocol (one request per line, one reply per request, events pushed to every client; mpv's
/// verbs get_property, set_property, observe_property, cycle, add, keypress as mpv_ipc.h says):
/// - Request: `{"command": ["seek", 10], "request_id": 7}`; "request_id" is optional (any JSON
///   value, echoed in the reply). A line that does not start with '{' is a text command, e.g.
///   `seek -10` or `toggle-pause`. Empty lines are ignored (no reply).
/// - Reply: `{"error": "success"}`, with `"data"` for queries (`["get", "state"]` →
///   `{"data": "paused", "error": "success"}`); a refusal or a bad request: `{"error":
///   "<reason>"}`.
/// - Events, to every client: `{"event": "state", "data": "paused"}`; names and data:
///   state (state name), stereo-mode (mode name), haptics (bool), stiffness (N/m), loop (bool),
///   seek (also a loop's restart), error (reason), shutdown, and mpv's file events: start-file
///   and end-file (with playlist_entry_id; end-file with reason eof, stop, quit or error, with
///   file_error for error and data "eof" or "silent" for eof), file-loaded, playback-restart
///   (after file-loaded and each seek), idle (also to a client that connects while the player is
///   idle with nothing current). Events caused by a command are sent before its reply.
/// - Limits: a line longer than maxLineBytes (4 KiB) is answered with
///   `{"error": "line too long (limit 4096 bytes)"}` and discarded up to its newline; the
///   connection stays open. Malformed JSON and binary input are answered with an error and never
///   end the connection or the player.
///
/// Thread-safety: thread-bound (the thread of the StateMachine).

#include <map>
#include <memory>
#include <string>
#include <string_view>

#include "depthtouch/control/mpv_ipc.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/unix_socket_server.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::control {

/// \brief Handles one request line. \return the reply line without '\n', or an empty string for
/// an empty line (no reply).
/// mpv's verbs (mpv_ipc.h) are answered as mpv does; \a observers are the sending client's
/// observed properties (nullptr: none can be observed).
/// \a clientName is what client_name answers.
std::string handleControlLine(std::string_view line, player::StateMachine &machine,
                              PropertyObservers *observers = nullptr,
                              std::string_view clientName = "ipc");

/// \return the JSON event line (without '\n') of \a event; empty for EndOfFile, which the
/// file's end-file tells.
std::string eventJson(const player::PlayerEvent &event);

/// \brief The control socket server: a UnixSocketServer speaking the protocol above to a
/// StateMachine, and broadcasting its events.
class ControlServer final : private platform::UnixSocketServer::Handler,
                            private player::PlayerListener {
public:
    /// \brief Creates the socket at \a path (mode 0600) and subscribes to \a machine's events.
    /// \return the server. Errors: as platform::UnixSocketServer::listen().
    static Result<std::unique_ptr<ControlServer>>
    create(std::string_view path, player::StateMachine &machine,
           platform::UnixSocketServerOptions options = {});

    /// Unsubscribes, closes every client and removes the socket file.
    ~ControlServer() override;

    /// \brief Serves clients for up to \a timeout (real time; zero: handle what is pending), then
    /// sends each client's observed properties that changed (property-change events).
    Result<void> poll(platform::Duration timeout);

    [[nodiscard]] std::size_t clientCount() const noexcept { return server_->clientCount(); }
    [[nodiscard]] const std::string &path() const noexcept { return server_->path(); }

private:
    explicit ControlServer(player::StateMachine &machine) noexcept;

    void onConnect(platform::UnixSocketServer::ClientId client) override;
    void onLine(platform::UnixSocketServer::ClientId client, std::string_view line) override;
    void onLineTooLong(platform::UnixSocketServer::ClientId client) override;
    void onDisconnect(platform::UnixSocketServer::ClientId client) override;
    void onPlayerEvent(const player::PlayerEvent &event) override;

    player::StateMachine &machine_;
    std::unique_ptr<platform::UnixSocketServer> server_;
    std::size_t maxLineBytes_ = 0;
    /// Each client's observe_property list (removed when it disconnects).
    std::map<platform::UnixSocketServer::ClientId, PropertyObservers> observers_;
};

} // namespace depthtouch::control
