#include "depthtouch/platform/assert.h"

#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace depthtouch::platform {

void assertionFailed(const char *expression, const char *file, int line,
                     const char *function) noexcept
{
    // One formatted buffer and one write(2): no allocation, no stdio lock, so this also works on
    // the real-time thread and in a forked child.
    char buf[512];
    const int n = std::snprintf(buf, sizeof(buf), "%s:%d: %s(): assertion `%s' failed\n", file,
                                line, function, expression);
    if (n > 0) {
        const std::size_t len = static_cast<std::size_t>(n) < sizeof(buf)
                                    ? static_cast<std::size_t>(n)
                                    : sizeof(buf) - 1;
        [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, buf, len);
    }
    std::abort();
}

} // namespace depthtouch::platform
