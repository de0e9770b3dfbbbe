#include "depthtouch/platform/result.h"

#include <cstdio>
#include <cstring>

namespace depthtouch {

const char *errcName(Errc code) noexcept
{
    switch (code) {
    case Errc::InvalidArgument: return "InvalidArgument";
    case Errc::InvalidState: return "InvalidState";
    case Errc::NotSupported: return "NotSupported";
    case Errc::NoDevice: return "NoDevice";
    case Errc::Busy: return "Busy";
    case Errc::Timeout: return "Timeout";
    case Errc::Io: return "Io";
    case Errc::OutOfResources: return "OutOfResources";
    case Errc::EndOfStream: return "EndOfStream";
    case Errc::PermissionDenied: return "PermissionDenied";
    }
    return "Unknown";
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
