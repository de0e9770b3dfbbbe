// Counts heap allocations (global operator new) made by the calling thread: this test program
// replaces every unaligned form of operator new and delete.
#include "allocation_counter.h"

#include <cstdlib>
#include <new>

namespace {
thread_local std::size_t tAllocations = 0;

void *countedAlloc(std::size_t size) noexcept
{
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
std::size_t threadAllocations() noexcept
{
    return tAllocations;
}
} // namespace depthtouch::testing
