#pragma once
/// \file
/// \brief The main thread's input loop: remote keys (any hal::RemoteInput backend) and the control
/// socket, both feeding the one command table of the StateMachine.
///
/// The loop alternates: it serves the socket without waiting, then waits for a key until the end
/// of a slice (default 20 ms), so a socket command waits at most one slice. When the remote goes
/// away (NoDevice) or fails, the loop logs it once and goes on with the socket alone.
/// Thread-safety: thread-bound (the main thread, with the StateMachine).
///
/// Wiring in a player's main thread (the pipeline implements player::PlayerActions and reports
/// back through the StateMachine's notifications):
/// \code
///   player::StateMachine machine(pipeline, settings);            // settings.url = FILE
///   auto remote = drivers::createRemoteInput(remoteNames, cfg);  // evdev, tty, mock, none
///   std::unique_ptr<control::ControlServer> server;
///   if (!controlPath.empty())
///       server = std::move(*control::ControlServer::create(controlPath, machine));
///   control::ControlLoop loop(machine, remote ? remote->get() : nullptr, server.get(), clock);
///   machine.execute("play");
///   while (!machine.quitRequested()) {
///       loop.runUntil(clock.now() + std::chrono::milliseconds(20));
///       if (pipeline.opened()) machine.onOpened();          // or onOpenFailed(reason)
///       if (pipeline.endOfStream()) machine.onEndOfStream();
///       if (pipeline.failed()) machine.onFailure(pipeline.reason());
///   }
/// \endcode

#include <cstddef>

#include "depthtouch/control/control_server.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::control {

/// Counters of a ControlLoop.
struct ControlLoopStats {
    std::size_t keys = 0;            ///< Key events received.
    std::size_t keyCommands = 0;     ///< Commands sent by keys.
    std::size_t refused = 0;         ///< Key commands the machine refused.
    bool remoteLost = false;         ///< The remote reported NoDevice or Io.
};

/// \brief Routes remote keys and socket commands to a StateMachine.
class ControlLoop {
public:
    /// \param[in] machine The state machine. \param[in] remote Remote keys, or nullptr.
    /// \param[in] server The control socket, or nullptr. \param[in] clock The remote's clock.
    /// All must outlive the loop. The machine's remote-connected follows \a remote (set now and
    /// after each poll: hal::RemoteInput::awaitingDevice(), false once lost).
    ControlLoop(player::StateMachine &machine, hal::RemoteInput *remote, ControlServer *server,
                platform::Clock &clock, platform::Duration slice = std::chrono::milliseconds(20));

    /// \brief Handles input until \a until (on \a clock) or until quit was accepted.
    /// \return ok. Errors: Io when the control socket's poll() fails.
    Result<void> runUntil(platform::TimePoint until);

    /// \brief Serves no control socket from now on (the remote goes on): called before the socket
    /// given at construction is closed, as after it failed.
    void detachServer() noexcept { server_ = nullptr; }

    [[nodiscard]] const ControlLoopStats &stats() const noexcept { return stats_; }

private:
    void handleKey(const hal::KeyEvent &event);

    player::StateMachine &machine_;
    hal::RemoteInput *remote_;
    ControlServer *server_;
    platform::Clock &clock_;
    platform::Duration slice_;
    ControlLoopStats stats_;
};

/// \brief Runs a ControlLoop until quit is accepted (or the socket fails): the simplest wiring
/// of a player's main thread.
Result<void> runControlLoop(player::StateMachine &machine, hal::RemoteInput *remote,
                            ControlServer *server, platform::Clock &clock);

} // namespace depthtouch::control
