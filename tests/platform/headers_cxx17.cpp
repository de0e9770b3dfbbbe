// Compiled as C++17 (see CMakeLists.txt): fails the build when a platform header needs C++20.
#include "depthtouch/platform/assert.h"
#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/fixed_pool.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/mailbox.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/report_file.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/seqlock.h"
#include "depthtouch/platform/spsc_ring.h"
#include "depthtouch/platform/thread_config.h"
#include "depthtouch/platform/unique_fd.h"

#include <cstdint>
#include <vector>

static_assert(__cplusplus == 201703L, "this file must be compiled as C++17");

namespace depthtouch::platform {

// Instantiate the templates so their member functions are checked too.
template class SpscRing<std::uint64_t, 8>;
template class TripleBuffer<std::vector<int>>;
template class FixedPool<std::vector<int>>;
template class SeqLockArray<3>;

} // namespace depthtouch::platform

template class depthtouch::Result<int>;
