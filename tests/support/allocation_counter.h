#pragma once
/// \file
/// \brief Counts heap allocations (operator new) made by the calling thread, for tests that check a
/// real-time or per-frame path allocates nothing. A test program gets it by linking the object
/// library `dt_test_allocation_counter`, which replaces the global operator new and delete.

#include <cstddef>

namespace depthtouch::testing {

/// \brief Counts operator new calls made by the calling thread while it is alive.
/// Thread-safety: thread-bound (it counts only the thread that constructed it).
class AllocationCounter {
public:
    AllocationCounter() noexcept;
    ~AllocationCounter();
    AllocationCounter(const AllocationCounter &) = delete;
    AllocationCounter &operator=(const AllocationCounter &) = delete;
    /// \return operator new calls on this thread since construction.
    [[nodiscard]] std::size_t count() const noexcept;

private:
    std::size_t start_;
};

} // namespace depthtouch::testing
