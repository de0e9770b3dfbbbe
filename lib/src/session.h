#pragma once
/// \file
/// \brief What a dt_handle's player thread does for the calls of depthtouch/client.h: commands,
/// property reads and writes and property observers over the state machine, through the control
/// socket's code (control::handleMpvCommand(), player::parseCommandJson()), so that a name, a
/// value and an error mean the same in both; and the player's events turned into dt_events.
/// Reference: libmpv's client API (mpv's client.h) for the error codes and event order
/// (START_FILE, FILE_LOADED, END_FILE with a reason).
/// Thread-safety: thread-bound (the handle's player thread, with the StateMachine).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "depthtouch/client.h"
#include "depthtouch/control/mpv_ipc.h"
#include "depthtouch/player/state_machine.h"
#include "event_queue.h"

namespace depthtouch::client {

/// An observer asked for with dt_observe_property().
struct ObserverSpec {
    std::uint64_t userdata = 0;
    std::string name;
    dt_format format = DT_FORMAT_NONE;
};

/// A property's value in a dt_format.
struct PropertyValue {
    dt_format format = DT_FORMAT_NONE;
    std::string text;
    int flag = 0;
    double number = 0.0;
};

/// \return whether \a name is a property of the control socket (mpv's "loop-file" too).
bool isPropertyName(const std::string &name);

/// \brief The player's side of a handle: its state machine, observers and event queue.
class Session final : public player::PlayerListener {
public:
    Session(player::StateMachine &machine, EventQueue &events);
    ~Session() override;
    Session(const Session &) = delete;
    Session &operator=(const Session &) = delete;

    /// dt_command(): \a args (the name first). \return a dt_error code.
    int command(const std::vector<std::string> &args);
    /// dt_get_property_*(): reads \a name in \a format into \a out. \return a dt_error code.
    int getProperty(const std::string &name, dt_format format, PropertyValue &out);
    /// dt_set_property_*(): sets \a name to \a value (a JSON string, number or bool).
    int setProperty(const std::string &name, const nlohmann::json &value);
    /// dt_observe_property(). \return a dt_error code.
    int observe(const ObserverSpec &spec);
    /// dt_unobserve_property(). \return how many were removed.
    int unobserve(std::uint64_t userdata);
    /// Queues a PROPERTY_CHANGE event for each observed property that changed.
    void sendPropertyChanges();
    /// Queues the events of quitting (END_FILE with reason QUIT while a file is open).
    void onQuit();

private:
    void onPlayerEvent(const player::PlayerEvent &event) override;
    void onStateChanged(player::PlayerState state);
    void endFile(int reason, int error);

    player::StateMachine &machine_;
    EventQueue &events_;
    control::PropertyObservers observers_;
    std::map<std::int64_t, ObserverSpec> specs_; ///< By the observer's id.
    std::int64_t nextId_ = 1;
    bool active_ = false; ///< A file was started and has not ended.
    bool loaded_ = false; ///< It reached Playing or Paused.
    bool eof_ = false;    ///< The stream ended (the next Stopped is END_FILE EOF).
};

} // namespace depthtouch::client
