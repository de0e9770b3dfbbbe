#include "depthtouch/platform/thread_config.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <sched.h>

namespace depthtouch::platform {

const char *schedPolicyName(SchedPolicy policy) noexcept
{
    static constexpr std::array<const char *, 2> kNames = {"SCHED_OTHER", "SCHED_FIFO"};
    return enumName(policy, kNames, "SCHED_?");
}

int toSchedPolicy(SchedPolicy policy) noexcept
{
    return policy == SchedPolicy::Fifo ? SCHED_FIFO : SCHED_OTHER;
}

int absolutePriority(const ThreadConfig &config) noexcept
{
    if (config.policy != SchedPolicy::Fifo)
        return 0;
    const int maxPriority = sched_get_priority_max(SCHED_FIFO);
    const int minPriority = sched_get_priority_min(SCHED_FIFO);
    const int priority = maxPriority + config.relativePriority;
    if (priority < minPriority)
        return minPriority;
    if (priority > maxPriority)
        return maxPriority;
    return priority;
}

} // namespace depthtouch::platform
