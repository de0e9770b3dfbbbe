/// \file
/// \brief AsyncOpener: see async_opener.h.

#include "async_opener.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace depthtouch::playback {

namespace {

/// \brief The media source a job opens, shared between the Receiver (which owns this wrapper)
/// and the job (which interrupts it when abandoned): the source outlives an interrupt() the main
/// thread makes while Receiver::open() drops it. Forwards every call. Thread-safety: as the
/// source's.
class SharedSource final : public hal::MediaSource {
public:
    explicit SharedSource(std::shared_ptr<hal::MediaSource> source) : s_(std::move(source)) {}
    ~SharedSource() override = default;

    [[nodiscard]] State state() const noexcept override { return s_->state(); }
    [[nodiscard]] Result<void> open(const char *url) override { return s_->open(url); }
    void close() noexcept override { s_->close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return s_->info(); }
    [[nodiscard]] Result<hal::Packet> readPacket() override { return s_->readPacket(); }
    [[nodiscard]] Result<void> seek(hal::Pts position) override { return s_->seek(position); }
    void interrupt() noexcept override { s_->interrupt(); }
    void cancelRead() noexcept override { s_->cancelRead(); }
    [[nodiscard]] Result<void> deliverAudio(int containerIndex) override
    {
        return s_->deliverAudio(containerIndex);
    }

private:
    const std::shared_ptr<hal::MediaSource> s_;
};

/// How long a job waits between the tries of an untilOpened open, and in which steps it looks
/// whether it was abandoned meanwhile.
constexpr auto kRetryInterval = std::chrono::milliseconds(500);
constexpr auto kRetryStep = std::chrono::milliseconds(20);

} // namespace

struct AsyncOpener::Request {
    SourceFactory makeSource;
    std::string url;
    receiver::DecoderFactory makeDecoder;
    receiver::ReceiverConfig config;
    bool untilOpened = false;
};

struct AsyncOpener::Job {
    std::mutex mutex;
    bool done = false; ///< Guarded by mutex.
    Outcome outcome;   ///< Guarded by mutex; written once, before done.
    /// The source being opened (Receiver::open() runs on it), null between tries. Guarded by
    /// mutex: abandon() interrupts it under the lock, so it is never destroyed meanwhile.
    std::shared_ptr<hal::MediaSource> source;
    std::thread thread;
    std::atomic<bool> abandoned{false}; ///< Set by abandon(): the job ends as soon as it can.

    /// Main thread: marks the job abandoned and interrupts its source. Never blocks (the job
    /// holds the lock only for a few stores).
    void abandon() noexcept
    {
        const std::lock_guard<std::mutex> lock(mutex);
        abandoned.store(true);
        if (source)
            source->interrupt();
    }
    /// Job thread: \a s is the source from now on. \return false when the job was abandoned
    /// already (then \a s is not to be opened).
    bool publish(std::shared_ptr<hal::MediaSource> s) noexcept
    {
        const std::lock_guard<std::mutex> lock(mutex);
        if (abandoned.load())
            return false;
        source = std::move(s);
        return true;
    }
    void unpublish() noexcept
    {
        const std::lock_guard<std::mutex> lock(mutex);
        source.reset();
    }
    [[nodiscard]] bool finished() noexcept
    {
        const std::lock_guard<std::mutex> lock(mutex);
        return done;
    }
};

namespace {

using Job = AsyncOpener::Job;
using Request = AsyncOpener::Request;
using Outcome = AsyncOpener::Outcome;

Outcome openReceiver(Job &job, const Request &req, bool &noSource)
{
    Outcome out;
    auto made = req.makeSource();
    if (!made) {
        noSource = true;
        out.error = std::string("no media source: ") + made.error().what;
        return out;
    }
    const std::shared_ptr<hal::MediaSource> source(std::move(*made));
    if (!job.publish(source)) {
        out.error = "cannot open '" + req.url + "': abandoned";
        return out;
    }
    auto rec = receiver::Receiver::open(std::make_unique<SharedSource>(source), req.url.c_str(),
                                        req.makeDecoder, req.config);
    job.unpublish();
    if (!rec) {
        out.error = "cannot open '" + req.url + "': " + rec.error().what;
        return out;
    }
    out.receiver = std::move(*rec);
    return out; // a source the receiver does not hold is destroyed here, on the job's thread
}

/// Waits kRetryInterval on \a clock, in kRetryStep steps. \return false when the job was
/// abandoned meanwhile.
bool waitToRetry(const Job &job, platform::Clock &clock)
{
    const platform::TimePoint end = clock.now() + kRetryInterval;
    while (!job.abandoned.load()) {
        const platform::TimePoint now = clock.now();
        if (now >= end)
            return true;
        clock.sleepFor(std::min<platform::Duration>(kRetryStep, end - now));
    }
    return false;
}

/// Opens as openReceiver() does; with Request::untilOpened a failed open (no sender yet: the
/// source's time-out, a refused connection) is tried again every kRetryInterval until one
/// succeeds or the job is abandoned. A source that cannot be made at all is not retried.
Outcome openWithRetries(Job &job, const Request &req, platform::Clock &clock)
{
    for (;;) {
        bool noSource = false;
        Outcome out = openReceiver(job, req, noSource);
        if (out.receiver || !req.untilOpened || noSource || job.abandoned.load())
            return out;
        if (!waitToRetry(job, clock))
            return out;
    }
}

/// The job's thread: opens, then hands the outcome over, or (abandoned) frees it here.
void runJob(Job &job, const Request &req, platform::Clock &clock)
{
    Outcome out = openWithRetries(job, req, clock);
    if (job.abandoned.load())
        out = Outcome{}; // closes the receiver on this thread, not the main one's
    const std::lock_guard<std::mutex> lock(job.mutex);
    if (!job.abandoned.load())
        job.outcome = std::move(out);
    job.done = true;
}

} // namespace

AsyncOpener::AsyncOpener(platform::Clock &clock) noexcept : clock_(clock) {}

AsyncOpener::~AsyncOpener()
{
    abandon();
    for (std::shared_ptr<Job> &job : jobs_) {
        // An interrupted job ends within about 100 ms on its own; nothing here waits for it.
        if (job->thread.joinable())
            job->thread.detach();
    }
}

bool AsyncOpener::start(SourceFactory makeSource, std::string url,
                        receiver::DecoderFactory makeDecoder,
                        const receiver::ReceiverConfig &config, std::string &error,
                        bool untilOpened)
{
    abandon();
    reap(false);
    next_ = std::make_unique<Request>(Request{std::move(makeSource), std::move(url),
                                              std::move(makeDecoder), config, untilOpened});
    return launchNext(error);
}

bool AsyncOpener::launchNext(std::string &error)
{
    if (!next_ || jobs_.size() >= kMaxJobs)
        return true;
    auto job = std::make_shared<Job>();
    std::unique_ptr<Request> req = std::move(next_);
    jobs_.reserve(kMaxJobs);
    try {
        // The thread holds the job and its request until it ends.
        job->thread = std::thread(
            [job, req = std::move(req), &clock = clock_] { runJob(*job, *req, clock); });
    } catch (const std::system_error &e) {
        error = std::string("cannot start the opening thread: ") + e.what();
        return false;
    }
    jobs_.push_back(job);
    current_ = std::move(job);
    return true;
}

void AsyncOpener::reap(bool withCurrent) noexcept
{
    const auto ended = [this, withCurrent](const std::shared_ptr<Job> &job) {
        if ((job == current_ && !withCurrent) || !job->finished())
            return false;
        if (job->thread.joinable())
            job->thread.join(); // it has finished its work: only its return is left
        return true;
    };
    jobs_.erase(std::remove_if(jobs_.begin(), jobs_.end(), ended), jobs_.end());
}

std::optional<AsyncOpener::Outcome> AsyncOpener::poll()
{
    reap(false);
    std::string error;
    if (!launchNext(error))
        return Outcome{nullptr, std::move(error), Errc::OutOfResources};
    if (!current_ || !current_->finished())
        return std::nullopt;
    Outcome out;
    {
        const std::lock_guard<std::mutex> lock(current_->mutex);
        out = std::move(current_->outcome);
    }
    reap(true);
    current_.reset();
    return out;
}

void AsyncOpener::abandon() noexcept
{
    next_.reset();
    if (!current_)
        return;
    current_->abandon();
    current_.reset();
}

} // namespace depthtouch::playback
