#pragma once
/// \file
/// \brief Cache-line size used to keep data written by different threads on different lines (no
/// false sharing). Thread-safety: constant. The header is C++17-clean.

#include <cstddef>

namespace depthtouch::platform {

/// Bytes per cache line on the targets (x86-64, Cortex-A53/A55/A72/A76: 64). A fixed value rather
/// than std::hardware_destructive_interference_size, whose value may change between compiler
/// versions and flags (GCC warns about it in headers), which would change the layout of shared
/// types.
inline constexpr std::size_t kCacheLineBytes = 64;

} // namespace depthtouch::platform
