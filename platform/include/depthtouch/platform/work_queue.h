#pragma once
/// \file
/// \brief The two sides of a worker thread that waits on a condition variable for jobs (a snapshot
/// writer, a recording encoder, a frame preparer): the owner's stop request, and the worker's wait
/// for its next job from a queue guarded by the same mutex.
/// Thread-safety: as documented per function; they allocate only as the queue's moves do.

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace depthtouch::platform {

/// \brief Sets \a flag to true under \a mutex, then wakes every thread waiting on \a cv: how an
/// owner tells its worker (which waits on \a cv for \a flag) to stop. The caller joins the worker
/// after. Thread-safety: any thread; \a flag must be guarded by \a mutex everywhere.
inline void raiseAndNotifyAll(std::mutex &mutex, bool &flag, std::condition_variable &cv)
{
    {
        const std::lock_guard<std::mutex> lock(mutex);
        flag = true;
    }
    cv.notify_all();
}

/// \brief Waits on \a cv (with \a lock, which holds the mutex guarding \a stop and \a queue) until
/// \a stop is set or \a queue has a job, then takes the job at its front.
/// \return the job, still under \a lock; nullopt when \a stop is set and \a queue is empty (the
/// jobs queued before the stop are all handed out first).
template <class Job>
std::optional<Job> waitForJob(std::unique_lock<std::mutex> &lock, std::condition_variable &cv,
                              const bool &stop, std::deque<Job> &queue)
{
    cv.wait(lock, [&] { return stop || !queue.empty(); });
    if (queue.empty())
        return std::nullopt;
    std::optional<Job> job(std::move(queue.front()));
    queue.pop_front();
    return job;
}

} // namespace depthtouch::platform
