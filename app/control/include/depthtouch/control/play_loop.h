#pragma once
/// \file
/// \brief The player's main loop (`depthtouch play`, libdepthtouch's player thread, the GStreamer
/// element: cli::PlayerCore::run()): the control loop run in turns (10 ms by default) on the
/// player's thread, driving the state machine from its remote, terminal and control socket, until
/// the player quits, ends (unless it idles), a stop flag is set or its duration is over; with the
/// resident and locked memory sampled at the start, after 5 s and at the end. Times in seconds,
/// memory in MiB. Thread-safety: the thread that runs the player (the stop flag may be set from
/// anywhere).

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "depthtouch/control/control_loop.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::control {

/// How the main loop ended.
struct LoopOutcome {
    std::string failure; ///< The reason when the player ended in Error.
    /// Whose failure: the input's (InvalidArgument) or the system's (OutOfResources: a thread
    /// that could not be started), player::StateMachine::errorKind().
    Errc failureKind = Errc::InvalidArgument;
    bool opened = false;         ///< The input played (Playing or Paused was reached).
    bool stoppedOpening = false; ///< The stop flag or the duration came while it was opening.
    bool stopped = false;        ///< The stop flag or the duration ended it (not a quit).
    double rssStart = -1.0;
    double rssAfterWarmup = -1.0;
    double rssEnd = -1.0;
    double lockedMiB = -1.0; ///< Locked memory (VmLck), MiB: the larger of the 5 s and end samples.
};

/// \brief When playUntilDone() ends besides a quit.
struct PlayLimits {
    double duration = 0.0; ///< Play time, s, after which it quits (0: none).
    bool idle = false;     ///< Stay when the player stops or fails (a client may play again).
    /// Send "play" first (`play FILE`); a player that waits for its client's loadfile does not
    /// (libdepthtouch: its file comes by dt_command()).
    bool start = true;
    /// How long each turn's control loop runs before the turn's \a eachTurn; zero: the socket is
    /// served without waiting (a caller whose \a eachTurn waits itself, for its API's calls).
    platform::Duration turn = std::chrono::milliseconds(10);
};

/// Hears that the control socket failed (its poll); the loop goes on without it.
using OnSocketFailure = std::function<void(const Error &)>;

/// \brief Sends "play" (unless \a limits say not), then runs \a loop in turns of \a limits' turn,
/// calling \a eachTurn after each (the pipeline's report to \a machine), until the machine quits,
/// or \a stop or \a limits' duration sends "quit", or the player stops or fails (unless \a limits
/// idle). A control socket that fails is told to \a socketFailed (may be empty), detached from
/// \a loop and closed (\a server reset); the remote goes on. \return how it ended.
LoopOutcome playUntilDone(player::StateMachine &machine, ControlLoop &loop,
                          std::unique_ptr<ControlServer> &server,
                          const std::function<void()> &eachTurn, const std::atomic<bool> &stop,
                          const PlayLimits &limits, platform::Clock &clock,
                          const OnSocketFailure &socketFailed = {});

} // namespace depthtouch::control
