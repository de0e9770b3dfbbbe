#pragma once
/// \file
/// \brief The blocking part of Playback::open() — the media source's open and the Receiver's
/// probe (a FIFO without a writer blocks in open(2), a silent network stream until its timeout)
/// — run on a thread of its own, so that the main thread goes on answering the control socket
/// and the remote while an input opens.
///
/// Each start() runs one job on a new thread. The job owns everything it uses (copies of the
/// factories, the URL, the settings, its result), so a job that is abandoned (a new open, stop(),
/// the player quitting) is left to finish on its detached thread and frees its result there;
/// nothing of the opener is touched by it. A job blocked for ever in the kernel (a FIFO never
/// written) thus never blocks the player; it ends with the process.
///
/// Thread-safety: start(), poll(), abandon() and the destructor on one thread (the main thread).

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "depthtouch/hal/media_source.h"
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
    };

    AsyncOpener() = default;
    AsyncOpener(const AsyncOpener &) = delete;
    AsyncOpener &operator=(const AsyncOpener &) = delete;
    /// Abandons the running job (see the file comment); never blocks.
    ~AsyncOpener();

    /// \brief Starts opening \a url: makeSource(), then receiver::Receiver::open() with
    /// \a makeDecoder and \a config, on a new thread. A job still running is abandoned first.
    /// With \a untilOpened a failed open is tried again every 0.5 s until one succeeds or the
    /// job is abandoned (a live address waiting for its next sender); its failures are not
    /// reported.
    /// \return false when no thread could be started (\a error then says why).
    bool start(SourceFactory makeSource, std::string url, receiver::DecoderFactory makeDecoder,
               const receiver::ReceiverConfig &config, std::string &error,
               bool untilOpened = false);
    /// \return the outcome once the job has finished (once; the opener is then idle), or nullopt
    /// while it runs or when no job was started. Never blocks.
    std::optional<Outcome> poll();
    /// \brief Drops the running job, if any: its thread is detached and its receiver, if it ever
    /// opens one, is closed on that thread. Never blocks.
    void abandon() noexcept;
    /// \return true while a job runs (started and not yet polled or abandoned).
    [[nodiscard]] bool busy() const noexcept { return job_ != nullptr; }

private:
    struct Job;
    std::shared_ptr<Job> job_;
};

} // namespace depthtouch::playback
