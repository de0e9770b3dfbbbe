/// \file
/// \brief `depthtouch play FILE|URL`: the set-top box player (docs/architecture.md §1). It runs the
/// player core (player_core.h: the backends chosen, playback::Playback driven by the
/// player::StateMachine, remote keys and the control socket through control::ControlLoop) on the
/// main thread, the one path libdepthtouch and the GStreamer element run too; what is `play`'s own
/// is around it: the stderr lines, the summary, the stats file and the exit code. Writes the force
/// log and the stats JSON (docs/architecture.md §4) when asked, and prints a summary.
///
/// The options are the rows of `play`'s option table (play_options.h); they may also come from a
/// TOML file (play_config.h): keys are the long option names without the dashes (`stiffness =
/// 1200`, `display = "headless"`, `loop = true`), read from the system file, the user file and
/// `--config` in that order (play_config_files.h); options given on the command line win. Unknown
/// keys and values of the wrong type are errors (exit 2).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "depthtouch/control/play_loop.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/message_text.h"
#include "depthtouch/platform/stop_signals.h"
#include "depthtouch/playback/play_report.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "option_cli.h"
#include "output_paths.h"
#include "play.h"
#include "play_config.h"
#include "play_backends.h"
#include "play_config_files.h"
#include "play_options.h"
#include "player_core.h"

namespace depthtouch::cli {

namespace {

std::atomic<bool> gPlayStop{false};

/// Prints \a why as the run's one error line (printable, at most 400 bytes of it): at the error
/// priority ("<3>") when stderr is the journal (a service), as the log's lines.
void failLine(std::string_view why)
{
    platform::printStderrLine(platform::LogLevel::Error, "depthtouch play: %s",
                              platform::printableText(why, 400).c_str());
}

/// Prints the player's errors on stderr, each once, as it happens (one line), and its state
/// changes when asked (--verbose; on a terminal unless --quiet), each with its priority ("<6>")
/// when stderr is the journal.
class StderrListener final : public player::PlayerListener {
public:
    StderrListener(bool states, bool verbose) : states_(states || verbose), verbose_(verbose) {}

    void onPlayerEvent(const player::PlayerEvent &e) override
    {
        switch (e.kind) {
        case player::PlayerEventKind::StateChanged:
            // "opening" says nothing new, and "error" follows its reason's line.
            if (states_ && e.state != player::PlayerState::Error &&
                (verbose_ || e.state != player::PlayerState::Opening))
                platform::printStderrLine(platform::LogLevel::Info, "depthtouch play: %s",
                                          player::playerStateName(e.state));
            break;
        case player::PlayerEventKind::Error:
            failLine(e.message);
            errorPrinted_ = true;
            break;
        case player::PlayerEventKind::EndOfFile:
            if (states_)
                platform::printStderrLine(platform::LogLevel::Info,
                                          "depthtouch play: end of stream (%s)", e.message.c_str());
            break;
        default:
            break;
        }
    }

    /// True once an error line was printed.
    [[nodiscard]] bool errorPrinted() const noexcept { return errorPrinted_; }

private:
    bool states_;
    bool verbose_;
    bool errorPrinted_ = false;
};

PlayResult badInput(const std::string &why)
{
    failLine(why);
    return {kExitBadInput, {}};
}

/// Checks the options that need no backend (the table's ranges, output paths).
/// \return the result of a bad option (exit 2) or an unusable output (1 or 2), or nullopt.
std::optional<PlayResult> checkPlayOptions(const PlayOptions &opt)
{
    if (const std::string bad = checkPlayOptionValues(opt); !bad.empty())
        return badInput(bad);
    if (opt.url.empty() && !opt.idle) // --idle: started idle, a client sends loadfile
        return badInput("nothing to play: give a file or URL");
    if (const platform::OutputPathCheck c = checkPlayOutputs(opt, true); c.exitCode != kExitOk) {
        failLine(c.message);
        return PlayResult{c.exitCode, {}};
    }
    return std::nullopt;
}

/// Says, as a warning line, that a player that stays up (--idle: the box's service) plays without
/// the first backend of the list it was given (a sound card the sandbox hides) and with the one
/// \a b names, or that the device of the backend chosen is not plugged in yet and is waited for (a
/// Falcon or a remote, hal::BackendConfig::awaitDevice): its summary, which says so too, comes only
/// at its stop. Nothing for another player, for the display (its summary says where the picture
/// went), for the default remote list (it takes the terminal's keys where play runs in one: none
/// elsewhere is no fallback), or when the first name was chosen and its device is there.
void warnFallback(const PlayOptions &opt, const OpenedBackend &b)
{
    std::string_view names = b.names;
    std::string_view first;
    if (!opt.idle || b.kind == drivers::BackendKind::Display ||
        (b.kind == drivers::BackendKind::RemoteInput && opt.remote == PlayOptions{}.remote) ||
        !hal::detail::nextBackendName(names, first))
        return;
    const hal::SelectionReport &report = b.report;
    if (first == report.chosen && b.awaitingDevice)
        platform::printStderrLine(platform::LogLevel::Warning,
                                  "depthtouch play: warning: no %s '%s' connected: playing without "
                                  "it until it is plugged in",
                                  drivers::backendKindName(b.kind), report.chosen.c_str());
    if (first == report.chosen)
        return;
    platform::printStderrLine(
        platform::LogLevel::Warning,
        "depthtouch play: warning: no %s '%s' (it could not be opened; --verbose says why): "
        "playing with '%s'",
        drivers::backendKindName(b.kind), platform::printableText(first, 60).c_str(),
        report.chosen.c_str());
}

/// Opens the player core of \a opt (player_core.h) into \a core, with \a keys and the warnings of
/// warnFallback() as its backends open. \return nullopt, or after the failure's one line its
/// result: bad input (2) for a name or option at fault, a decoder or source that cannot be made, a
/// pipeline that cannot be made on the backends, or a control socket path at fault
/// (controlSocketBadInput()); else failure (1).
std::optional<PlayResult> openPlay(const PlayOptions &opt, platform::Clock &clock,
                                   const player::KeyMap &keys, std::unique_ptr<PlayerCore> &core)
{
    PlayerCoreSetup setup;
    setup.keys = keys;
    setup.opened = [&opt](const OpenedBackend &b) { warnFallback(opt, b); };
    const std::optional<PlayOpenFailure> bad = PlayerCore::open(opt, clock, std::move(setup), core);
    if (!bad)
        return std::nullopt;
    failLine(bad->message);
    return PlayResult{
        bad->badInput || bad->part == PlayPart::Playback ? kExitBadInput : kExitFailure, {}};
}

/// Writes the stats file and works out the exit code of a run that ended as \a out says; prints
/// the summary when the input played.
PlayResult finishPlay(const PlayOptions &opt, const playback::PlayRunFigures &run,
                      control::LoopOutcome out, bool quitRequested, bool errorPrinted)
{
    PlayResult result;
    result.stats = playback::playStatsJson(opt.url, run);
    // An output that could not be written: exit 1.
    std::string lost = opt.stats.empty() ? std::string() : writeStatsFile(opt.stats, result.stats);
    const bool statsLost = !lost.empty();
    const bool forceLogLost = run.haptic && run.haptic->forceLogLost;
    if (lost.empty() && forceLogLost)
        lost = "cannot write the force log " + platform::quotedText(opt.forceLog, 120) +
               " (disk full?)";
    if (lost.empty() && !run.stats.recordingLost.empty())
        lost = "lost the recording " + platform::quotedText(opt.record, 120) + ": " +
               run.stats.recordingLost;
    if (lost.empty() && !run.stats.avLogLost.empty())
        lost = platform::quotedText(opt.avLog, 120) + ": " + run.stats.avLogLost;
    if (lost.empty() && !run.stats.snapshotLost.empty())
        lost = "in " + platform::quotedText(opt.snapshotDir, 120) + ": " + run.stats.snapshotLost;
    if (lost.empty())
        lost = run.audioOutputLost; // the `wav` file: its open, a write or its rename failed

    // A player that stays up (--idle: the box's service) spends most of its life waiting for a
    // sender, or in the error of the last one until the next: it printed each failure as it came,
    // and a stop (SIGTERM from `systemctl stop`, --duration) is its normal end, exit 0, not one
    // more failure (systemd marks a unit whose stop exits 1 failed). A lost output still counts.
    if (opt.idle && out.stopped) {
        out.failure.clear();
        out.stoppedOpening = false;
        quitRequested = true;
    }
    // An input that opened but failed before giving a single frame (cut after its header) is
    // bad input like one that does not open.
    if (out.opened && run.stats.framesReceived == 0 && !out.failure.empty())
        out.opened = false;
    if (!out.opened) {
        if (!out.failure.empty()) {
            if (!errorPrinted) // else printed when it happened
                failLine(out.failure);
            // A thread the system would not start (RLIMIT_NPROC, no memory) is no fault of the
            // input: exit 1, as for a lost output.
            result.exitCode =
                out.failureKind == Errc::OutOfResources ? kExitFailure : kExitBadInput;
        } else if (out.stoppedOpening) {
            failLine("stopped while opening " + platform::quotedText(opt.url, 120));
            result.exitCode = kExitFailure;
        } else if (!quitRequested) {
            failLine("nothing was played");
            result.exitCode = kExitBadInput;
        } else if (!lost.empty()) { // quit was sent before anything played
            failLine(lost);
            result.exitCode = kExitFailure;
        }
        return result;
    }
    if (!lost.empty() && out.failure.empty())
        failLine(lost);
    // The summary names only the files that were written; --quiet prints none (mpv's
    // --really-quiet: errors only).
    if (!opt.quiet)
        playback::printPlaySummary(
            opt.url, run, run.stats.recordingLost.empty() ? opt.record : std::string(),
            forceLogLost ? std::string() : opt.forceLog, statsLost ? std::string() : opt.stats);
    result.exitCode = out.failure.empty() && lost.empty() ? kExitOk : kExitFailure;
    if (run.haptic && run.haptic->maxForce > run.deviceMaxForce + 1e-9)
        result.exitCode = kExitFailure;
    return result;
}

} // namespace

void requestPlayStop() noexcept
{
    gPlayStop.store(true);
}

PlayResult runPlay(const PlayOptions &opt, const player::KeyMap &keys)
{
    if (std::optional<PlayResult> bad = checkPlayOptions(opt))
        return *bad;
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    std::unique_ptr<PlayerCore> core;
    if (std::optional<PlayResult> bad = openPlay(opt, clock, keys, core))
        return *bad;
    player::StateMachine &machine = core->machine();
    StderrListener listener(!opt.quiet && ::isatty(STDERR_FILENO) == 1, opt.verbose);
    machine.addListener(&listener);

    gPlayStop.store(false);
    // Every stop signal quits the same way, until the outputs are written (the recording and the
    // force log finished, the stats written); the control loop's waits are restarted.
    const platform::StopSignals signals(gPlayStop, true);
    playback::Playback &playback = core->playback();
    const control::LoopOutcome out = core->run(
        [&playback, &machine] { playback.report(machine); }, gPlayStop, {opt.duration, opt.idle},
        [](const Error &e) {
            platform::printStderrLine(platform::LogLevel::Error,
                                      "depthtouch play: control socket failed: %s", e.what);
        });
    const playback::PlayRunFigures run = core->finish(out);
    const PlayResult result =
        finishPlay(opt, run, out, machine.quitRequested(), listener.errorPrinted());
    machine.removeListener(&listener);
    return result;
}

void registerPlayCommand(CLI::App &app, int &exitCode)
{
    auto o = std::make_shared<PlayOptions>();
    CLI::App *cmd = &addCommand(
        app, "play", "Play a color + depth file or stream: stereo video and haptics in real time");
    addOptions(*cmd, playOptionTable(), *o);
    onRun(*cmd, [o, cmd, &exitCode] {
        const GivenOnCommandLine given = [cmd](const std::string &key) {
            return optionGiven(*cmd, "--" + key);
        };
        const ConfigDirs dirs = configDirsFromEnvironment();
        const PlayConfigLoad load = loadPlayConfigFiles(playConfigFiles(dirs, *o), given, *o);
        player::KeyMap keys;
        std::string error = load.error;
        if (error.empty())
            error = loadKeyMapFiles(keyMapFiles(dirs, *o), keys);
        if (!error.empty()) {
            failLine(error);
            exitCode = kExitBadInput;
            return;
        }
        if (o->showConfig) {
            std::fputs(showPlayConfig(*o, load).c_str(), stdout);
            exitCode = std::fflush(stdout) == 0 && std::ferror(stdout) == 0 ? 0 : 1;
            return;
        }
        // As `mpv --idle`: with --idle and no file the player starts idle and waits for a
        // client's loadfile on its control socket.
        if (o->url.empty() && !o->idle) {
            failLine("url is required: the file or stream to play (or --show-config, or --idle "
                     "with --control)");
            exitCode = kExitBadInput;
            return;
        }
        // The log's timestamped lines only when asked for (--verbose, or DT_LOG's levels): the
        // player's own lines say what went wrong, once.
        if (std::getenv("DT_LOG") == nullptr)
            platform::setLogLevel(o->verbose ? platform::LogLevel::Info : platform::LogLevel::Off);
        exitCode = runPlay(*o, keys).exitCode;
    });
}

} // namespace depthtouch::cli
