#pragma once
/// \file
/// \brief Memory pressure without root for the page-fault tests: madvise(MADV_PAGEOUT) (Linux >=
/// 5.4) on every mapping of the calling process, as the kernel's reclaim does under pressure:
/// file pages are dropped or unmapped (a later access faults), anonymous pages go to swap where
/// there is some. Locked mappings are skipped by the kernel (EINVAL), which is what the tests show.
/// Thread-safety: reentrant (reads /proc/self/maps).

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sys/mman.h>

namespace depthtouch::test {

/// \brief What pageOutProcess() did.
struct PageOutResult {
    int mappings = 0;       ///< Mappings madvise() accepted.
    int refused = 0;        ///< Mappings it refused (locked, special, or no MADV_PAGEOUT).
    bool supported = false; ///< The kernel knows MADV_PAGEOUT (at least one mapping accepted).
};

/// \brief madvise(MADV_PAGEOUT) on every mapping of this process but the kernel's special ones
/// ([vvar], [vdso], [vsyscall]).
inline PageOutResult pageOutProcess()
{
    PageOutResult result;
#ifdef MADV_PAGEOUT
    std::FILE *maps = std::fopen("/proc/self/maps", "re");
    if (maps == nullptr)
        return result;
    char line[512];
    while (std::fgets(line, sizeof(line), maps) != nullptr) {
        unsigned long long begin = 0;
        unsigned long long end = 0;
        if (std::sscanf(line, "%llx-%llx", &begin, &end) != 2 || end <= begin)
            continue;
        if (std::strstr(line, "[vvar") != nullptr || std::strstr(line, "[vdso]") != nullptr ||
            std::strstr(line, "[vsyscall]") != nullptr)
            continue;
        // NOLINTNEXTLINE(performance-no-int-to-ptr)
        void *address = reinterpret_cast<void *>(static_cast<std::uintptr_t>(begin));
        if (madvise(address, static_cast<std::size_t>(end - begin), MADV_PAGEOUT) == 0)
            ++result.mappings;
        else
            ++result.refused;
    }
    std::fclose(maps);
    result.supported = result.mappings > 0;
#endif
    return result;
}

} // namespace depthtouch::test
