#pragma once
/// \file
/// \brief Test support: this process's resident memory, for tests that pin which buffers become
/// resident (a pool's slots when a frame is first written into them). Linux only.

#include <unistd.h>

#include <fstream>

namespace depthtouch::testing {

/// \return this process's resident memory (bytes), from /proc/self/statm; 0 if unreadable.
inline long long residentBytes()
{
    std::ifstream statm("/proc/self/statm");
    long long size = 0;
    long long resident = 0;
    statm >> size >> resident;
    return resident * sysconf(_SC_PAGESIZE);
}

} // namespace depthtouch::testing
