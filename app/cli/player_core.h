#pragma once
/// \file
/// \brief The player core: one player of `play`'s options, the one path of `depthtouch play`
/// (cmd_play.cpp), of libdepthtouch's player thread (lib/src/player_thread.cpp) and of the
/// GStreamer element depthtouchsink (gst/src/feed_player.cpp), as mpv's command-line player and
/// libmpv run one player core (mpv's player/main.c: mp_create(), mp_initialize(), the play loop).
/// It opens the backends and the pipeline (openPlayer()), makes the state machine
/// (playerSettings() with the key map given) and the control socket (--control), runs the loop
/// (control::playUntilDone()), and at the end stops and closes the pipeline and gathers what the
/// run measured (playback::PlayRunFigures). What differs between the three is only what each does
/// around it: play's stderr lines, summary, stats file and exit code (docs/playing.md); the
/// library's API calls and events (docs/embedding.md); the element's pads.
///
/// Nothing here prints or logs: a failure comes back as data (PlayOpenFailure), and a control
/// socket that fails while playing is told to the caller's hook.
/// Thread-safety: open() on any thread; then thread-bound (the thread that runs the player; a
/// std::thread started after open() may take it over).

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "depthtouch/control/control_loop.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/control/play_loop.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/playback/play_report.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/key_bindings.h"
#include "depthtouch/player/state_machine.h"
#include "play.h"
#include "play_backends.h"

namespace depthtouch::cli {

/// \brief What a caller of PlayerCore::open() adds to the options.
struct PlayerCoreSetup {
    player::KeyMap keys; ///< The remote's key map: the defaults, as input.conf files rebound them.
    OnBackendOpened opened; ///< Hears of each backend as it opens (play's warnings); may be empty.
    const PlayerFeed *feed = nullptr; ///< The caller's own source (the element's pads), or null.
    /// A display to play on instead of --display's (the library's render API), with the name the
    /// report gives it; null: --display's.
    std::unique_ptr<hal::Display> display;
    std::string displayName;
    /// The control loop's slice (control::ControlLoop): how long it waits on the remote before it
    /// serves the socket again.
    platform::Duration slice = std::chrono::milliseconds(10);
};

/// \brief \return whether a control socket that could not be made for \a e is the path's fault
/// (bad input: it exists and is not a socket, another player listens on it, too long, no such
/// folder, no permission), not the system's.
bool controlSocketBadInput(const Error &e);

/// \brief Writes the stats JSON \a stats (docs/architecture.md §4) to \a path as `play --stats`
/// does (platform::writeOutputFile(): whole or not at all). \return an empty string, or the one
/// line of the output lost ("cannot write the stats 'PATH': why").
std::string writeStatsFile(const std::string &path, const nlohmann::json &stats);

/// \brief One player: its backends, pipeline, state machine, control socket and loop.
class PlayerCore {
public:
    /// \brief Opens the player of \a opt on \a clock (which must outlive it): openPlayer() with
    /// \a setup's display, feed and hook, the state machine, then the control socket of --control.
    /// The options' values are not checked here (checkPlayOptionValues(), checkPlayOutputs()).
    /// \return nullopt with the player in \a out, or the first failure: a part of openPlayer()'s,
    /// or PlayPart::ControlSocket (its message "cannot create the control socket 'PATH': why",
    /// badInput by controlSocketBadInput(), the socket's error in PlayOpenFailure::error).
    static std::optional<PlayOpenFailure> open(const PlayOptions &opt, platform::Clock &clock,
                                               PlayerCoreSetup setup,
                                               std::unique_ptr<PlayerCore> &out);

    /// Stops and closes the pipeline when finish() did not, then the backends.
    ~PlayerCore();
    PlayerCore(const PlayerCore &) = delete;
    PlayerCore &operator=(const PlayerCore &) = delete;

    [[nodiscard]] player::StateMachine &machine() noexcept { return *machine_; }
    [[nodiscard]] playback::Playback &playback() noexcept { return *player_.playback; }
    [[nodiscard]] const PlayBackends &backends() const noexcept { return player_.backends; }

    /// \brief Runs the loop (control::playUntilDone()) with \a eachTurn after each turn, until
    /// quit, \a stop, \a limits' duration, or the end (unless \a limits idle). A control socket
    /// that fails is told to \a socketFailed (may be empty) and closed; the remote goes on.
    /// \return how it ended.
    control::LoopOutcome run(const std::function<void()> &eachTurn, const std::atomic<bool> &stop,
                             const control::PlayLimits &limits,
                             const control::OnSocketFailure &socketFailed = {});

    /// \brief Stops and closes the pipeline (the recording ends, the snapshots are written, a file
    /// sound output is finished), then gathers the run's figures with \a out's memory samples and
    /// failure. Once; the figures' info points into the pipeline, which lives as long as this.
    playback::PlayRunFigures finish(const control::LoopOutcome &out);

private:
    PlayerCore(const PlayOptions &opt, platform::Clock &clock);

    const PlayOptions options_;
    platform::Clock &clock_;
    OpenedPlayer player_; ///< The Playback, then its backends.
    std::unique_ptr<player::StateMachine> machine_;
    std::unique_ptr<control::ControlServer> server_;
    std::unique_ptr<control::ControlLoop> loop_;
    bool finished_ = false;
};

} // namespace depthtouch::cli
