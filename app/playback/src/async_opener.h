#pragma once
/// \file
/// \brief The blocking part of Playback::open() — the media source's open and the Receiver's
/// probe (a FIFO without a writer, a silent network stream until its time-out, a device nobody
/// writes) — run on a thread of its own, so that the main thread goes on answering the control
/// socket and the remote while an input opens.
///
/// Bounded (issue 60, class 6: zapping): at most kMaxJobs (2) jobs are alive at any time, the one
/// in flight and one being abandoned. A job that is abandoned (a new open, stop(), the player
/// quitting) is interrupted at once: its media source's hal::MediaSource::interrupt()
/// (libavformat's interrupt callback for the ffmpeg source: its blocking call returns within 100
/// ms) and its retry wait are cut short, so it ends within about 100 ms. A start() while two jobs
/// are still alive is kept as the next job (a later start() replaces it: it never costs a thread)
/// and started by poll() once one of them has ended. A source whose open does not honour
/// interrupt() (a backend call blocked in the kernel) thus holds one slot at most, never a thread
/// per zap.
///
/// Each job owns everything it uses (copies of the factories, the URL, the settings, its result);
/// an abandoned job frees its result on its own thread. Threads that have ended are joined by
/// start() and poll(); the destructor interrupts and detaches those still running.
///
/// Thread-safety: start(), poll(), abandon(), the queries and the destructor on one thread (the
/// main thread).

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::playback {

/// \brief Opens a Receiver on a worker thread. See the file comment.
class AsyncOpener {
public:
    using SourceFactory = std::function<Result<std::unique_ptr<hal::MediaSource>>()>;
    /// What a finished job gives: the receiver, or why it failed (one line, e.g. "cannot open
    /// 'x.mkv': No such file").
    struct Outcome {
        std::unique_ptr<receiver::Receiver> receiver;
        std::string error; ///< Empty on success.
        /// Whose failure: the input's (InvalidArgument) or the system's (OutOfResources: the
        /// opening thread could not be started).
        Errc kind = Errc::InvalidArgument;
    };
    /// The most jobs (threads) alive at once: the one in flight and one being abandoned.
    static constexpr std::size_t kMaxJobs = 2;

    /// \a clock times the retries' waits (start()'s untilOpened); it must outlive every job (the
    /// default, SteadyClock::instance(), is never destroyed).
    explicit AsyncOpener(platform::Clock &clock = platform::SteadyClock::instance()) noexcept;
    AsyncOpener(const AsyncOpener &) = delete;
    AsyncOpener &operator=(const AsyncOpener &) = delete;
    /// Abandons (interrupts) every job and detaches the threads still running; never blocks.
    ~AsyncOpener();

    /// \brief Starts opening \a url: makeSource(), then receiver::Receiver::open() with
    /// \a makeDecoder and \a config, on a new thread. The job in flight, if any, is abandoned
    /// first (interrupted). When kMaxJobs jobs are still alive the open is kept and started by
    /// poll() as soon as one of them ends. With \a untilOpened a failed open is tried again every
    /// 0.5 s until one succeeds or the job is abandoned (a live address waiting for its next
    /// sender); its failures are not reported.
    /// \return false when no thread could be started (\a error then says why).
    bool start(SourceFactory makeSource, std::string url, receiver::DecoderFactory makeDecoder,
               const receiver::ReceiverConfig &config, std::string &error,
               bool untilOpened = false);
    /// \brief Joins the jobs that have ended and starts the kept open when a slot is free.
    /// \return the outcome of the job in flight once it has finished (once; the opener is then
    /// idle), or nullopt while it runs or when no job was started. A kept open whose thread
    /// cannot be started is an outcome with an error. Never blocks.
    std::optional<Outcome> poll();
    /// \brief Drops the job in flight, if any, and the kept open: the job is interrupted and ends
    /// on its thread (which start() or poll() joins later); its receiver, if it ever opens one,
    /// is closed there. Never blocks.
    void abandon() noexcept;
    /// \return true while an open is in flight or kept (started and not yet polled or abandoned).
    [[nodiscard]] bool busy() const noexcept { return current_ != nullptr || next_ != nullptr; }
    /// \return the jobs whose threads have not been joined yet (at most kMaxJobs).
    [[nodiscard]] std::size_t jobsAlive() const noexcept { return jobs_.size(); }

    struct Job;     ///< One open on its thread (async_opener.cpp).
    struct Request; ///< What start() was asked to open (async_opener.cpp).

private:
    /// Joins and drops the jobs (abandoned, or in flight when \a withCurrent) that have ended.
    void reap(bool withCurrent) noexcept;
    /// Starts the kept open on a new thread when fewer than kMaxJobs jobs are alive.
    /// \return false when its thread could not be started (\a error says why).
    bool launchNext(std::string &error);

    platform::Clock &clock_;
    std::vector<std::shared_ptr<Job>> jobs_; ///< Alive: started, thread not joined yet.
    std::shared_ptr<Job> current_;           ///< The job in flight (one of jobs_), or null.
    std::unique_ptr<Request> next_;          ///< The open kept until a slot frees, or null.
};

} // namespace depthtouch::playback
