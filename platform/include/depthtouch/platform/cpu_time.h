#pragma once
/// \file
/// \brief CPU time of the process, for benchmarks on machines shared with other load.
///
/// The header is C++17-clean.

#include "depthtouch/platform/clock.h"

namespace depthtouch::platform {

/// \brief CPU time used by the whole process so far, all threads (CLOCK_PROCESS_CPUTIME_ID).
/// Benchmarks divide work by it to get a per-core rate that other load on a shared machine does
/// not inflate. Not a TimePoint: it only advances while the process runs. Thread-safe.
Duration processCpuTime() noexcept;

} // namespace depthtouch::platform
