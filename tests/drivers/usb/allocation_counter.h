#pragma once
/// \file
/// \brief Heap allocations (operator new) made so far by the calling thread, in the test programs
/// that link allocation_counter.cpp.
#include <cstddef>

namespace depthtouch::testing {
[[nodiscard]] std::size_t threadAllocations() noexcept;
} // namespace depthtouch::testing
