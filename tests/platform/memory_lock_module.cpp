// A shared object that embeds dt_platform's memory locking, as the GStreamer element's plugin does:
// memory_lock_test.cpp dlopen()s it and asks it to lock "" (memory_lock.h, lockLoadedObjects()),
// which must take in this object's own segments, where a plugin's haptic code lives, and not the
// program's alone.

#include "depthtouch/platform/memory_lock.h"

extern "C" {

/// \brief Locks the loaded objects named "" from inside this shared object.
/// \param text set to the address of this function, a byte of this object's code segment.
/// \return the bytes locked, or −errno of the first mlock() that failed.
__attribute__((visibility("default"))) long dtLockFromModule(const void **text)
{
    static const char *const kSelf[] = {"", nullptr};
    *text = reinterpret_cast<const void *>(&dtLockFromModule);
    const depthtouch::platform::LockResult r = depthtouch::platform::lockLoadedObjects(kSelf);
    return r.failedErrno != 0 ? -static_cast<long>(r.failedErrno) : static_cast<long>(r.bytes);
}

} // extern "C"
