#include "depthtouch/control/control_loop.h"

#include <algorithm>

#include "depthtouch/platform/log.h"
#include "depthtouch/player/key_bindings.h"

DT_LOG_CATEGORY(Control)

namespace depthtouch::control {

ControlLoop::ControlLoop(player::StateMachine &machine, hal::RemoteInput *remote,
                         ControlServer *server, platform::Clock &clock, platform::Duration slice)
    : machine_(machine), remote_(remote), server_(server), clock_(clock),
      slice_(std::max(slice, platform::Duration(std::chrono::milliseconds(1))))
{
    if (remote_ != nullptr)
        machine_.setRemoteConnected(!remote_->awaitingDevice());
}

Result<void> ControlLoop::runUntil(platform::TimePoint until)
{
    while (!machine_.quitRequested()) {
        if (server_ != nullptr)
            DT_TRY(server_->poll(platform::Duration::zero()));
        if (machine_.quitRequested())
            break;
        const platform::TimePoint now = clock_.now();
        if (now >= until)
            break;
        const platform::TimePoint sliceEnd = std::min(until, now + slice_);
        if (remote_ != nullptr && !stats_.remoteLost) {
            Result<hal::KeyEvent> key = remote_->poll(sliceEnd);
            machine_.setRemoteConnected(!remote_->awaitingDevice());
            if (key) {
                handleKey(*key);
            } else if (key.error().code != Errc::Timeout) {
                char buf[160];
                DT_LOG(Control, Warning, "Remote control lost, going on without it: %s",
                       key.error().format(buf, sizeof buf));
                stats_.remoteLost = true;
                machine_.setRemoteConnected(false);
            }
        } else if (server_ != nullptr) {
            DT_TRY(server_->poll(sliceEnd - now));
        } else {
            clock_.sleepUntil(sliceEnd);
        }
    }
    return ok();
}

void ControlLoop::handleKey(const hal::KeyEvent &event)
{
    ++stats_.keys;
    const std::optional<player::Command> command = machine_.keyMap().commandFor(event);
    if (!command)
        return;
    ++stats_.keyCommands;
    const player::CommandOutcome out = machine_.execute(*command);
    if (!out.accepted) {
        ++stats_.refused;
        DT_LOG(Control, Info, "%s: %s", hal::keyName(event.key), out.reason.c_str());
    }
}

Result<void> runControlLoop(player::StateMachine &machine, hal::RemoteInput *remote,
                            ControlServer *server, platform::Clock &clock)
{
    ControlLoop loop(machine, remote, server, clock);
    while (!machine.quitRequested())
        DT_TRY(loop.runUntil(clock.now() + std::chrono::seconds(1)));
    return ok();
}

} // namespace depthtouch::control
