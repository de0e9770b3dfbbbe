/// \file
/// \brief pollInput() (see poll_input.h).

#include "depthtouch/drivers/common/poll_input.h"

#include <poll.h>

#include <algorithm>
#include <cerrno>

namespace depthtouch::drivers {

PollResult pollInput(int fd, platform::Duration wait, short &revents) noexcept
{
    const auto ms = std::min(std::chrono::ceil<std::chrono::milliseconds>(wait), kMaxPollWait);
    pollfd p{fd, POLLIN, 0};
    const int n = ::poll(&p, 1, static_cast<int>(ms.count()));
    revents = p.revents;
    if (n < 0)
        return errno == EINTR ? PollResult::Interrupted : PollResult::Failed;
    return n == 0 ? PollResult::Timeout : PollResult::Ready;
}

} // namespace depthtouch::drivers
