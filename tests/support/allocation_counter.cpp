#include "support/allocation_counter.h"

#include <cstdlib>
#include <new>

// Every unaligned form of operator new and delete is replaced, so allocation and release always
// pair malloc with free (AddressSanitizer checks the pairing).
namespace {
thread_local bool tCounting = false;
thread_local std::size_t tAllocations = 0;

void *countedAlloc(std::size_t size) noexcept
{
    if (tCounting)
        ++tAllocations;
    return std::malloc(size != 0 ? size : 1);
}

void *countedAllocOrThrow(std::size_t size)
{
    if (void *p = countedAlloc(size))
        return p;
    throw std::bad_alloc();
}
} // namespace

void *operator new(std::size_t size)
{
    return countedAllocOrThrow(size);
}
void *operator new[](std::size_t size)
{
    return countedAllocOrThrow(size);
}
void *operator new(std::size_t size, const std::nothrow_t &) noexcept
{
    return countedAlloc(size);
}
void *operator new[](std::size_t size, const std::nothrow_t &) noexcept
{
    return countedAlloc(size);
}
void operator delete(void *p) noexcept
{
    std::free(p);
}
void operator delete[](void *p) noexcept
{
    std::free(p);
}
void operator delete(void *p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete[](void *p, std::size_t) noexcept
{
    std::free(p);
}
void operator delete(void *p, const std::nothrow_t &) noexcept
{
    std::free(p);
}
void operator delete[](void *p, const std::nothrow_t &) noexcept
{
    std::free(p);
}

namespace depthtouch::testing {

AllocationCounter::AllocationCounter() noexcept : start_(tAllocations)
{
    tCounting = true;
}
AllocationCounter::~AllocationCounter()
{
    tCounting = false;
}
std::size_t AllocationCounter::count() const noexcept
{
    return tAllocations - start_;
}

} // namespace depthtouch::testing
