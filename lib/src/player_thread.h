#pragma once
/// \file
/// \brief The player thread of a dt_handle: it opens the backends and the Playback through `play`'s
/// own path (app/cli/play_backends.h: the backend table, drivers/backends.h), makes the state
/// machine, and runs the loop of `play` (app/control/play_loop.h) in 10 ms turns: the pipeline's
/// report, the control socket (option "control") and the remote (option "remote"), the observers;
/// between turns it carries out the calls the API posts (call(), post()), at once when one comes.
/// Unlike `play`, it stays up when a file ends or fails (idle, as libmpv), until quit or destroy.
/// Thread-safety: call(), post() and the destructor are thread-safe; what they run runs on the
/// player thread.

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
    /// Runs the loop until quit or stop_. \a eachTurn runs after the calls of each turn.
    void loop(Session &session, player::StateMachine &machine,
              const std::function<void()> &eachTurn, double duration);
    /// Takes the tasks queued, waiting up to 10 ms for one (or for stop_).
    std::deque<std::shared_ptr<Task>> takeTasks();
    /// Answers the tasks still queued with DT_ERROR_UNINITIALIZED (the player quit).
    void refuseQueued();

    EventQueue &events_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::shared_ptr<Task>> tasks_;
    bool stop_ = false;  ///< The destructor asks the loop to quit.
    bool ended_ = false; ///< The loop ended: calls are refused.
    std::thread thread_;
};

} // namespace depthtouch::client
