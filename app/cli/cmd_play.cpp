/// \file
/// \brief `depthtouch play FILE|URL`: the set-top box player (DESIGN.md §1). The backends chosen
/// here (display, haptic device, decoder, remote) are handed to playback::Playback, driven by the
/// player::StateMachine; remote keys and the control socket reach the machine through
/// control::ControlLoop on the main thread. Writes the force log and the stats JSON (DESIGN.md §4)
/// when asked, and prints a summary.
///
/// Options may also come from a TOML file (`--config`): keys are the long option names without
/// the dashes (`stiffness = 1200`, `display = "headless"`, `loop = true`); options given on the
/// command line win. Unknown keys and values of the wrong type are errors (exit 2).

#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "depthtouch/control/control_loop.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "message_text.h"
#include "output_paths.h"
#include "play.h"
#include "play_config.h"

namespace depthtouch::cli {

namespace {

std::atomic<bool> gPlayStop{false};

extern "C" void onPlayStopSignal(int)
{
    gPlayStop.store(true);
}

/// Resident set size, MiB (Linux /proc), or −1.
double residentMiB()
{
    std::ifstream f("/proc/self/statm");
    long pages = 0;
    long resident = 0;
    if (!(f >> pages >> resident))
        return -1.0;
    return static_cast<double>(resident) * 4096.0 / (1024.0 * 1024.0);
}

/// Prints the player's errors on stderr, each once, as it happens (one line), and its state
/// changes when asked (--verbose; on a terminal unless --quiet).
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
                std::fprintf(stderr, "depthtouch play: %s\n", player::playerStateName(e.state));
            break;
        case player::PlayerEventKind::Error:
            std::fprintf(stderr, "depthtouch play: %s\n", printableText(e.message, 400).c_str());
            errorPrinted_ = true;
            break;
        case player::PlayerEventKind::EndOfFile:
            if (states_)
                std::fprintf(stderr, "depthtouch play: end of stream (%s)\n", e.message.c_str());
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

/// \return the exit code of a control socket that could not be made: bad input (2) when the
/// path is at fault (exists and is not a socket, another player listens on it, too long, no such
/// folder, no permission), else failure (1).
int controlSocketExitCode(const Error &e)
{
    if (e.code == Errc::InvalidArgument || e.code == Errc::Busy ||
        e.code == Errc::PermissionDenied)
        return kExitBadInput;
    switch (e.sysErrno) {
    case ENOENT:
    case ENOTDIR:
    case ENAMETOOLONG:
    case ELOOP:
    case EROFS:
    case EADDRINUSE:
    case EISDIR:
        return kExitBadInput;
    default:
        return kExitFailure;
    }
}

bool parseSize(const std::string &text, int &w, int &h)
{
    if (text.empty()) {
        w = h = 0;
        return true;
    }
    char x = 0;
    char extra = 0;
    return std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) == 3 && (x == 'x' || x == 'X') &&
           w >= 16 && h >= 16 && w <= 8192 && h <= 8192;
}

/// Prints \a why as the run's one error line (printable, at most 400 bytes of it).
void failLine(std::string_view why)
{
    std::fprintf(stderr, "depthtouch play: %s\n", printableText(why, 400).c_str());
}

PlayResult badInput(const std::string &why)
{
    failLine(why);
    return {kExitBadInput, {}};
}

/// Checks the options that need no backend (ranges, output paths).
/// \return the result of a bad option (exit 2) or an unusable output (1 or 2), or nullopt.
std::optional<PlayResult> checkPlayOptions(const PlayOptions &opt, int &outW, int &outH)
{
    if (!player::stereoModeFromName(opt.stereo))
        return badInput("--stereo must be sbs, tab, anaglyph, mono or interleaved");
    if (!(opt.rate >= 100.0 && opt.rate <= 10000.0))
        return badInput("--rate must be in [100, 10000] Hz");
    if (!(opt.stiffness >= 1.0 && opt.stiffness <= 20000.0))
        return badInput("--stiffness must be in [1, 20000] N/m");
    if (!(opt.duration >= 0.0 && opt.duration <= 7 * 24 * 3600.0))
        return badInput("--duration must be >= 0 s");
    if (!(opt.osdSeconds >= 0.0 && opt.osdSeconds <= 86400.0))
        return badInput("--osd-seconds must be in [0, 86400] s");
    if (!(opt.lodTarget >= 0.0 && opt.lodTarget <= 4.0))
        return badInput("--lod-target must be in [0, 4] refresh periods (0: off)");
    if (!(opt.maxLateness >= 0.0 && opt.maxLateness <= 10.0))
        return badInput("--max-lateness must be in [0, 10] seconds");
    if (opt.reengage != "ramp" && opt.reengage != "release")
        return badInput("--reengage must be ramp or release");
    if (!parseSize(opt.size, outW, outH))
        return badInput("--size must be WxH, 16..8192 pixels each");
    if (opt.url.empty())
        return badInput("nothing to play: give a file or URL");
    if (opt.recordCrf < 0 || opt.recordCrf > 51)
        return badInput("--record-crf must be in [0, 51]");
    // Outputs: a missing folder is bad input, an output that takes no byte is lost at once.
    for (const OutputPathCheck &c : {checkOutputPath("--record", opt.record),
                                     checkOutputPath("--force-log", opt.forceLog),
                                     checkOutputPath("--stats", opt.stats, true)}) {
        if (c.exitCode != kExitOk) {
            failLine(c.message);
            return PlayResult{c.exitCode, {}};
        }
    }
    return std::nullopt;
}

} // namespace

void requestPlayStop() noexcept
{
    gPlayStop.store(true);
}

PlayResult runPlay(const PlayOptions &opt)
{
    int outW = 0;
    int outH = 0;
    if (std::optional<PlayResult> bad = checkPlayOptions(opt, outW, outH))
        return *bad;
    const auto stereo = player::stereoModeFromName(opt.stereo);

    platform::SteadyClock &clock = platform::SteadyClock::instance();
    hal::BackendConfig cfg;
    cfg.clock = &clock;

    // Backends.
    hal::BackendConfig displayCfg = cfg;
    displayCfg.options = hal::OptionList(opt.displayOptions);
    hal::SelectionReport displayReport;
    auto display = drivers::createDisplay(opt.display, displayCfg, &displayReport);
    if (!display) {
        failLine(displayReport.message);
        return {display.error().code == Errc::InvalidArgument ? kExitBadInput : kExitFailure, {}};
    }
    hal::BackendConfig hapticCfg = cfg;
    hapticCfg.options = hal::OptionList(opt.hapticOptions);
    hal::SelectionReport hapticReport;
    auto device = drivers::createHapticDevice(opt.haptic, hapticCfg, &hapticReport);
    if (!device) {
        failLine(hapticReport.message);
        return {device.error().code == Errc::InvalidArgument ? kExitBadInput : kExitFailure, {}};
    }
    std::unique_ptr<hal::RemoteInput> remote;
    hal::SelectionReport remoteReport;
    if (!opt.remote.empty() && opt.remote != "none") {
        hal::BackendConfig remoteCfg = cfg;
        remoteCfg.options = hal::OptionList(opt.remoteOptions);
        auto r = drivers::createRemoteInput(opt.remote, remoteCfg, &remoteReport);
        if (!r) {
            failLine(remoteReport.message);
            return {r.error().code == Errc::InvalidArgument ? kExitBadInput : kExitFailure, {}};
        }
        remote = std::move(*r);
    }
    // Check the decoder and source names now (one clear line), then make them per open().
    {
        hal::SelectionReport rep;
        hal::BackendConfig decoderCfg = cfg;
        decoderCfg.options = hal::OptionList(opt.decoderOptions);
        if (auto d = drivers::createVideoDecoder(opt.decoder, decoderCfg, &rep); !d) {
            failLine(rep.message);
            return {kExitBadInput, {}};
        }
        if (auto s = drivers::createMediaSource(opt.source, cfg, &rep); !s) {
            failLine(rep.message);
            return {kExitBadInput, {}};
        }
    }

    playback::PlaybackConfig pc;
    pc.haptics.servoRateHz = opt.rate;
    pc.haptics.renderer.stiffness = opt.stiffness;
    pc.haptics.renderer.reengage =
        opt.reengage == "ramp" ? haptics::Reengage::Ramp : haptics::Reengage::Release;
    pc.haptics.requireRt = opt.requireRt;
    pc.haptics.forceLogPath = opt.forceLog;
    pc.stereoMode = *stereo;
    pc.outputWidth = outW;
    pc.outputHeight = outH;
    pc.frameCompatible = !opt.size.empty(); // a display-sized output is a 3D TV's frame
    pc.snapshotDir = opt.snapshotDir;
    pc.snapshotEvery = opt.snapshotEvery;
    pc.recordPath = opt.record;
    pc.recordCrf = opt.recordCrf;
    pc.meshStep = opt.meshStep;
    pc.osdSeconds = opt.osdSeconds;
    pc.lodTarget = opt.lodTarget;
    pc.maxLateness = opt.maxLateness;
    playback::PlaybackHal ph;
    const std::string sourceName = opt.source;
    const std::string decoderName = opt.decoder;
    ph.makeSource = [sourceName, cfg]() { return drivers::createMediaSource(sourceName, cfg); };
    const std::string decoderOptions = opt.decoderOptions;
    ph.makeDecoder = [decoderName, decoderOptions, cfg](const hal::StreamInfo &) {
        hal::BackendConfig c = cfg;
        c.options = hal::OptionList(decoderOptions);
        return drivers::createVideoDecoder(decoderName, c);
    };
    ph.display = display->get();
    ph.device = hapticReport.chosen == "none" ? nullptr : device->get();
    ph.clock = &clock;
    auto pb = playback::Playback::create(pc, ph);
    if (!pb)
        return badInput(pb.error().what);
    playback::Playback &playback = **pb;

    player::PlayerSettings settings;
    settings.url = opt.url;
    settings.loop = opt.loop;
    settings.stereoMode = *stereo;
    settings.haptics = true;
    settings.stiffness = opt.stiffness;
    settings.range.max = std::max(settings.range.max, opt.stiffness);
    settings.range.min = std::min(settings.range.min, opt.stiffness);
    player::StateMachine machine(playback, settings);
    StderrListener listener(!opt.quiet && ::isatty(STDERR_FILENO) == 1, opt.verbose);
    machine.addListener(&listener);

    std::unique_ptr<control::ControlServer> server;
    if (!opt.control.empty()) {
        auto s = control::ControlServer::create(opt.control, machine);
        if (!s) {
            char why[160];
            std::fprintf(stderr, "depthtouch play: cannot create the control socket %s: %s\n",
                         quotedText(opt.control, 120).c_str(), s.error().format(why, sizeof why));
            return {controlSocketExitCode(s.error()), {}};
        }
        server = std::move(*s);
    }
    control::ControlLoop loop(machine, remote.get(), server.get(), clock,
                              std::chrono::milliseconds(10));

    gPlayStop.store(false);
    std::signal(SIGINT, &onPlayStopSignal);
    std::signal(SIGTERM, &onPlayStopSignal);

    const double rssStart = residentMiB();
    double rssAfterWarmup = -1.0;
    const platform::TimePoint start = clock.now();
    std::string failure;         // the reason when the player ends in Error
    bool opened = false;
    bool stoppedOpening = false; // a signal or --duration came while the input was opening
    machine.execute("play");
    while (!machine.quitRequested()) {
        if (auto r = loop.runUntil(clock.now() + std::chrono::milliseconds(10)); !r) {
            std::fprintf(stderr, "depthtouch play: control socket failed: %s\n", r.error().what);
            server.reset();
        }
        playback.report(machine);
        const player::PlayerState st = machine.state();
        if (st == player::PlayerState::Playing || st == player::PlayerState::Paused)
            opened = true;
        // A failure counts while the player stays in Error; one it left (a client's stop or
        // play, with --idle) was recovered from.
        if (st == player::PlayerState::Error)
            failure = machine.errorReason();
        else
            failure.clear();
        const double elapsed = platform::toSeconds(clock.now() - start);
        if (rssAfterWarmup < 0.0 && elapsed >= 5.0)
            rssAfterWarmup = residentMiB();
        if (gPlayStop.load() || (opt.duration > 0.0 && elapsed >= opt.duration)) {
            stoppedOpening = st == player::PlayerState::Opening;
            machine.execute("quit");
            break;
        }
        if (st == player::PlayerState::Error && !opt.idle)
            break;
        if (st == player::PlayerState::Stopped && !opt.idle)
            break;
    }
    const double rssEnd = residentMiB();
    (void)playback.stop();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);

    // Stats.
    PlayResult result;
    const playback::PlaybackInfo &info = playback.info();
    const playback::PlaybackStats ps = playback.stats();
    const auto hs = playback.hapticStats();
    nlohmann::json j = hs ? nlohmann::json::parse(hs->toJson()) : nlohmann::json::object();
    j["url"] = opt.url;
    j["mode"] = info.mode;
    j["depth_size"] = {info.depthWidth, info.depthHeight};
    j["color_size"] = {info.colorWidth, info.colorHeight};
    j["output_size"] = {info.outputWidth, info.outputHeight};
    j["fps"] = info.fps;
    j["display"] = displayReport.chosen;
    j["haptic_device"] = hapticReport.chosen;
    j["frames_decoded"] = ps.receiver.colorFrames + ps.receiver.depthFrames;
    j["frames_received"] = ps.framesReceived;
    j["frames_presented"] = ps.framesPresented;
    j["frames_dropped"] = ps.framesDropped;
    j["frames_late"] = ps.framesLate;
    j["late_ms_max"] = ps.lateMsMax;
    j["frames_concealed"] = ps.receiver.framesConcealed;
    j["decode_errors"] = ps.receiver.decodeErrors;
    j["zero_copy"] = ps.zeroCopy;
    j["color_frames_dmabuf"] = ps.receiver.colorFramesZeroCopy;
    j["color_frames_imported"] = ps.colorFramesImported;
    j["color_frames_dmabuf_uploaded"] = ps.colorFramesDmaBufUploaded;
    j["depth_pairs_published"] = ps.depthPairsPublished;
    j["render_ms_p50"] = ps.renderMsP50;
    j["render_ms_p99"] = ps.renderMsP99;
    j["mesh_triangles_p50"] = ps.meshTrianglesP50;
    j["lod_budget_blocks"] = ps.lodBudget;
    j["frames_lod_limited"] = ps.framesLodLimited;
    j["presented_fps"] = ps.presentedFps;
    j["playing_s"] = ps.playingSeconds;
    j["seeks"] = ps.seeks;
    j["snapshots_written"] = ps.snapshotsWritten;
    j["frames_recorded"] = ps.framesRecorded;
    j["frames_prepared_ahead"] = ps.framesPreparedAhead;
    j["rss_mib_start"] = rssStart;
    j["rss_mib_after_5s"] = rssAfterWarmup;
    j["rss_mib_end"] = rssEnd;
    j["notes"] = info.notes;
    j["final_state"] = player::playerStateName(machine.state());
    if (!failure.empty())
        j["error"] = failure;
    result.stats = j;
    std::string lost; // an output that could not be written: exit 1
    if (!opt.stats.empty()) {
        if (auto w = platform::writeOutputFile(opt.stats, j.dump(2) + "\n"); !w) {
            char why[160];
            lost = "cannot write the stats " + quotedText(opt.stats, 120) + ": " +
                   w.error().format(why, sizeof why);
        }
    }

    if (lost.empty() && hs && hs->forceLogLost)
        lost = "cannot write the force log " + quotedText(opt.forceLog, 120) + " (disk full?)";

    // An input that opened but failed before giving a single frame (cut after its header) is
    // bad input like one that does not open.
    if (opened && ps.framesReceived == 0 && !failure.empty())
        opened = false;
    if (!opened) {
        if (!failure.empty()) {
            if (!listener.errorPrinted()) // else printed when it happened
                failLine(failure);
            result.exitCode = kExitBadInput;
        } else if (stoppedOpening) {
            failLine("stopped while opening " + quotedText(opt.url, 120));
            result.exitCode = kExitFailure;
        } else if (!machine.quitRequested()) {
            failLine("nothing was played");
            result.exitCode = kExitBadInput;
        } else if (!lost.empty()) { // quit was sent before anything played
            failLine(lost);
            result.exitCode = kExitFailure;
        }
        return result;
    }
    if (!lost.empty() && failure.empty())
        failLine(lost);
    std::printf("DepthTouch play: %s (%s, %dx%d depth at %.3g fps) on %s, haptics %s\n",
                opt.url.c_str(), info.mode.c_str(), info.depthWidth, info.depthHeight, info.fps,
                displayReport.chosen.c_str(),
                info.haptics ? hapticReport.chosen.c_str() : "off");
    for (const std::string &n : info.notes)
        std::printf("  note              %s\n", n.c_str());
    std::printf("  frames            %llu received, %llu presented, %llu dropped, %llu late "
                "(at most %.0f ms; %.1f fps presented; render p50 %.1f ms, p99 %.1f ms)\n",
                static_cast<unsigned long long>(ps.framesReceived),
                static_cast<unsigned long long>(ps.framesPresented),
                static_cast<unsigned long long>(ps.framesDropped),
                static_cast<unsigned long long>(ps.framesLate), ps.lateMsMax, ps.presentedFps,
                ps.renderMsP50, ps.renderMsP99);
    if (ps.lodBudget > 0)
        std::printf("  level of detail   %.0f triangles a frame (median); %llu of %llu frames made "
                    "coarser to keep time, budget now %zu blocks\n",
                    ps.meshTrianglesP50, static_cast<unsigned long long>(ps.framesLodLimited),
                    static_cast<unsigned long long>(ps.framesPresented), ps.lodBudget);
    if (hs) {
        std::printf("  haptic thread     %s\n", hs->thread.c_str());
        std::printf("  haptic updates    %llu (%llu in contact), %llu overruns, %llu safety "
                    "releases\n",
                    static_cast<unsigned long long>(hs->updates),
                    static_cast<unsigned long long>(hs->contactUpdates),
                    static_cast<unsigned long long>(hs->overruns),
                    static_cast<unsigned long long>(hs->safetyReleases));
        std::printf("  wake latency      p50 %.1f us, p99 %.1f us; update time p50 %.2f us, p99 "
                    "%.2f us\n",
                    hs->wakeLatency.p50Us, hs->wakeLatency.p99Us, hs->updateTime.p50Us,
                    hs->updateTime.p99Us);
        std::printf("  max force         %.2f N (device maximum %.2f N)\n", hs->maxForce,
                    (*device)->capabilities().maxForce);
    }
    std::printf("  memory            %.1f MiB resident at start, %.1f MiB at the end\n", rssStart,
                rssEnd);
    if (!opt.record.empty())
        std::printf("  recording         %s (%llu frames)\n", opt.record.c_str(),
                    static_cast<unsigned long long>(ps.framesRecorded));
    if (!opt.forceLog.empty() || !opt.stats.empty())
        std::printf("  files             %s%s%s\n", opt.forceLog.c_str(),
                    !opt.forceLog.empty() && !opt.stats.empty() ? ", " : "", opt.stats.c_str());
    result.exitCode = failure.empty() && lost.empty() ? kExitOk : kExitFailure;
    if (hs && hs->maxForce > (*device)->capabilities().maxForce + 1e-9)
        result.exitCode = kExitFailure;
    return result;
}

void registerPlayCommand(CLI::App &app, int &exitCode)
{
    auto o = std::make_shared<PlayOptions>();
    CLI::App *cmd = app.add_subcommand(
        "play", "Play a color + depth file or stream: stereo video and haptics in real time");
    cmd->add_option("url", o->url, "File path or stream URL")->required();
    cmd->add_option("--display", o->display, "Display backend(s): headless, x11, kms, mock")
        ->capture_default_str();
    cmd->add_option("--display-options", o->displayOptions, "Options of the display backend");
    cmd->add_option("--haptic", o->haptic, "Haptic device backend(s): falcon, sim, mock, none")
        ->capture_default_str();
    cmd->add_option("--haptic-options", o->hapticOptions,
                    "Options of the haptic device, e.g. intent=stroke for sim");
    cmd->add_option("--decoder", o->decoder, "Video decoder backend(s)")->capture_default_str();
    cmd->add_option("--decoder-options", o->decoderOptions,
                    "Options of the decoder backend(s), e.g. drm-prime (zero-copy) or pool=24");
    cmd->add_option("--source", o->source, "Media source backend")->capture_default_str();
    cmd->add_option("--remote", o->remote, "Remote control backend(s): evdev, tty, none")
        ->capture_default_str();
    cmd->add_option("--remote-options", o->remoteOptions,
                    "Options of the remote, e.g. device=/dev/input/event3");
    cmd->add_option("--stereo", o->stereo, "Stereo layout: sbs, tab, anaglyph, mono, interleaved")
        ->capture_default_str();
    cmd->add_option("--stiffness", o->stiffness, "Surface stiffness, N/m")->capture_default_str();
    cmd->add_option("--rate", o->rate, "Haptic servo rate, Hz")->capture_default_str();
    cmd->add_option("--reengage", o->reengage,
                    "After a force jump (scene cut): ramp (re-seat the proxy, ramp the force in) "
                    "or release (paper IV.C)")
        ->capture_default_str();
    cmd->add_flag("--loop", o->loop, "Start again at the end");
    cmd->add_option("--duration", o->duration, "Stop after this many seconds (0: at the end)");
    cmd->add_option("--snapshot-dir", o->snapshotDir, "Folder for PNG snapshots of the output");
    cmd->add_option("--snapshot-every", o->snapshotEvery, "Snapshot every N presented frames");
    cmd->add_option("--record", o->record,
                    "Record the output as the viewer sees it (H.264; .mkv, .mp4, .ts)");
    cmd->add_option("--record-crf", o->recordCrf, "x264 CRF of the recording")
        ->capture_default_str();
    cmd->add_option("--force-log", o->forceLog, "Force log CSV (one row per haptic update)");
    cmd->add_option("--stats", o->stats, "Stats JSON written at the end");
    cmd->add_option("--control", o->control, "Control socket path (JSON lines)");
    cmd->add_option("--config", o->config, "TOML file with any of these options");
    cmd->add_option("--size", o->size, "Output size WxH (default: 2 x depth width by height)");
    cmd->add_option("--mesh-step", o->meshStep, "Drawn mesh step (0: adaptive level of detail)");
    cmd->add_option("--osd-seconds", o->osdSeconds,
                    "On-screen display time after start and each command, s (0: always shown)");
    cmd->add_option("--lod-target", o->lodTarget,
                    "Level of detail: share of the display's refresh period (or of the frame "
                    "period, if shorter) drawing may take; the mesh is made coarser when it takes "
                    "longer (0: off, full detail)")
        ->capture_default_str();
    cmd->add_option("--max-lateness", o->maxLateness,
                    "Seconds a frame may be late and still be drawn (the next ones catch up); "
                    "later ones are dropped (0: drop as soon as the next frame is due)")
        ->capture_default_str();
    cmd->add_flag("--require-rt", o->requireRt, "Fail when SCHED_FIFO is refused");
    cmd->add_flag("--idle", o->idle, "Stay up after the end or an error (for --control)");
    cmd->add_flag("--quiet", o->quiet, "No state-change lines on stderr (errors only)");
    cmd->add_flag("--verbose", o->verbose,
                  "State changes and the log (INFO and up) on stderr; without it a failure is "
                  "one line");
    cmd->callback([o, cmd, &exitCode] {
        if (!o->config.empty()) {
            std::string text;
            std::string err = readPlayConfigFile(o->config, text);
            if (err.empty())
                err = applyPlayConfigText(text, o->config, [cmd](const std::string &key) {
                    const CLI::Option *given = cmd->get_option_no_throw("--" + key);
                    return given != nullptr && given->count() > 0;
                }, *o);
            if (!err.empty()) {
                std::fprintf(stderr, "depthtouch play: %s\n", printableText(err, 400).c_str());
                exitCode = kExitBadInput;
                return;
            }
        }
        // The log's timestamped lines only when asked for (--verbose, or DT_LOG's levels): the
        // player's own lines say what went wrong, once.
        if (std::getenv("DT_LOG") == nullptr)
            platform::setLogLevel(o->verbose ? platform::LogLevel::Info : platform::LogLevel::Off);
        exitCode = runPlay(*o).exitCode;
    });
}

} // namespace depthtouch::cli
