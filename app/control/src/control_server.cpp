#include "depthtouch/control/control_server.h"

#include <exception>
#include <utility>

#include <nlohmann/json.hpp>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Control)

namespace depthtouch::control {

namespace {

using nlohmann::json;

std::string dump(const json &j)
{
    // Replace invalid UTF-8 rather than throw: a reply must always go out.
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string errorReply(std::string_view reason, const json *requestId = nullptr)
{
    json reply = {{"error", reason}};
    if (requestId != nullptr)
        reply["request_id"] = *requestId;
    return dump(reply);
}

player::PlayerEvent makeIdleEvent()
{
    player::PlayerEvent e;
    e.kind = player::PlayerEventKind::Idle;
    return e;
}

std::string_view trimmed(std::string_view s) noexcept
{
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
        s.remove_suffix(1);
    return s;
}

} // namespace

std::string handleControlLine(std::string_view line, player::StateMachine &machine,
                              PropertyObservers *observers, std::string_view clientName)
{
    const std::string_view text = trimmed(line);
    if (text.empty())
        return {};
    if (text.front() != '{') {
        // A plain text command, e.g. "seek -10".
        const player::CommandOutcome out = machine.execute(text);
        if (!out.accepted)
            return errorReply(out.reason);
        json reply = {{"error", "success"}};
        if (!std::holds_alternative<std::monostate>(out.data))
            reply["data"] = valueJson(out.data);
        return dump(reply);
    }

    json request;
    try {
        request = json::parse(text);
    } catch (const json::parse_error &e) {
        return errorReply("malformed JSON at byte " + std::to_string(e.byte));
    } catch (const json::exception &) {
        // out_of_range.406: a number beyond a double's range (1e400); the parser's message would
        // quote the request, so the reply names the problem only.
        return errorReply("malformed JSON: a number is out of range");
    }
    if (!request.is_object())
        return errorReply("a request must be a JSON object");
    const auto idIt = request.find("request_id");
    const json *requestId = idIt != request.end() ? &*idIt : nullptr;
    const auto cmdIt = request.find("command");
    if (cmdIt == request.end())
        return errorReply("missing \"command\"", requestId);

    if (std::optional<std::string> mpv =
            handleMpvCommand(*cmdIt, requestId, machine, observers, clientName))
        return std::move(*mpv);
    const player::ParsedCommand parsed = player::parseCommandJson(*cmdIt);
    if (!parsed)
        return errorReply(parsed.error, requestId);
    const player::CommandOutcome out = machine.execute(*parsed.command);
    if (!out.accepted)
        return errorReply(out.reason, requestId);
    json reply = {{"error", "success"}};
    if (!std::holds_alternative<std::monostate>(out.data))
        reply["data"] = valueJson(out.data);
    if (requestId != nullptr)
        reply["request_id"] = *requestId;
    return dump(reply);
}

std::string eventJson(const player::PlayerEvent &event)
{
    json j = {{"event", player::playerEventName(event.kind)}};
    switch (event.kind) {
    case player::PlayerEventKind::StateChanged:
        j["data"] = player::playerStateName(event.state);
        break;
    case player::PlayerEventKind::StereoModeChanged:
        j["data"] = player::stereoModeName(event.stereoMode);
        break;
    case player::PlayerEventKind::HapticsChanged:
        j["data"] = event.haptics;
        break;
    case player::PlayerEventKind::StiffnessChanged:
        j["data"] = event.stiffness;
        break;
    case player::PlayerEventKind::LoopChanged:
        j["data"] = event.loop;
        break;
    case player::PlayerEventKind::EndOfFile:
        return {}; // told by the file's end-file (reason eof, data eof or silent)
    case player::PlayerEventKind::Error:
        j["data"] = event.message;
        break;
    case player::PlayerEventKind::StartFile:
        j["playlist_entry_id"] = event.playlistEntryId;
        break;
    case player::PlayerEventKind::FileEnded:
        j["reason"] = event.message;
        j["playlist_entry_id"] = event.playlistEntryId;
        if (event.message == "error")
            j["file_error"] = event.detail;
        else if (event.message == "eof")
            j["data"] = event.detail; // the player's own: eof, or silent (a live stream)
        break;
    case player::PlayerEventKind::Seeked:
    case player::PlayerEventKind::Quit:
    case player::PlayerEventKind::FileLoaded:
    case player::PlayerEventKind::PlaybackRestart:
    case player::PlayerEventKind::Idle:
        break;
    }
    return dump(j);
}

Result<std::unique_ptr<ControlServer>>
ControlServer::create(std::string_view path, player::StateMachine &machine,
                      platform::UnixSocketServerOptions options)
{
    std::unique_ptr<ControlServer> control(new ControlServer(machine));
    auto server = platform::UnixSocketServer::listen(path, *control, options);
    if (!server)
        return unexpected(server.error());
    control->server_ = std::move(*server);
    control->maxLineBytes_ = options.maxLineBytes;
    machine.addListener(control.get());
    return control;
}

ControlServer::ControlServer(player::StateMachine &machine) noexcept : machine_(machine) {}

ControlServer::~ControlServer()
{
    machine_.removeListener(this);
}

void ControlServer::onLine(platform::UnixSocketServer::ClientId client, std::string_view line)
{
    std::string reply;
    try {
        // mpv names its IPC clients ipc-0, ipc-1, ... (client_name).
        reply =
            handleControlLine(line, machine_, &observers_[client], "ipc-" + std::to_string(client));
    } catch (const std::exception &e) {
        // Nothing a client sends may end the player: the client gets the reason instead.
        DT_LOG(Control, Error, "Control line failed: %s", e.what());
        reply = errorReply("the command failed: " + std::string(e.what()));
    }
    if (reply.empty())
        return;
    reply += '\n';
    server_->send(client, reply);
}

void ControlServer::onLineTooLong(platform::UnixSocketServer::ClientId client)
{
    DT_LOG(Control, Warning, "Discarding a control line longer than %zu bytes", maxLineBytes_);
    server_->send(client,
                  errorReply("line too long (limit " + std::to_string(maxLineBytes_) + " bytes)") +
                      "\n");
}

void ControlServer::onConnect(platform::UnixSocketServer::ClientId client)
{
    // A player started idle with no file (play --idle) says so to a client that connects, as mpv
    // started with --idle does to the clients that connect as it starts: node-mpv waits for it.
    if (machine_.url().empty() && machine_.state() == player::PlayerState::Idle)
        server_->send(client, eventJson(makeIdleEvent()) + "\n");
}

void ControlServer::onDisconnect(platform::UnixSocketServer::ClientId client)
{
    observers_.erase(client);
}

Result<void> ControlServer::poll(platform::Duration timeout)
{
    DT_TRY(server_->poll(timeout));
    std::vector<std::string> lines;
    for (auto &[client, observers] : observers_) {
        lines.clear();
        propertyChanges(machine_, observers, lines);
        for (std::string &line : lines)
            server_->send(client, line += '\n');
    }
    return {};
}

void ControlServer::onPlayerEvent(const player::PlayerEvent &event)
{
    std::string line = eventJson(event);
    if (server_ && !line.empty())
        server_->broadcast(line += '\n');
}

} // namespace depthtouch::control
