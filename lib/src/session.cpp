/// \file
/// \brief The player thread's side of a dt_handle: see session.h.

#include "session.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "depthtouch/player/command.h"

namespace depthtouch::client {

namespace {

using nlohmann::json;

/// The most observers of a handle (as the control socket's per client).
constexpr std::size_t kMaxObservers = 64;

/// \return the dt_error of a control socket reply's "error" text \a error (mpv's texts), or
/// \a refusal for the player's own reason of a refusal.
int codeOfReply(const std::string &error, int refusal)
{
    if (error == "success")
        return DT_ERROR_SUCCESS;
    if (error == "property not found")
        return DT_ERROR_PROPERTY_NOT_FOUND;
    if (error == "property unavailable")
        return DT_ERROR_PROPERTY_UNAVAILABLE;
    if (error == "unsupported format for accessing property")
        return DT_ERROR_PROPERTY_FORMAT;
    if (error == "invalid parameter")
        return DT_ERROR_INVALID_PARAMETER;
    return refusal;
}

/// Runs mpv's verb \a request on \a machine. \return the parsed reply, or nullopt when \a request
/// is no mpv verb.
std::optional<json> mpvReply(const json &request, player::StateMachine &machine,
                             control::PropertyObservers *observers)
{
    const std::optional<std::string> line =
        control::handleMpvCommand(request, nullptr, machine, observers);
    if (!line)
        return std::nullopt;
    return json::parse(*line);
}

/// \return the code of \a reply (refusals: \a refusal).
int replyCode(const json &reply, int refusal)
{
    const auto it = reply.find("error");
    if (it == reply.end() || !it->is_string())
        return DT_ERROR_GENERIC;
    return codeOfReply(it->get<std::string>(), refusal);
}

/// \return \a data as mpv's string form: yes/no, a number with six decimals, or the text.
std::string mpvString(const json &data)
{
    if (data.is_boolean())
        return data.get<bool>() ? "yes" : "no";
    if (data.is_number()) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.6f", data.get<double>());
        return buf;
    }
    if (data.is_string())
        return data.get<std::string>();
    return {};
}

/// Converts \a data (a JSON bool, number or text) to \a format in \a out.
/// \return DT_ERROR_SUCCESS, DT_ERROR_PROPERTY_UNAVAILABLE (null), DT_ERROR_PROPERTY_FORMAT.
int convert(const json &data, dt_format format, PropertyValue &out)
{
    if (data.is_null())
        return DT_ERROR_PROPERTY_UNAVAILABLE;
    PropertyValue v;
    v.format = format;
    switch (format) {
    case DT_FORMAT_STRING:
        if (!data.is_boolean() && !data.is_number() && !data.is_string())
            return DT_ERROR_PROPERTY_FORMAT;
        v.text = mpvString(data);
        break;
    case DT_FORMAT_FLAG:
        if (!data.is_boolean())
            return DT_ERROR_PROPERTY_FORMAT;
        v.flag = data.get<bool>() ? 1 : 0;
        break;
    case DT_FORMAT_DOUBLE:
        if (!data.is_number())
            return DT_ERROR_PROPERTY_FORMAT;
        v.number = data.get<double>();
        break;
    default:
        v.format = DT_FORMAT_NONE;
        break;
    }
    out = std::move(v);
    return DT_ERROR_SUCCESS;
}

/// \return an event of \a id without data.
QueuedEvent eventOf(dt_event_id id)
{
    QueuedEvent e;
    e.id = id;
    return e;
}

} // namespace

bool isPropertyName(const std::string &name)
{
    return name == "loop-file" || player::propertyFromName(name).has_value();
}

Session::Session(player::StateMachine &machine, EventQueue &events)
    : machine_(machine), events_(events)
{
    machine_.addListener(this);
}

Session::~Session()
{
    machine_.removeListener(this);
}

int Session::command(const std::vector<std::string> &args)
{
    if (args.empty())
        return DT_ERROR_INVALID_PARAMETER;
    json request = json::array();
    for (const std::string &a : args)
        request.push_back(a);
    if (args[0] == "observe_property" || args[0] == "observe_property_string" ||
        args[0] == "unobserve_property")
        return DT_ERROR_INVALID_PARAMETER; // dt_observe_property() is the API's way
    if (std::optional<json> reply = mpvReply(request, machine_, nullptr))
        return replyCode(*reply, DT_ERROR_COMMAND);
    const player::ParsedCommand parsed = player::parseCommandJson(request);
    if (!parsed)
        return DT_ERROR_INVALID_PARAMETER;
    return machine_.execute(*parsed.command).accepted ? DT_ERROR_SUCCESS : DT_ERROR_COMMAND;
}

int Session::getProperty(const std::string &name, dt_format format, PropertyValue &out)
{
    const char *verb = format == DT_FORMAT_STRING ? "get_property_string" : "get_property";
    const std::optional<json> reply = mpvReply(json::array({verb, name}), machine_, nullptr);
    if (!reply)
        return DT_ERROR_GENERIC;
    if (const int code = replyCode(*reply, DT_ERROR_PROPERTY_UNAVAILABLE); code < 0)
        return code;
    const auto data = reply->find("data");
    return convert(data == reply->end() ? json() : *data, format, out);
}

int Session::setProperty(const std::string &name, const json &value)
{
    const std::optional<json> reply =
        mpvReply(json::array({"set_property", name, value}), machine_, nullptr);
    if (!reply)
        return DT_ERROR_GENERIC;
    return replyCode(*reply, DT_ERROR_PROPERTY_ERROR);
}

int Session::observe(const ObserverSpec &spec)
{
    if (observers_.size() >= kMaxObservers)
        return DT_ERROR_INVALID_PARAMETER;
    const std::int64_t id = nextId_++;
    const std::optional<json> reply =
        mpvReply(json::array({"observe_property", id, spec.name}), machine_, &observers_);
    if (!reply)
        return DT_ERROR_GENERIC;
    if (const int code = replyCode(*reply, DT_ERROR_INVALID_PARAMETER); code < 0)
        return code;
    specs_[id] = spec;
    return DT_ERROR_SUCCESS;
}

int Session::unobserve(std::uint64_t userdata)
{
    int removed = 0;
    for (auto it = specs_.begin(); it != specs_.end();) {
        if (it->second.userdata != userdata) {
            ++it;
            continue;
        }
        const std::int64_t id = it->first;
        observers_.erase(
            std::remove_if(observers_.begin(), observers_.end(),
                           [id](const control::PropertyObserver &o) { return o.id == id; }),
            observers_.end());
        it = specs_.erase(it);
        ++removed;
    }
    return removed;
}

void Session::sendPropertyChanges()
{
    std::vector<std::string> lines;
    control::propertyChanges(machine_, observers_, lines);
    for (const std::string &line : lines) {
        const json change = json::parse(line);
        const auto spec = specs_.find(change.value("id", std::int64_t{0}));
        if (spec == specs_.end())
            continue;
        QueuedEvent e;
        e.id = DT_EVENT_PROPERTY_CHANGE;
        e.userdata = spec->second.userdata;
        e.name = spec->second.name;
        PropertyValue v;
        const auto data = change.find("data");
        if (data != change.end() && convert(*data, spec->second.format, v) == DT_ERROR_SUCCESS) {
            e.format = v.format;
            e.text = std::move(v.text);
            e.flag = v.flag;
            e.number = v.number;
        }
        events_.push(std::move(e));
    }
}

void Session::endFile(int reason, int error)
{
    QueuedEvent e;
    e.id = DT_EVENT_END_FILE;
    e.endFile.reason = reason;
    e.endFile.error = error;
    events_.push(std::move(e));
    active_ = false;
    loaded_ = false;
    eof_ = false;
}

void Session::onQuit()
{
    if (active_)
        endFile(DT_END_FILE_REASON_QUIT, 0);
}

void Session::onStateChanged(player::PlayerState state)
{
    using player::PlayerState;
    switch (state) {
    case PlayerState::Opening:
        if (active_)
            endFile(DT_END_FILE_REASON_STOP, 0);
        active_ = true;
        events_.push(eventOf(DT_EVENT_START_FILE));
        break;
    case PlayerState::Playing:
    case PlayerState::Paused:
        if (active_ && !loaded_) {
            loaded_ = true;
            events_.push(eventOf(DT_EVENT_FILE_LOADED));
        }
        break;
    case PlayerState::Stopped:
    case PlayerState::Idle:
        if (active_)
            endFile(eof_ ? DT_END_FILE_REASON_EOF : DT_END_FILE_REASON_STOP, 0);
        break;
    case PlayerState::Error:
        if (active_)
            endFile(DT_END_FILE_REASON_ERROR, loaded_ ? DT_ERROR_GENERIC : DT_ERROR_LOADING_FAILED);
        break;
    }
}

void Session::onPlayerEvent(const player::PlayerEvent &event)
{
    switch (event.kind) {
    case player::PlayerEventKind::StateChanged:
        onStateChanged(event.state);
        break;
    case player::PlayerEventKind::EndOfFile:
        if (event.message != "loop")
            eof_ = true;
        break;
    case player::PlayerEventKind::Seeked:
        events_.push(eventOf(DT_EVENT_SEEK));
        break;
    case player::PlayerEventKind::Quit:
        onQuit();
        break;
    default:
        break;
    }
}

} // namespace depthtouch::client
