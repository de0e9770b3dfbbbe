/// \file
/// \brief The player's main loop: see play_loop.h.

#include "depthtouch/control/play_loop.h"

#include <algorithm>
#include <chrono>

#include "depthtouch/platform/memory_lock.h"

namespace depthtouch::control {

LoopOutcome playUntilDone(player::StateMachine &machine, ControlLoop &loop,
                          std::unique_ptr<ControlServer> &server,
                          const std::function<void()> &eachTurn, const std::atomic<bool> &stop,
                          const PlayLimits &limits, platform::Clock &clock,
                          const OnSocketFailure &socketFailed)
{
    LoopOutcome out;
    out.rssStart = platform::residentMiB();
    const platform::TimePoint start = clock.now();
    if (limits.start)
        machine.execute("play");
    while (!machine.quitRequested()) {
        if (auto r = loop.runUntil(clock.now() + limits.turn); !r) {
            if (socketFailed)
                socketFailed(r.error());
            loop.detachServer(); // before the server it points to is closed
            server.reset();
        }
        eachTurn();
        const player::PlayerState st = machine.state();
        if (st == player::PlayerState::Playing || st == player::PlayerState::Paused)
            out.opened = true;
        // A failure counts while the player stays in Error; one it left (a client's stop or
        // play, with --idle) was recovered from.
        if (st == player::PlayerState::Error) {
            out.failure = machine.errorReason();
            out.failureKind = machine.errorKind();
        } else
            out.failure.clear();
        const double elapsed = platform::toSeconds(clock.now() - start);
        if (out.rssAfterWarmup < 0.0 && elapsed >= 5.0) {
            out.rssAfterWarmup = platform::residentMiB();
            out.lockedMiB = platform::lockedMiB();
        }
        if (stop.load() || (limits.duration > 0.0 && elapsed >= limits.duration)) {
            out.stoppedOpening = st == player::PlayerState::Opening;
            out.stopped = true;
            machine.execute("quit");
            break;
        }
        if ((st == player::PlayerState::Error || st == player::PlayerState::Stopped) &&
            !limits.idle)
            break;
    }
    out.rssEnd = platform::residentMiB();
    out.lockedMiB = std::max(out.lockedMiB, platform::lockedMiB());
    return out;
}

} // namespace depthtouch::control
