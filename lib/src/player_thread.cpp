/// \file
/// \brief The player thread of a dt_handle: see player_thread.h.

#include "player_thread.h"

#include <chrono>
#include <exception>
#include <future>
#include <optional>
#include <string>
#include <utility>

#include "depthtouch/control/control_loop.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/audio_reader.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/output_paths.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "play_options.h"

DT_LOG_CATEGORY(Client)

namespace depthtouch::client {

/// A call waiting for the player thread.
struct PlayerThread::Task {
    Call call;
    std::promise<int> done; ///< Set for call(); unused for post().
    bool async = false;
    std::uint64_t userdata = 0;
};

/// The backends of a player (as `play`'s): destroyed after the Playback.
struct PlayerThread::Backends {
    std::unique_ptr<hal::Display> display;
    std::unique_ptr<hal::HapticDevice> device;
    std::unique_ptr<hal::RemoteInput> remote;
    std::unique_ptr<hal::AudioOutput> audio;
    bool noDevice = false; ///< The haptic backend chosen is `none`.
};

namespace {

/// \return \a cfg with the backend options \a options.
hal::BackendConfig withOptions(const hal::BackendConfig &cfg, const std::string &options)
{
    hal::BackendConfig c = cfg;
    c.options = hal::OptionList(options);
    return c;
}

/// Moves \a made into \a into. \return DT_ERROR_SUCCESS, DT_ERROR_OPTION_FORMAT for a name or an
/// option at fault (InvalidArgument), else \a failure; logs the reason.
template <class T>
int take(Result<std::unique_ptr<T>> made, const hal::SelectionReport &report,
         std::unique_ptr<T> &into, int failure)
{
    if (!made) {
        DT_LOG(Client, Error, "%s", report.message.c_str());
        return made.error().code == Errc::InvalidArgument ? DT_ERROR_OPTION_FORMAT : failure;
    }
    into = std::move(*made);
    return DT_ERROR_SUCCESS;
}

/// Checks the output paths of \a opt as `play` does. \return DT_ERROR_SUCCESS or
/// DT_ERROR_INVALID_PARAMETER (logged).
int checkOutputs(const cli::PlayOptions &opt)
{
    const std::string wav =
        opt.noAudio ? std::string()
                    : drivers::audioOutputFilePath(opt.audioDevice, opt.audioDeviceOptions);
    for (const platform::OutputPathCheck &c :
         {platform::checkOutputPath("--record", opt.record),
          platform::checkOutputPath("--force-log", opt.forceLog),
          platform::checkOutputPath("--av-log", opt.avLog),
          platform::checkOutputPath("--stats", opt.stats, true),
          platform::checkOutputPath("--audio-device-options path", wav, true),
          platform::checkOutputFolder("--snapshot-dir", opt.snapshotDir)}) {
        if (c.exitCode != platform::kOutputUsable) {
            DT_LOG(Client, Error, "%s", c.message.c_str());
            return DT_ERROR_INVALID_PARAMETER;
        }
    }
    return DT_ERROR_SUCCESS;
}

/// Opens the backends of \a opt into \a b, as `play` does. \return a dt_error code.
int openBackends(const cli::PlayOptions &opt, const hal::BackendConfig &cfg, auto &b)
{
    hal::SelectionReport rep;
    int rc = take(drivers::createDisplay(opt.display, withOptions(cfg, opt.displayOptions), &rep),
                  rep, b.display, DT_ERROR_VO_INIT_FAILED);
    if (rc < 0)
        return rc;
    // As play: a player that stays up (idle) picks its devices up when they are plugged in.
    hal::BackendConfig hapticCfg = withOptions(cfg, opt.hapticOptions);
    hapticCfg.awaitDevice = opt.idle;
    rc = take(drivers::createHapticDevice(opt.haptic, hapticCfg, &rep), rep, b.device,
              DT_ERROR_HAPTIC_INIT_FAILED);
    if (rc < 0)
        return rc;
    b.noDevice = rep.chosen == "none";
    if (!opt.remote.empty() && opt.remote != "none") {
        hal::BackendConfig remoteCfg = withOptions(cfg, opt.remoteOptions);
        remoteCfg.awaitDevice = opt.idle;
        rc = take(drivers::createRemoteInput(opt.remote, remoteCfg, &rep), rep, b.remote,
                  DT_ERROR_GENERIC);
        if (rc < 0)
            return rc;
    }
    if (!opt.noAudio && opt.audioDevice != "none") {
        rc = take(drivers::createAudioOutput(opt.audioDevice,
                                             withOptions(cfg, opt.audioDeviceOptions), &rep),
                  rep, b.audio, DT_ERROR_AO_INIT_FAILED);
        if (rc < 0)
            return rc;
    }
    // The decoder and source are made per open: their names are checked now.
    std::unique_ptr<hal::VideoDecoder> decoder;
    rc = take(drivers::createVideoDecoder(opt.decoder, withOptions(cfg, opt.decoderOptions), &rep),
              rep, decoder, DT_ERROR_OPTION_FORMAT);
    if (rc < 0)
        return rc;
    std::unique_ptr<hal::MediaSource> source;
    return take(drivers::createMediaSource(opt.source, withOptions(cfg, opt.sourceOptions), &rep),
                rep, source, DT_ERROR_OPTION_FORMAT);
}

/// \return the HAL of the player (as `play`'s): \a b's display, device and sound output, a source
/// and decoders per open.
playback::PlaybackHal playbackHal(const cli::PlayOptions &opt, const hal::BackendConfig &cfg,
                                  const auto &b)
{
    playback::PlaybackHal ph;
    ph.makeSource = [name = opt.source, c = withOptions(cfg, opt.sourceOptions)]() {
        return drivers::createMediaSource(name, c);
    };
    ph.makeDecoder = [name = opt.decoder, c = withOptions(cfg, opt.decoderOptions)](
                         const hal::StreamInfo &) { return drivers::createVideoDecoder(name, c); };
    ph.display = b.display.get();
    ph.device = b.noDevice ? nullptr : b.device.get();
    ph.clock = cfg.clock;
    ph.audioOutput = b.audio.get();
    ph.makeAudioSource = [](const std::string &url) -> Result<std::unique_ptr<hal::AudioSource>> {
        auto reader = media::AudioReader::open(url);
        if (!reader)
            return unexpected(reader.error());
        return std::unique_ptr<hal::AudioSource>(std::move(*reader));
    };
    ph.makeLiveAudioSource =
        [](const hal::AudioStreamInfo &stream) -> Result<playback::PlaybackHal::LiveAudio> {
        auto reader = media::AudioReader::fromPackets(stream);
        if (!reader)
            return unexpected(reader.error());
        playback::PlaybackHal::LiveAudio live;
        live.sink = (*reader)->packetSink();
        live.source = std::move(*reader);
        return live;
    };
    return ph;
}

/// \return the state machine's settings of \a opt (as `play`'s; nothing to open yet).
player::PlayerSettings playerSettings(const cli::PlayOptions &opt)
{
    player::PlayerSettings settings;
    settings.loop = opt.loop;
    settings.reopenWhenSilent = opt.idle;
    settings.stereoMode = *player::stereoModeFromName(opt.stereo);
    settings.haptics = true;
    settings.stiffness = opt.stiffness;
    settings.volume = opt.volume;
    settings.mute = opt.mute;
    return settings;
}

} // namespace

PlayerThread::PlayerThread(EventQueue &events) : events_(events) {}

int PlayerThread::start(const cli::PlayOptions &options, const std::vector<ObserverSpec> &observers,
                        EventQueue &events, std::unique_ptr<PlayerThread> &out)
{
    if (!cli::checkPlayOptionValues(options).empty())
        return DT_ERROR_OPTION_FORMAT;
    if (const int rc = checkOutputs(options); rc < 0)
        return rc;
    std::unique_ptr<PlayerThread> t(new PlayerThread(events));
    auto started = std::make_shared<std::promise<int>>();
    std::future<int> result = started->get_future();
    t->thread_ = std::thread(&PlayerThread::runGuarded, t.get(), options, observers,
                             [started](int rc) { started->set_value(rc); });
    const int rc = result.get();
    if (rc < 0) {
        t->thread_.join(); // the thread ends after a failed open
        return rc;
    }
    out = std::move(t);
    return DT_ERROR_SUCCESS;
}

PlayerThread::~PlayerThread()
{
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable())
        thread_.join();
}

int PlayerThread::call(Call c)
{
    auto task = std::make_shared<Task>();
    task->call = std::move(c);
    std::future<int> result = task->done.get_future();
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (ended_)
            return DT_ERROR_UNINITIALIZED;
        tasks_.push_back(task);
    }
    cv_.notify_all();
    return result.get();
}

int PlayerThread::post(std::uint64_t userdata, Call c)
{
    auto task = std::make_shared<Task>();
    task->call = std::move(c);
    task->async = true;
    task->userdata = userdata;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (ended_)
            return DT_ERROR_UNINITIALIZED;
        tasks_.push_back(std::move(task));
    }
    cv_.notify_all();
    return DT_ERROR_SUCCESS;
}

std::deque<std::shared_ptr<PlayerThread::Task>> PlayerThread::takeTasks()
{
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, std::chrono::milliseconds(10), [this] { return !tasks_.empty() || stop_; });
    return std::exchange(tasks_, {});
}

void PlayerThread::refuseQueued()
{
    std::deque<std::shared_ptr<Task>> left;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        ended_ = true;
        left = std::exchange(tasks_, {});
    }
    for (const std::shared_ptr<Task> &t : left) {
        if (t->async) {
            QueuedEvent e;
            e.id = DT_EVENT_COMMAND_REPLY;
            e.error = DT_ERROR_UNINITIALIZED;
            e.userdata = t->userdata;
            events_.push(std::move(e));
        } else {
            t->done.set_value(DT_ERROR_UNINITIALIZED);
        }
    }
}

void PlayerThread::loop(Session &session, player::StateMachine &machine,
                        const std::function<void()> &eachTurn, double duration)
{
    platform::Clock &clock = platform::SteadyClock::instance();
    const platform::TimePoint begin = clock.now();
    while (!machine.quitRequested()) {
        for (const std::shared_ptr<Task> &t : takeTasks()) {
            int rc = DT_ERROR_GENERIC;
            try {
                rc = t->call(session);
            } catch (const std::bad_alloc &) {
                rc = DT_ERROR_NOMEM;
            } catch (const std::exception &) {
                rc = DT_ERROR_GENERIC;
            }
            if (!t->async) {
                t->done.set_value(rc);
                continue;
            }
            QueuedEvent e;
            e.id = DT_EVENT_COMMAND_REPLY;
            e.error = rc;
            e.userdata = t->userdata;
            events_.push(std::move(e));
        }
        eachTurn();
        session.sendPropertyChanges();
        bool stop = false;
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            stop = stop_;
        }
        if (stop || (duration > 0.0 && platform::toSeconds(clock.now() - begin) >= duration))
            machine.execute("quit");
    }
}

void PlayerThread::run(cli::PlayOptions opt, std::vector<ObserverSpec> observers,
                       const std::function<void(int)> &started)
{
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    Backends b;
    if (const int rc = openBackends(opt, cfg, b); rc < 0) {
        started(rc);
        return;
    }
    auto pb = playback::Playback::create(cli::landPlayOptions(opt), playbackHal(opt, cfg, b));
    if (!pb) {
        DT_LOG(Client, Error, "%s", pb.error().what);
        started(pb.error().code == Errc::InvalidArgument ? DT_ERROR_OPTION_FORMAT
                                                         : DT_ERROR_VO_INIT_FAILED);
        return;
    }
    playback::Playback &playback = **pb;
    player::StateMachine machine(playback, playerSettings(opt));
    Session session(machine, events_);
    std::unique_ptr<control::ControlServer> server;
    if (!opt.control.empty()) {
        auto s = control::ControlServer::create(opt.control, machine);
        if (!s) {
            DT_LOG(Client, Error, "cannot create the control socket: %s", s.error().what);
            started(DT_ERROR_INVALID_PARAMETER);
            return;
        }
        server = std::move(*s);
    }
    for (const ObserverSpec &o : observers)
        (void)session.observe(o); // checked by dt_observe_property()
    auto input = std::make_unique<control::ControlLoop>(machine, b.remote.get(), server.get(),
                                                        clock, std::chrono::milliseconds(1));
    started(DT_ERROR_SUCCESS);

    loop(
        session, machine,
        [&] {
            // The remote's keys wait at most 1 ms; the socket is served without waiting.
            const auto wait =
                b.remote ? std::chrono::milliseconds(1) : std::chrono::milliseconds(0);
            if (auto r = input->runUntil(clock.now() + wait); !r) {
                DT_LOG(Client, Error, "control socket failed: %s", r.error().what);
                input = std::make_unique<control::ControlLoop>(machine, b.remote.get(), nullptr,
                                                               clock, std::chrono::milliseconds(1));
                server.reset();
            }
            playback.report(machine);
        },
        opt.duration);
    (void)playback.stop();
    playback.close();
    input.reset();
    server.reset();
}

void PlayerThread::runGuarded(cli::PlayOptions options, std::vector<ObserverSpec> observers,
                              std::function<void(int)> started)
{
    bool told = false;    // started() was called
    bool running = false; // with success
    const std::function<void(int)> once = [&](int rc) {
        told = true;
        running = rc == DT_ERROR_SUCCESS;
        started(rc);
    };
    try {
        run(std::move(options), std::move(observers), once);
    } catch (const std::bad_alloc &) {
        DT_LOG(Client, Error, "the player thread ran out of memory");
        if (!told)
            started(DT_ERROR_NOMEM);
    } catch (const std::exception &e) {
        DT_LOG(Client, Error, "the player thread failed: %s", e.what());
        if (!told)
            started(DT_ERROR_GENERIC);
    }
    refuseQueued();
    if (!running)
        return;
    QueuedEvent shutdown;
    shutdown.id = DT_EVENT_SHUTDOWN;
    events_.push(std::move(shutdown));
}

} // namespace depthtouch::client
