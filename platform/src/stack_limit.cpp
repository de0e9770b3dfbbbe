/// \file
/// \brief ensureStackLimit(): see stack_limit.h.

#include "depthtouch/platform/stack_limit.h"

#include <cerrno>
#include <cstring>
#include <string>

#include <pthread.h>
#include <sys/resource.h>

namespace depthtouch::platform {

namespace {

std::string kib(rlim_t bytes)
{
    return std::to_string(bytes / 1024) + " KiB";
}

/// Raises the default stack of threads started from now on to at least \a minimumBytes.
std::string raiseDefaultThreadStack(std::size_t minimumBytes)
{
    pthread_attr_t attr;
    if (const int err = pthread_getattr_default_np(&attr); err != 0)
        return std::string("pthread_getattr_default_np: ") + std::strerror(err);
    std::size_t size = 0;
    int err = pthread_attr_getstacksize(&attr, &size);
    if (err == 0 && size < minimumBytes) {
        err = pthread_attr_setstacksize(&attr, minimumBytes);
        if (err == 0)
            err = pthread_setattr_default_np(&attr);
    }
    pthread_attr_destroy(&attr);
    if (err != 0)
        return std::string("the default thread stack: ") + std::strerror(err);
    return {};
}

} // namespace

std::string ensureStackLimit(std::size_t minimumBytes)
{
    rlimit limit{};
    if (getrlimit(RLIMIT_STACK, &limit) != 0)
        return std::string("getrlimit(RLIMIT_STACK): ") + std::strerror(errno);
    const auto minimum = static_cast<rlim_t>(minimumBytes);
    if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur < minimum) {
        if (limit.rlim_max != RLIM_INFINITY && limit.rlim_max < minimum)
            return "the stack limit (ulimit -s) is " + kib(limit.rlim_max) + ", below the " +
                   kib(minimum) + " depthtouch needs";
        limit.rlim_cur = minimum;
        if (setrlimit(RLIMIT_STACK, &limit) != 0)
            return std::string("setrlimit(RLIMIT_STACK): ") + std::strerror(errno);
    }
    return raiseDefaultThreadStack(minimumBytes);
}

} // namespace depthtouch::platform
