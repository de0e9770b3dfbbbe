/// \file
/// \brief The player core: see player_core.h.

#include "player_core.h"

#include <cerrno>
#include <utility>

#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/message_text.h"

namespace depthtouch::cli {

bool controlSocketBadInput(const Error &e)
{
    if (e.code == Errc::InvalidArgument || e.code == Errc::Busy || e.code == Errc::PermissionDenied)
        return true;
    switch (e.sysErrno) {
    case ENOENT:
    case ENOTDIR:
    case ENAMETOOLONG:
    case ELOOP:
    case EROFS:
    case EADDRINUSE:
    case EISDIR:
        return true;
    default:
        return false;
    }
}

std::string writeStatsFile(const std::string &path, const nlohmann::json &stats)
{
    if (auto w = platform::writeOutputFile(path, stats.dump(2) + "\n"); !w) {
        char why[160];
        return "cannot write the stats " + platform::quotedText(path, 120) + ": " +
               w.error().format(why, sizeof why);
    }
    return {};
}

PlayerCore::PlayerCore(const PlayOptions &opt, platform::Clock &clock)
    : options_(opt), clock_(clock)
{
}

std::optional<PlayOpenFailure> PlayerCore::open(const PlayOptions &opt, platform::Clock &clock,
                                                PlayerCoreSetup setup,
                                                std::unique_ptr<PlayerCore> &out)
{
    std::unique_ptr<PlayerCore> core(new PlayerCore(opt, clock));
    if (setup.display) {
        core->player_.backends.display = std::move(setup.display);
        core->player_.backends.displayReport.chosen = setup.displayName;
    }
    if (std::optional<PlayOpenFailure> bad =
            openPlayer(opt, clock, core->player_, setup.opened, setup.feed))
        return bad;
    player::PlayerSettings settings = playerSettings(opt);
    settings.keys = std::move(setup.keys);
    core->machine_ =
        std::make_unique<player::StateMachine>(*core->player_.playback, std::move(settings));
    if (!opt.control.empty()) {
        auto s = control::ControlServer::create(opt.control, *core->machine_);
        if (!s) {
            char why[160];
            PlayOpenFailure f;
            f.part = PlayPart::ControlSocket;
            f.message = "cannot create the control socket " +
                        platform::quotedText(opt.control, 120) + ": " +
                        s.error().format(why, sizeof why);
            f.badInput = controlSocketBadInput(s.error());
            f.error = s.error();
            return f;
        }
        core->server_ = std::move(*s);
    }
    core->loop_ =
        std::make_unique<control::ControlLoop>(*core->machine_, core->player_.backends.remote.get(),
                                               core->server_.get(), clock, setup.slice);
    out = std::move(core);
    return std::nullopt;
}

PlayerCore::~PlayerCore()
{
    loop_.reset();
    server_.reset();
    if (!finished_ && player_.playback) {
        (void)player_.playback->stop();
        player_.playback->close();
    }
}

control::LoopOutcome PlayerCore::run(const std::function<void()> &eachTurn,
                                     const std::atomic<bool> &stop,
                                     const control::PlayLimits &limits,
                                     const control::OnSocketFailure &socketFailed)
{
    return control::playUntilDone(*machine_, *loop_, server_, eachTurn, stop, limits, clock_,
                                  socketFailed);
}

playback::PlayRunFigures PlayerCore::finish(const control::LoopOutcome &out)
{
    playback::Playback &playback = *player_.playback;
    PlayBackends &b = player_.backends;
    (void)playback.stop();
    playback.close(); // the recording ends and the snapshots are written: their losses count
    finished_ = true;

    playback::PlayRunFigures run;
    run.info = &playback.info();
    run.stats = playback.stats();
    run.haptic = playback.hapticStats();
    run.display = b.displayReport.chosen;
    if (run.display == "headless" && options_.display != "headless")
        run.displayNote = "no screen found (x11 needs $DISPLAY, kms a free DRM card): the picture "
                          "was drawn offscreen; --display x11 or kms shows it (docs/playing.md)";
    run.hapticDevice = b.hapticReport.chosen;
    run.remoteConnected = machine_->remoteConnected();
    run.audioDevice = b.audio ? b.audioReport.chosen : std::string();
    if (b.audio) {
        b.audio->close(); // closed by playback.close(); a file output is finished by now
        run.audioOutputLost = b.audio->lostOutput();
    }
    run.deviceMaxForce = b.device->capabilities().maxForce;
    run.rssStart = out.rssStart;
    run.rssAfterWarmup = out.rssAfterWarmup;
    run.rssEnd = out.rssEnd;
    run.lockedMiB = out.lockedMiB;
    run.finalState = player::playerStateName(machine_->state());
    run.failure = out.failure;
    return run;
}

} // namespace depthtouch::cli
