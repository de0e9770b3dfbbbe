/// \file
/// \brief play's player fed by depthtouchsink's pads: see feed_player.h.

#include "feed_player.h"

#include <chrono>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/options/option_range.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/player/command.h"
#include "depthtouch/player/state_machine.h"
#include "play_backends.h"
#include "play_options.h"
#include "player_core.h"

namespace depthtouch::gst {

namespace {

/// The url the state machine opens: any text (PadMediaSource reads the pads whatever it is).
constexpr const char *kFeedUrl = "depthtouchsink:pads";
/// Loop turns (10 ms each) between two readouts.
constexpr int kReadoutTurns = 10;

/// \return play's options with \a s in them; the rest at play's defaults, without sound or remote.
cli::PlayOptions playOptionsOf(const PlayerSettings &s)
{
    cli::PlayOptions o;
    o.url = kFeedUrl;
    o.haptic = s.haptic.device;
    o.hapticOptions = s.haptic.deviceOptions;
    o.stiffness = s.haptic.stiffness;
    o.method = s.haptic.method;
    o.display = s.display;
    o.displayOptions = s.displayOptions;
    o.control = s.control;
    o.noAudio = true;
    o.remote = "none";
    return o;
}

/// \return the one line of \a f: which backend failed and why.
std::string failureLine(const cli::PlayOptions &o, const cli::PlayOpenFailure &f)
{
    switch (f.part) {
    case cli::PlayPart::Display:
        return "cannot open the display '" + o.display + "': " + f.message;
    case cli::PlayPart::HapticDevice:
        return "cannot open the haptic device '" + o.haptic + "': " + f.message;
    default:
        return f.message;
    }
}

/// \return what \a pb and \a machine tell now; the force of \a last when no task runs any more.
PlayerReadout readOut(playback::Playback &pb, const player::StateMachine &machine,
                      const PlayerReadout &last)
{
    PlayerReadout r;
    r.state = player::playerStateName(machine.state());
    const playback::PlaybackStats st = pb.stats();
    r.framesPaired = st.receiver.framesOutput;
    r.framesPresented = st.framesPresented;
    r.depthMissing = st.receiver.depthMissing;
    r.depthUnpaired = st.receiver.depthUnpaired;
    r.depthPairsPublished = st.depthPairsPublished;
    r.position = pb.position();
    r.gl = pb.info().gl;
    r.haptics = pb.info().haptics;
    if (const auto hs = pb.hapticStats()) {
        r.hapticUpdates = hs->updates;
        r.safetyTrips = hs->safetyReleases;
        r.watchdogTrips = hs->watchdogTrips;
        r.pageFaults = hs->pageFaultsMinor + hs->pageFaultsMajor;
        r.maxForce = hs->maxForce;
        r.servoRateHz = hs->updates > 1 && hs->runSeconds > 0.0
                            ? static_cast<double>(hs->updates - 1) / hs->runSeconds
                            : 0.0;
    }
    if (const haptic_task::HapticTask *task = pb.hapticTask()) {
        const glm::dvec3 f = task->lastForce();
        r.forceZ = f.z;
        r.force = glm::length(f);
    } else {
        r.forceZ = last.forceZ;
        r.force = last.force;
    }
    return r;
}

} // namespace

std::unique_ptr<FeedPlayer> FeedPlayer::open(const PlayerSettings &settings,
                                             std::shared_ptr<PadFeed> feed,
                                             std::function<playback::MasterClock()> masterClock,
                                             std::string &why)
{
    auto options = std::make_unique<cli::PlayOptions>(playOptionsOf(settings));
    why = checkHapticSettings(settings.haptic);
    if (!why.empty())
        return nullptr;
    if (why = cli::checkPlayOptionValues(*options); !why.empty())
        return nullptr;
    // play's own player core (cli::PlayerCore), its source the pads: without sound or remote
    // (playOptionsOf()), a pause in the pipeline not a silent sender.
    cli::PlayerFeed pads;
    pads.makeSource = [feed]() -> Result<std::unique_ptr<hal::MediaSource>> {
        return std::unique_ptr<hal::MediaSource>(std::make_unique<PadMediaSource>(feed));
    };
    pads.masterClock = std::move(masterClock);
    cli::PlayerCoreSetup setup;
    setup.feed = &pads;
    setup.slice = std::chrono::milliseconds(1);
    std::unique_ptr<cli::PlayerCore> core;
    if (const auto bad = cli::PlayerCore::open(*options, platform::SteadyClock::instance(),
                                               std::move(setup), core)) {
        why = failureLine(*options, *bad);
        return nullptr;
    }
    std::unique_ptr<FeedPlayer> p(new FeedPlayer(std::move(options), std::move(core)));
    p->feed_ = std::move(feed);
    return p;
}

FeedPlayer::FeedPlayer(std::unique_ptr<cli::PlayOptions> options,
                       std::unique_ptr<cli::PlayerCore> core)
    : options_(std::move(options)), core_(std::move(core)),
      deviceName_(core_->backends().hapticReport.chosen),
      displayName_(core_->backends().displayReport.chosen), stiffness_(options_->stiffness)
{
}

FeedPlayer::~FeedPlayer()
{
    stop_.store(true);
    if (feed_)
        feed_->shutdown();
    if (thread_.joinable())
        thread_.join();
    core_.reset(); // the socket, the Playback stopped and closed, then its backends
}

std::string FeedPlayer::start(std::function<void(const std::string &)> onEnd)
{
    if (thread_.joinable())
        return "started twice";
    thread_ = std::thread([this, onEnd = std::move(onEnd)] { run(onEnd); });
    return {};
}

PlayerReadout FeedPlayer::readout()
{
    const std::lock_guard lock(mutex_);
    return readout_;
}

void FeedPlayer::run(const std::function<void(const std::string &)> &onEnd)
{
    playback::Playback &pb = core_->playback();
    player::StateMachine &machine = core_->machine();
    int turn = 0;
    double stiffness = options_->stiffness;
    std::uint64_t flushSeeks = 0; // those taken: a flush before the loop started is taken first
    const auto eachTurn = [&] {
        if (const std::uint64_t n = flushSeeks_.load(); n != flushSeeks) {
            flushSeeks = n;
            // The pads' running time starts from 0 again: the player's timeline with it. Where
            // nothing is open, the next open reads from the pads' next frames anyway.
            (void)pb.seek(0.0, player::SeekMode::Absolute);
        }
        pb.report(machine);
        const player::PlayerState st = machine.state();
        if (wantPaused_.load() && st == player::PlayerState::Playing)
            machine.execute("pause");
        else if (!wantPaused_.load() && st == player::PlayerState::Paused)
            machine.execute("play");
        if (const double k = stiffness_.load(); k != stiffness) {
            stiffness = k;
            machine.execute("stiffness " + options::OptionRange::number(k));
        }
        if (++turn % kReadoutTurns == 0) {
            PlayerReadout r = readOut(pb, machine, readout());
            const std::lock_guard lock(mutex_);
            readout_ = std::move(r);
        }
    };
    const control::LoopOutcome out = core_->run(eachTurn, stop_, {}, [](const Error &e) {
        platform::printStderrLine(platform::LogLevel::Error,
                                  "depthtouchsink: control socket failed: %s", e.what);
    });
    {
        PlayerReadout r = readOut(pb, machine, readout());
        const std::lock_guard lock(mutex_);
        readout_ = std::move(r);
    }
    (void)pb.stop();
    if (!stop_.load() && onEnd)
        onEnd(out.failure);
}

} // namespace depthtouch::gst
