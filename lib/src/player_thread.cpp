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
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/output_paths.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "depthtouch/playback/play_report.h"
#include "play_backends.h"
#include "play_config_files.h"
#include "play_options.h"
#include "player_core.h"

DT_LOG_CATEGORY(Client)

namespace depthtouch::client {

/// A call waiting for the player thread.
struct PlayerThread::Task {
    Call call;
    std::promise<int> done; ///< Set for call(); unused for post().
    bool async = false;
    std::uint64_t userdata = 0;
};

namespace {

/// \return the dt_error code of a player \a f says could not be opened, as `play` would open it
/// (its line logged): DT_ERROR_OPTION_FORMAT for a name or option at fault, else the part's.
int openErrorCode(const cli::PlayOpenFailure &f)
{
    DT_LOG(Client, Error, "%s", f.message.c_str());
    if (f.badInput)
        return DT_ERROR_OPTION_FORMAT;
    switch (f.part) {
    case cli::PlayPart::Display:
    case cli::PlayPart::Playback:
        return DT_ERROR_VO_INIT_FAILED;
    case cli::PlayPart::HapticDevice:
        return DT_ERROR_HAPTIC_INIT_FAILED;
    case cli::PlayPart::AudioOutput:
        return DT_ERROR_AO_INIT_FAILED;
    case cli::PlayPart::VideoDecoder:
    case cli::PlayPart::MediaSource:
        return DT_ERROR_OPTION_FORMAT;
    case cli::PlayPart::ControlSocket:
        return DT_ERROR_INVALID_PARAMETER;
    case cli::PlayPart::RemoteInput:
        break;
    }
    return DT_ERROR_GENERIC;
}

} // namespace

PlayerThread::PlayerThread(EventQueue &events) : events_(events) {}

int PlayerThread::start(const cli::PlayOptions &options, const std::vector<ObserverSpec> &observers,
                        std::shared_ptr<HostFrames> render, EventQueue &events,
                        std::unique_ptr<PlayerThread> &out)
{
    if (!cli::checkPlayOptionValues(options).empty())
        return DT_ERROR_OPTION_FORMAT;
    // The output paths, checked as `play` checks them.
    if (const platform::OutputPathCheck c = cli::checkPlayOutputs(options, false);
        c.exitCode != platform::kOutputUsable) {
        DT_LOG(Client, Error, "%s", c.message.c_str());
        return DT_ERROR_INVALID_PARAMETER;
    }
    std::unique_ptr<PlayerThread> t(new PlayerThread(events));
    auto started = std::make_shared<std::promise<int>>();
    std::future<int> result = started->get_future();
    t->thread_ = std::thread(&PlayerThread::runGuarded, t.get(), options, observers,
                             std::move(render), [started](int rc) { started->set_value(rc); });
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
        stop_.store(true);
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

void PlayerThread::runTasks(Session &session)
{
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
}

void PlayerThread::run(cli::PlayOptions opt, std::vector<ObserverSpec> observers,
                       const std::shared_ptr<HostFrames> &render,
                       const std::function<void(int)> &started)
{
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    cli::PlayerCoreSetup setup;
    if (render) {
        // The render API: the host's framebuffer instead of a display of the player's own.
        auto d = makeHostDisplay(render, clock, opt.displayOptions);
        if (!d) {
            DT_LOG(Client, Error, "render API: %s", d.error().what);
            started(DT_ERROR_OPTION_FORMAT);
            return;
        }
        setup.display = std::move(*d);
        setup.displayName = "render-api";
    }
    setup.slice = std::chrono::milliseconds(1);
    // The key map file of option "input-conf" (libmpv reads no config files of its own: neither
    // /etc/depthtouch's nor the user's).
    if (const std::string e = cli::loadKeyMapFiles(cli::keyMapFiles({}, opt), setup.keys);
        !e.empty()) {
        DT_LOG(Client, Error, "%s", e.c_str());
        started(DT_ERROR_OPTION_FORMAT);
        return;
    }
    std::unique_ptr<cli::PlayerCore> core;
    if (const std::optional<cli::PlayOpenFailure> bad =
            cli::PlayerCore::open(opt, clock, std::move(setup), core)) {
        started(openErrorCode(*bad));
        return;
    }
    playback::Playback &playback = core->playback();
    player::StateMachine &machine = core->machine();
    Session session(machine, events_);
    for (const ObserverSpec &o : observers)
        (void)session.observe(o); // checked by dt_observe_property()
    started(DT_ERROR_SUCCESS);

    // play's loop (the player core's), idle as libmpv: it stays up when a file ends or fails,
    // until quit or destroy. Each turn serves the remote (waiting at most 1 ms for its keys) and
    // the socket, then the pipeline's report, then the API's calls (waiting up to 10 ms for one).
    control::PlayLimits limits;
    limits.duration = opt.duration;
    limits.idle = true;
    limits.start = false; // its file comes by dt_command() loadfile
    limits.turn =
        core->backends().remote ? std::chrono::milliseconds(1) : std::chrono::milliseconds(0);
    const control::LoopOutcome out = core->run(
        [&] {
            playback.report(machine);
            runTasks(session);
            session.sendPropertyChanges();
        },
        stop_, limits,
        [](const Error &e) { DT_LOG(Client, Error, "control socket failed: %s", e.what); });
    const playback::PlayRunFigures run = core->finish(out);
    // Option "stats": the JSON of `play --stats`, of the last file the player opened.
    if (!opt.stats.empty()) {
        const std::string lost =
            cli::writeStatsFile(opt.stats, playback::playStatsJson(machine.url(), run));
        if (!lost.empty())
            DT_LOG(Client, Error, "%s", lost.c_str());
    }
}

void PlayerThread::runGuarded(cli::PlayOptions options, std::vector<ObserverSpec> observers,
                              std::shared_ptr<HostFrames> render, std::function<void(int)> started)
{
    bool told = false;    // started() was called
    bool running = false; // with success
    const std::function<void(int)> once = [&](int rc) {
        told = true;
        running = rc == DT_ERROR_SUCCESS;
        started(rc);
    };
    try {
        run(std::move(options), std::move(observers), render, once);
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
