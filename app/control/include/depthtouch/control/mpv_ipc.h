#pragma once
/// \file
/// \brief mpv's JSON IPC on the control socket: the verbs a UI written for mpv sends
/// (get_property, get_property_string, set_property, set_property_string, observe_property,
/// unobserve_property, cycle, add, keypress, get_version, client_name), answered as mpv answers
/// them, over the player's own properties (player::Property: mpv's time-pos, playback-time,
/// duration, percent-pos, time-remaining, pause, path, filename, media-title, idle-active,
/// eof-reached, volume, mute, playlist-count, playlist-pos, playlist-pos-1, and the player's
/// stereo-mode, haptics, stiffness, haptic-force, contact, loop). mpv's input commands (loadfile,
/// playlist-next, playlist-prev, cycle, add) are rows of the player's one command table.
///
/// Reference: mpv's manual, "JSON IPC" (docs/man/ipc.rst): a request `{"command": ["get_property",
/// "time-pos"], "request_id": 7}` is answered `{"data": 12.5, "error": "success", "request_id":
/// 7}`; errors carry mpv's texts ("property not found", "property unavailable", "unsupported format
/// for accessing property", "invalid parameter"); an observed property sends
/// `{"event": "property-change", "id": 1, "name": "time-pos", "data": 12.5}` when it changes (no
/// "data" while it is unavailable), the first one at once.
///
/// Units: time-pos and duration in s, percent-pos in %, stiffness in N/m, haptic-force in N.
/// Thread-safety: thread-bound (the StateMachine's thread).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "depthtouch/player/state_machine.h"

namespace depthtouch::control {

/// One observe_property of a client: its id, the property, and the value last sent.
struct PropertyObserver {
    std::int64_t id = 0;
    player::Property property = player::Property::State;
    bool loopFile = false; ///< Observed as "loop-file" ("inf"/"no") rather than "loop" (bool).
    /// The name a client observes that is no property of the player ("fullscreen"), else empty:
    /// as mpv's observe_property, which takes any name, it is answered once by a property-change
    /// without "data" (a property that is not available).
    std::string other;
    std::string last;  ///< The "data" last sent, as JSON text ("" before the first event).
    bool sent = false; ///< The first property-change went out.
};

/// The observers of one client (a few: one per property a UI shows).
using PropertyObservers = std::vector<PropertyObserver>;

/// \brief Answers \a command when its first element is one of mpv's verbs above.
/// \param command The request's "command" array.
/// \param requestId The request's "request_id", or nullptr.
/// \param observers The sending client's observers (observe_property adds, unobserve_property
/// removes), or nullptr where there is no client (then observing is refused).
/// \param clientName What client_name answers (mpv's "ipc-N": the sending connection's name).
/// \return the reply line (without '\n'), or std::nullopt when \a command is not an mpv verb.
std::optional<std::string> handleMpvCommand(const nlohmann::json &command,
                                            const nlohmann::json *requestId,
                                            player::StateMachine &machine,
                                            PropertyObservers *observers,
                                            std::string_view clientName = "ipc");

/// \return \a value as JSON: null (nothing), a bool, a number or a text. Reentrant.
nlohmann::json valueJson(const player::Value &value);

/// \brief Appends to \a lines (without '\n') one property-change event per observer of
/// \a observers whose property changed since its last event (or has had none).
void propertyChanges(player::StateMachine &machine, PropertyObservers &observers,
                     std::vector<std::string> &lines);

} // namespace depthtouch::control
