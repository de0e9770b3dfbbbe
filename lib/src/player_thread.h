#pragma once
/// \file
/// \brief The player thread of a dt_handle: it runs `play`'s own player core
/// (app/cli/player_core.h: the backend table, the Playback, the state machine, the control socket
/// of option "control", the remote of option "remote" and `play`'s loop, app/control/play_loop.h);
/// each turn of the loop it gives the pipeline's report, carries out the calls the API posts
/// (call(), post()), waiting up to 10 ms for one and at once when one comes, and tells the
/// observers. Unlike `play`, it stays up when a file ends or fails (idle, as libmpv), until quit or
/// destroy. Thread-safety: call(), post() and the destructor are thread-safe; what they run runs on
/// the player thread.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "event_queue.h"
#include "host_frames.h"
#include "play.h"
#include "session.h"

namespace depthtouch::client {

class PlayerThread {
public:
    /// A call carried out on the player thread: \return a dt_error code.
    using Call = std::function<int(Session &)>;

    /// \brief Starts the thread, which opens the backends of \a options and adds \a observers;
    /// with \a render (the render API's frames; may be null) its display is the render API's
    /// (makeHostDisplay(), options "display-options") instead of the option "display"'s.
    /// \return DT_ERROR_SUCCESS with the thread in \a out, or the error of the failed open
    /// (DT_ERROR_VO_INIT_FAILED, _HAPTIC_INIT_FAILED, _AO_INIT_FAILED, _OPTION_FORMAT,
    /// _INVALID_PARAMETER, _GENERIC); then no thread runs.
    static int start(const cli::PlayOptions &options, const std::vector<ObserverSpec> &observers,
                     std::shared_ptr<HostFrames> render, EventQueue &events,
                     std::unique_ptr<PlayerThread> &out);

    /// Quits the player (when it has not quit), stops playback and joins the thread.
    ~PlayerThread();
    PlayerThread(const PlayerThread &) = delete;
    PlayerThread &operator=(const PlayerThread &) = delete;

    /// \brief Runs \a call on the player thread and waits for it.
    /// \return its code, or DT_ERROR_UNINITIALIZED when the player has quit.
    int call(Call call);
    /// \brief Queues \a call; its code comes as DT_EVENT_COMMAND_REPLY with \a userdata.
    /// \return DT_ERROR_SUCCESS, or DT_ERROR_UNINITIALIZED when the player has quit.
    int post(std::uint64_t userdata, Call call);

private:
    struct Task;

    explicit PlayerThread(EventQueue &events);
    /// The thread: opens, reports the open's code through \a started, then runs the loop.
    void run(cli::PlayOptions options, std::vector<ObserverSpec> observers,
             const std::shared_ptr<HostFrames> &render, const std::function<void(int)> &started);
    /// run() with every exception caught (logged; an open not yet reported is DT_ERROR_NOMEM or
    /// DT_ERROR_GENERIC), then the queued calls refused and DT_EVENT_SHUTDOWN queued.
    void runGuarded(cli::PlayOptions options, std::vector<ObserverSpec> observers,
                    std::shared_ptr<HostFrames> render, std::function<void(int)> started);
    /// Carries out the calls queued (waiting up to 10 ms for one, or for stop_) on \a session.
    void runTasks(Session &session);
    /// Takes the tasks queued, waiting up to 10 ms for one (or for stop_).
    std::deque<std::shared_ptr<Task>> takeTasks();
    /// Answers the tasks still queued with DT_ERROR_UNINITIALIZED (the player quit).
    void refuseQueued();

    EventQueue &events_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::shared_ptr<Task>> tasks_;
    std::atomic<bool> stop_{false}; ///< The destructor asks the loop to quit (set under mutex_).
    bool ended_ = false;            ///< The loop ended: calls are refused.
    std::thread thread_;
};

} // namespace depthtouch::client
