#include "depthtouch/platform/memory_lock.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <link.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace depthtouch::platform {

const char *const kRuntimeObjects[] = {
    "", "libc.so", "libm.so", "libstdc++.so", "libgcc_s.so", "ld-linux", nullptr};

namespace {

std::uintptr_t pageBytes() noexcept
{
    const long size = sysconf(_SC_PAGESIZE);
    return size > 0 ? static_cast<std::uintptr_t>(size) : 4096u;
}

/// One mlock() of [begin, end) (page-aligned), added to \a result.
void lockPages(std::uintptr_t begin, std::uintptr_t end, LockResult &result) noexcept
{
    if (end <= begin)
        return;
    // NOLINTNEXTLINE(performance-no-int-to-ptr): an address range, not an object
    if (mlock(reinterpret_cast<const void *>(begin), end - begin) == 0) {
        result.bytes += end - begin;
        ++result.regions;
    } else if (result.failedErrno == 0) {
        result.failedErrno = errno;
    }
}

/// \return true when the page at \a address is mapped (mincore() says ENOMEM for an unmapped one).
bool pageMapped(std::uintptr_t address) noexcept
{
    unsigned char resident = 0;
    // NOLINTNEXTLINE(performance-no-int-to-ptr)
    return mincore(reinterpret_cast<void *>(address), pageBytes(), &resident) == 0;
}

/// dl_iterate_phdr() state: which objects to lock and what was locked.
struct ObjectWalk {
    const char *const *prefixes;
    LockResult result;
};

/// \return true when the last component of \a path starts with one of \a prefixes ("" matches the
/// empty name that dl_iterate_phdr gives the program itself, and the object this code is linked
/// into, \a self: a shared object that embeds it, such as the GStreamer element's plugin).
bool nameMatches(const char *path, bool self, const char *const *prefixes) noexcept
{
    const char *slash = std::strrchr(path, '/');
    const char *base = slash != nullptr ? slash + 1 : path;
    for (const char *const *p = prefixes; *p != nullptr; ++p) {
        if ((*p)[0] == '\0') {
            if (path[0] == '\0' || self)
                return true;
        } else if (std::strncmp(base, *p, std::strlen(*p)) == 0) {
            return true;
        }
    }
    return false;
}

/// \return whether one of \a info's PT_LOAD segments holds \a address.
bool holds(const dl_phdr_info *info, std::uintptr_t address) noexcept
{
    for (int i = 0; i < info->dlpi_phnum; ++i) {
        const ElfW(Phdr) &ph = info->dlpi_phdr[i];
        const std::uintptr_t begin = info->dlpi_addr + ph.p_vaddr;
        if (ph.p_type == PT_LOAD && address >= begin && address - begin < ph.p_memsz)
            return true;
    }
    return false;
}

int lockObject(dl_phdr_info *info, std::size_t, void *data) noexcept
{
    auto &walk = *static_cast<ObjectWalk *>(data);
    const char *name = info->dlpi_name != nullptr ? info->dlpi_name : "";
    // The vDSO has a name ("linux-vdso.so.1") and is not backed by a file: never matched, and
    // not lockable anyway. Where this code is linked into a shared object (a plugin loaded by
    // another program), that object holds the haptic thread's code: it is "" too.
    const bool self = holds(info, reinterpret_cast<std::uintptr_t>(&lockObject));
    if (!nameMatches(name, self, walk.prefixes))
        return 0;
    const std::uintptr_t page = pageBytes();
    for (int i = 0; i < info->dlpi_phnum; ++i) {
        const ElfW(Phdr) &ph = info->dlpi_phdr[i];
        if (ph.p_type != PT_LOAD || ph.p_memsz == 0)
            continue;
        const std::uintptr_t begin = (info->dlpi_addr + ph.p_vaddr) & ~(page - 1);
        const std::uintptr_t end =
            (info->dlpi_addr + ph.p_vaddr + ph.p_memsz + page - 1) & ~(page - 1);
        lockPages(begin, end, walk.result);
    }
    return 0;
}

/// \return the value in KiB of the "\a key:" line of /proc/self/status, or −1.
double statusKiB(const char *key) noexcept
{
    std::FILE *f = std::fopen("/proc/self/status", "re");
    if (f == nullptr)
        return -1.0;
    char line[256];
    const std::size_t keyLength = std::strlen(key);
    double value = -1.0;
    while (std::fgets(line, sizeof(line), f) != nullptr) {
        if (std::strncmp(line, key, keyLength) == 0 && line[keyLength] == ':') {
            long long kib = 0;
            if (std::sscanf(line + keyLength + 1, "%lld", &kib) == 1)
                value = static_cast<double>(kib);
            break;
        }
    }
    std::fclose(f);
    return value;
}

} // namespace

const char *memoryLockModeName(MemoryLockMode mode) noexcept
{
    static constexpr std::array<const char *, 4> kNames = {"none", "owned", "onfault", "all"};
    return enumName(mode, kNames, "?");
}

LockResult lockRegion(const MemoryRegion &region) noexcept
{
    LockResult result;
    if (region.address == nullptr || region.bytes == 0)
        return result;
    const std::uintptr_t page = pageBytes();
    const auto address = reinterpret_cast<std::uintptr_t>(region.address);
    const std::uintptr_t begin = address & ~(page - 1);
    const std::uintptr_t last = (address + region.bytes - 1) & ~(page - 1);
    // Stop at the first unmapped page: mlock() of a range with a hole fails as a whole.
    std::uintptr_t end = begin;
    while (end <= last && pageMapped(end))
        end += page;
    lockPages(begin, end, result);
    return result;
}

LockResult lockLoadedObjects(const char *const *sonamePrefixes) noexcept
{
    ObjectWalk walk{sonamePrefixes, {}};
    if (sonamePrefixes != nullptr)
        dl_iterate_phdr(&lockObject, &walk);
    return walk.result;
}

void unlockRegion(const MemoryRegion &region) noexcept
{
    if (region.address == nullptr || region.bytes == 0)
        return;
    const std::uintptr_t page = pageBytes();
    const auto address = reinterpret_cast<std::uintptr_t>(region.address);
    const std::uintptr_t begin = address & ~(page - 1);
    const std::uintptr_t end = (address + region.bytes + page - 1) & ~(page - 1);
    // NOLINTNEXTLINE(performance-no-int-to-ptr)
    (void)munlock(reinterpret_cast<const void *>(begin), end - begin);
}

double residentMiB() noexcept
{
    const double kib = statusKiB("VmRSS");
    return kib < 0.0 ? -1.0 : kib / 1024.0;
}

double lockedMiB() noexcept
{
    const double kib = statusKiB("VmLck");
    return kib < 0.0 ? -1.0 : kib / 1024.0;
}

PageFaults threadPageFaults() noexcept
{
    PageFaults faults;
#ifdef RUSAGE_THREAD
    rusage usage{};
    if (getrusage(RUSAGE_THREAD, &usage) == 0) {
        faults.minor = static_cast<std::uint64_t>(usage.ru_minflt);
        faults.major = static_cast<std::uint64_t>(usage.ru_majflt);
    }
#endif
    return faults;
}

std::size_t heapBlockBytes(const void *p, std::size_t fallback) noexcept
{
    if (p == nullptr)
        return 0;
#if defined(__GLIBC__)
    const std::size_t bytes = malloc_usable_size(const_cast<void *>(p));
    return bytes > 0 ? bytes : fallback;
#else
    return fallback;
#endif
}

std::uint64_t addressSpaceLimitBytes() noexcept
{
    struct rlimit r {};
    if (::getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur == RLIM_INFINITY)
        return 0;
    return static_cast<std::uint64_t>(r.rlim_cur);
}

} // namespace depthtouch::platform
