#pragma once
/// \file
/// \brief Counts heap allocations of the calling thread (the test program replaces operator new).

#include <cstddef>

namespace depthtouch::receivertest {

/// Counts operator new calls made by the calling thread while it is alive.
class AllocationCounter {
public:
    AllocationCounter() noexcept;
    ~AllocationCounter();
    AllocationCounter(const AllocationCounter &) = delete;
    AllocationCounter &operator=(const AllocationCounter &) = delete;
    [[nodiscard]] std::size_t count() const noexcept;

private:
    std::size_t start_;
};

} // namespace depthtouch::receivertest
