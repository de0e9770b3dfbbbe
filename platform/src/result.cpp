#include "depthtouch/platform/result.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cstddef>
#include <cstdio>
#include <cstring>

namespace depthtouch {

const char *errcName(Errc code) noexcept
{
    static constexpr std::array<const char *, 10> kNames = {
        "InvalidArgument", "InvalidState", "NotSupported",   "NoDevice",    "Busy",
        "Timeout",         "Io",           "OutOfResources", "EndOfStream", "PermissionDenied"};
    static_assert(kNames.size() == static_cast<std::size_t>(Errc::PermissionDenied) + 1);
    return platform::enumName(code, kNames, "Unknown");
}

const char *Error::format(char *buf, std::size_t size) const noexcept
{
    if (buf == nullptr || size == 0)
        return buf;
    if (sysErrno != 0) {
        char errBuf[128];
        // GNU strerror_r returns the message pointer, which may or may not be errBuf.
        const char *msg = strerror_r(sysErrno, errBuf, sizeof(errBuf));
        std::snprintf(buf, size, "%s (%s, %s)", what, errcName(code), msg);
    } else {
        std::snprintf(buf, size, "%s (%s)", what, errcName(code));
    }
    return buf;
}

} // namespace depthtouch
