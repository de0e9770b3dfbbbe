/// \file
/// \brief AsyncOpener: see async_opener.h.

#include "async_opener.h"

#include "depthtouch/platform/clock.h"

#include <atomic>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace depthtouch::playback {

struct AsyncOpener::Job {
    std::mutex mutex;
    bool done = false; ///< Guarded by mutex.
    Outcome outcome;   ///< Guarded by mutex; written once, before done.
    std::thread thread;
    std::atomic<bool> abandoned{false}; ///< Set by abandon(): a retrying job stops trying.
};

namespace {

AsyncOpener::Outcome openReceiver(const AsyncOpener::SourceFactory &makeSource,
                                  const std::string &url,
                                  const receiver::DecoderFactory &makeDecoder,
                                  const receiver::ReceiverConfig &config, bool &noSource)
{
    AsyncOpener::Outcome out;
    auto source = makeSource();
    if (!source) {
        noSource = true;
        out.error = std::string("no media source: ") + source.error().what;
        return out;
    }
    auto rec = receiver::Receiver::open(std::move(*source), url.c_str(), makeDecoder, config);
    if (!rec) {
        out.error = "cannot open '" + url + "': " + rec.error().what;
        return out;
    }
    out.receiver = std::move(*rec);
    return out;
}

/// Opens as openReceiver() does; with \a untilOpened a failed open (no sender yet: the source's
/// time-out, a refused connection) is tried again every kRetryInterval until one succeeds or the
/// job is abandoned. A source that cannot be made at all is not retried.
AsyncOpener::Outcome openWithRetries(const AsyncOpener::SourceFactory &makeSource,
                                     const std::string &url,
                                     const receiver::DecoderFactory &makeDecoder,
                                     const receiver::ReceiverConfig &config, bool untilOpened,
                                     const std::atomic<bool> &abandoned)
{
    constexpr auto kRetryInterval = std::chrono::milliseconds(500);
    for (;;) {
        bool noSource = false;
        AsyncOpener::Outcome out = openReceiver(makeSource, url, makeDecoder, config, noSource);
        if (out.receiver || !untilOpened || noSource || abandoned.load())
            return out;
        platform::SteadyClock::instance().sleepFor(kRetryInterval);
        if (abandoned.load())
            return out;
    }
}

} // namespace

AsyncOpener::~AsyncOpener()
{
    abandon();
}

bool AsyncOpener::start(SourceFactory makeSource, std::string url,
                        receiver::DecoderFactory makeDecoder,
                        const receiver::ReceiverConfig &config, std::string &error,
                        bool untilOpened)
{
    abandon();
    auto job = std::make_shared<Job>();
    try {
        // The thread holds the job (and its own copies of what it uses) until it ends.
        job->thread =
            std::thread([job, makeSource = std::move(makeSource), url = std::move(url),
                         makeDecoder = std::move(makeDecoder), config, untilOpened]() mutable {
                Outcome out = openWithRetries(makeSource, url, makeDecoder, config, untilOpened,
                                              job->abandoned);
                std::lock_guard<std::mutex> lock(job->mutex);
                job->outcome = std::move(out);
                job->done = true;
            });
    } catch (const std::system_error &e) {
        error = std::string("cannot start the opening thread: ") + e.what();
        return false;
    }
    job_ = std::move(job);
    return true;
}

std::optional<AsyncOpener::Outcome> AsyncOpener::poll()
{
    if (!job_)
        return std::nullopt;
    Outcome out;
    {
        std::lock_guard<std::mutex> lock(job_->mutex);
        if (!job_->done)
            return std::nullopt;
        out = std::move(job_->outcome);
    }
    job_->thread.join(); // it has finished its work: only its return is left
    job_.reset();
    return out;
}

void AsyncOpener::abandon() noexcept
{
    if (!job_)
        return;
    job_->abandoned.store(true);
    if (job_->thread.joinable())
        job_->thread.detach();
    job_.reset();
}

} // namespace depthtouch::playback
