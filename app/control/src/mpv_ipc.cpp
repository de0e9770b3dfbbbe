#include "depthtouch/control/mpv_ipc.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "depthtouch/hal/remote_input.h"
#include "depthtouch/player/key_bindings.h"

namespace depthtouch::control {

namespace {

using nlohmann::json;
using player::Property;

// mpv's error texts (mpv's client.h, mpv_error_string()).
constexpr const char *kNotFound = "property not found";
constexpr const char *kUnavailable = "property unavailable";
constexpr const char *kFormat = "unsupported format for accessing property";
constexpr const char *kInvalid = "invalid parameter";

std::string dump(const json &j)
{
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string reply(const char *error, const json *requestId, const json *data = nullptr)
{
    json r = {{"error", error}};
    if (data != nullptr)
        r["data"] = *data;
    if (requestId != nullptr)
        r["request_id"] = *requestId;
    return dump(r);
}

std::string reply(const std::string &error, const json *requestId)
{
    return reply(error.c_str(), requestId);
}

/// \a value of \a property as JSON: mpv's integer properties (playlist-count, playlist-pos,
/// playlist-pos-1) as integers, the others as valueJson() says.
json propertyJson(Property property, const player::Value &value)
{
    const double *d = std::get_if<double>(&value);
    if (d != nullptr && (property == Property::PlaylistCount || property == Property::PlaylistPos ||
                         property == Property::PlaylistPos1))
        return static_cast<std::int64_t>(std::llround(*d));
    return valueJson(value);
}

/// A property as a client names it: mpv's "loop-file" is the player's loop, as "inf" or "no".
struct Named {
    Property property = Property::State;
    bool loopFile = false;
};

std::optional<Named> propertyNamed(const json &name)
{
    if (!name.is_string())
        return std::nullopt;
    const std::string &text = name.get_ref<const std::string &>();
    if (text == "loop-file")
        return Named{Property::Loop, true};
    if (const std::optional<Property> p = player::propertyFromName(text))
        return Named{*p, false};
    return std::nullopt;
}

/// A command's property argument: the property it names, or the reply that refuses the command.
struct PropertyArgument {
    std::optional<Named> named;
    std::string refusal; ///< mpv's reply, when named is empty.
};

/// \return the property that element \a at of \a command names, or the refusal mpv replies:
/// "invalid parameter" when \a wellFormed is false (the caller's count and type checks of
/// \a command), "property not found" for a name that is no property.
PropertyArgument propertyArgument(const json &command, std::size_t at, bool wellFormed,
                                  const json *requestId)
{
    if (!wellFormed)
        return {std::nullopt, reply(kInvalid, requestId)};
    const std::optional<Named> named = propertyNamed(command[at]);
    if (!named)
        return {std::nullopt, reply(kNotFound, requestId)};
    return {named, {}};
}

/// The value of \a named now, or the reason there is none ("property unavailable").
player::CommandOutcome read(player::StateMachine &machine, const Named &named)
{
    player::Command get;
    get.id = player::CommandId::Get;
    get.property = named.property;
    player::CommandOutcome out = machine.execute(get);
    if (out.accepted && named.loopFile && std::holds_alternative<bool>(out.data))
        out.data = std::string(std::get<bool>(out.data) ? "inf" : "no");
    return out;
}

/// mpv's string form of a value: yes/no, a number with six decimals, or the text.
std::string asMpvString(const player::Value &value)
{
    if (const bool *b = std::get_if<bool>(&value))
        return *b ? "yes" : "no";
    if (const double *d = std::get_if<double>(&value)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.6f", *d);
        return buf;
    }
    if (const std::string *s = std::get_if<std::string>(&value))
        return *s;
    return {};
}

/// \a value as a flag: a JSON bool, or (from set_property_string) yes/no/true/false/inf.
std::optional<bool> flag(const json &value)
{
    if (value.is_boolean())
        return value.get<bool>();
    if (value.is_string()) {
        const std::string &s = value.get_ref<const std::string &>();
        if (s == "yes" || s == "true" || s == "inf")
            return true;
        if (s == "no" || s == "false")
            return false;
    }
    return std::nullopt;
}

/// \a value as a finite number: a JSON number, or (from set_property_string) its text.
std::optional<double> number(const json &value)
{
    double v = std::numeric_limits<double>::quiet_NaN();
    if (value.is_number())
        v = value.get<double>();
    else if (value.is_string()) {
        const std::string &s = value.get_ref<const std::string &>();
        char *end = nullptr;
        v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size())
            return std::nullopt;
    }
    if (!std::isfinite(v))
        return std::nullopt;
    return v;
}

/// \return the player command text that sets \a named to \a value, "" when the value does not fit
/// (kFormat), or nullopt when the property cannot be set (kUnavailable).
std::optional<std::string> setterText(player::StateMachine &machine, const Named &named,
                                      const json &value)
{
    char buf[96];
    switch (named.property) {
    case Property::Pause: {
        const std::optional<bool> on = flag(value);
        return on ? std::string(*on ? "pause" : "play") : std::string();
    }
    case Property::Haptics:
    case Property::Loop: {
        const std::optional<bool> on = flag(value);
        if (!on)
            return std::string();
        return std::string(named.property == Property::Haptics ? "haptics " : "loop ") +
               (*on ? "on" : "off");
    }
    case Property::StereoMode:
        return value.is_string() ? "stereo-mode " + value.get<std::string>() : std::string();
    case Property::Mute: {
        const std::optional<bool> on = flag(value);
        return on ? std::string(*on ? "mute on" : "mute off") : std::string();
    }
    case Property::Volume:
    case Property::Stiffness:
    case Property::TimePos:
    case Property::PlaybackTime:
    case Property::PercentPos: {
        const std::optional<double> v = number(value);
        if (!v)
            return std::string();
        if (named.property == Property::Stiffness)
            std::snprintf(buf, sizeof buf, "stiffness %.17g", *v);
        else if (named.property == Property::Volume)
            std::snprintf(buf, sizeof buf, "volume %.17g", *v);
        else if (named.property != Property::PercentPos) // time-pos, playback-time
            std::snprintf(buf, sizeof buf, "seek %.17g absolute", std::max(0.0, *v));
        else {
            const player::CommandOutcome d = read(machine, Named{Property::Duration, false});
            if (!d.accepted || !std::holds_alternative<double>(d.data))
                return std::nullopt;
            const double duration = std::get<double>(d.data);
            std::snprintf(buf, sizeof buf, "seek %.17g absolute",
                          std::clamp(*v, 0.0, 100.0) / 100.0 * duration);
        }
        return std::string(buf);
    }
    default: // read-only
        return std::nullopt;
    }
}

std::string run(player::StateMachine &machine, const std::string &text, const json *requestId)
{
    const player::CommandOutcome out = machine.execute(text);
    return out.accepted ? reply("success", requestId) : reply(out.reason, requestId);
}

std::string getProperty(const json &command, const json *requestId, player::StateMachine &machine,
                        bool asString)
{
    const PropertyArgument arg = propertyArgument(command, 1, command.size() == 2, requestId);
    if (!arg.named)
        return arg.refusal;
    const player::CommandOutcome out = read(machine, *arg.named);
    if (!out.accepted)
        return reply(out.reason, requestId);
    const json data =
        asString ? json(asMpvString(out.data)) : propertyJson(arg.named->property, out.data);
    return reply("success", requestId, &data);
}

/// \return whether the flag property \a named (pause) already has \a value: mpv answers success for
/// `set_property pause false` while playing, where the player's `play` command would be refused.
bool alreadySet(player::StateMachine &machine, const Named &named, const json &value)
{
    if (named.property != Property::Pause)
        return false;
    const std::optional<bool> on = flag(value);
    const player::CommandOutcome now = read(machine, named);
    return on && now.accepted && std::holds_alternative<bool>(now.data) &&
           std::get<bool>(now.data) == *on;
}

std::string setProperty(const json &command, const json *requestId, player::StateMachine &machine,
                        bool fromString)
{
    const PropertyArgument arg = propertyArgument(command, 1, command.size() == 3, requestId);
    if (!arg.named)
        return arg.refusal;
    if (fromString && !command[2].is_string())
        return reply(kFormat, requestId);
    const std::optional<std::string> text = setterText(machine, *arg.named, command[2]);
    if (!text)
        return reply(kUnavailable, requestId);
    if (text->empty())
        return reply(kFormat, requestId);
    if (alreadySet(machine, *arg.named, command[2]))
        return reply("success", requestId);
    return run(machine, *text, requestId);
}

/// mpv's `cycle NAME [up|down]` and `add NAME [N]`: the command table's rows of those names
/// (player::mpvCommandAliases()), with mpv's errors: "property not found" for a name that is no
/// property, "unsupported format for accessing property" for add's value that is no number,
/// "property unavailable" for one that does not cycle or add (read-only).
std::string cycleOrAdd(const json &command, const json *requestId, player::StateMachine &machine)
{
    const bool add = command[0] == "add";
    const PropertyArgument arg =
        propertyArgument(command, 1, command.size() == 2 || command.size() == 3, requestId);
    if (!arg.named)
        return arg.refusal;
    if (add && command.size() == 3 && !number(command[2]))
        return reply(kFormat, requestId);
    const player::ParsedCommand parsed = player::parseCommandJson(command);
    if (!parsed)
        return reply(kUnavailable, requestId);
    const player::CommandOutcome out = machine.execute(*parsed.command);
    return out.accepted ? reply("success", requestId) : reply(out.reason, requestId);
}

/// mpv's client API version (MPV_CLIENT_API_VERSION of mpv 0.38's client.h: MPV_MAKE_VERSION(2,
/// 3), major << 16 | minor), which get_version answers.
constexpr std::int64_t kMpvClientApiVersion = (2 << 16) | 3;

std::string keypress(const json &command, const json *requestId, player::StateMachine &machine)
{
    if (command.size() != 2 || !command[1].is_string())
        return reply(kInvalid, requestId);
    // The names of input.conf (player::keyFromInputName()): the kernel's (KEY_PLAYPAUSE, KEY_ESC),
    // mpv's (VOLUME_UP, SPACE, PGUP) and the terminal's characters (m).
    const hal::Key key = player::keyFromInputName(command[1].get_ref<const std::string &>());
    if (key == hal::Key::Unknown)
        return reply(kInvalid, requestId);
    const char *text = machine.keyMap().commandText(key);
    if (text == nullptr)
        return reply("success", requestId); // an unbound key does nothing, as in mpv
    return run(machine, text, requestId);
}

std::string observe(const json &command, const json *requestId, PropertyObservers *observers)
{
    const bool wellFormed =
        observers != nullptr && command.size() == 3 && command[1].is_number_integer();
    const PropertyArgument arg = propertyArgument(command, 2, wellFormed, requestId);
    // mpv observes any name (mpv_observe_property "usually fails only on OOM or unsupported
    // format"): one the player does not have is a property that is not available. A UI observes
    // its whole list at start (node-mpv: fullscreen, sub-visibility) and fails on a refusal.
    const bool other = !arg.named && wellFormed && command[2].is_string();
    if (!arg.named && !other)
        return arg.refusal;
    constexpr std::size_t kMaxObservers = 64; // a client cannot grow the player without bound
    if (observers->size() >= kMaxObservers)
        return reply(kInvalid, requestId);
    PropertyObserver o;
    o.id = command[1].get<std::int64_t>();
    if (arg.named) {
        o.property = arg.named->property;
        o.loopFile = arg.named->loopFile;
    } else {
        o.other = command[2].get<std::string>();
    }
    observers->push_back(std::move(o));
    return reply("success", requestId);
}

std::string unobserve(const json &command, const json *requestId, PropertyObservers *observers)
{
    if (observers == nullptr || command.size() != 2 || !command[1].is_number_integer())
        return reply(kInvalid, requestId);
    const std::int64_t id = command[1].get<std::int64_t>();
    const auto gone = std::remove_if(observers->begin(), observers->end(),
                                     [id](const PropertyObserver &o) { return o.id == id; });
    if (gone == observers->end())
        return reply(kInvalid, requestId);
    observers->erase(gone, observers->end());
    return reply("success", requestId);
}

} // namespace

json valueJson(const player::Value &value)
{
    return std::visit(
        [](const auto &v) -> json {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::monostate>)
                return nullptr;
            else
                return v;
        },
        value);
}

std::optional<std::string> handleMpvCommand(const json &command, const json *requestId,
                                            player::StateMachine &machine,
                                            PropertyObservers *observers,
                                            std::string_view clientName)
{
    if (!command.is_array() || command.empty() || !command[0].is_string())
        return std::nullopt;
    const std::string &verb = command[0].get_ref<const std::string &>();
    if (verb == "get_property" || verb == "get_property_string")
        return getProperty(command, requestId, machine, verb == "get_property_string");
    if (verb == "set_property" || verb == "set_property_string")
        return setProperty(command, requestId, machine, verb == "set_property_string");
    if (verb == "cycle" || verb == "add")
        return cycleOrAdd(command, requestId, machine);
    if (verb == "get_version") {
        const json version = kMpvClientApiVersion;
        return command.size() == 1 ? reply("success", requestId, &version)
                                   : reply(kInvalid, requestId);
    }
    if (verb == "client_name") { // mpv: the name of the client sending it ("ipc-0", ...)
        const json name = std::string(clientName);
        return command.size() == 1 ? reply("success", requestId, &name)
                                   : reply(kInvalid, requestId);
    }
    if (verb == "keypress")
        return keypress(command, requestId, machine);
    if (verb == "observe_property" || verb == "observe_property_string")
        return observe(command, requestId, observers);
    if (verb == "unobserve_property")
        return unobserve(command, requestId, observers);
    return std::nullopt;
}

void propertyChanges(player::StateMachine &machine, PropertyObservers &observers,
                     std::vector<std::string> &lines)
{
    for (PropertyObserver &o : observers) {
        if (!o.other.empty()) { // no property of the player: not available, said once
            if (!o.sent)
                lines.push_back(
                    dump(json{{"event", "property-change"}, {"id", o.id}, {"name", o.other}}));
            o.sent = true;
            continue;
        }
        const player::CommandOutcome out = read(machine, Named{o.property, o.loopFile});
        const std::string now =
            out.accepted ? dump(propertyJson(o.property, out.data)) : std::string();
        if (o.sent && now == o.last)
            continue;
        json event = {{"event", "property-change"},
                      {"id", o.id},
                      {"name", o.loopFile ? "loop-file" : player::propertyName(o.property)}};
        if (out.accepted)
            event["data"] = propertyJson(o.property, out.data);
        lines.push_back(dump(event));
        o.last = now;
        o.sent = true;
    }
}

} // namespace depthtouch::control
