// platform::RealtimeThread's stack pre-faulting when static TLS takes part of the stack: glibc
// carves a thread's static TLS (and its thread descriptor) from the top of the stack it was given,
// so less than stackBytes lies below the thread's first frame. The pre-fault must stop at what is
// left (less its 16 KiB margin): touching stackBytes from there would run into the guard page. This
// program holds 96 KiB of static TLS, which the others do not, so it is a test of its own.
#include "depthtouch/platform/realtime_thread.h"

#include <cstdint>
#include <pthread.h>

#include <gtest/gtest.h>

#include "depthtouch/platform/thread_config.h"

namespace depthtouch::platform {
namespace {

constexpr std::size_t kTlsBytes = 96 * 1024;
thread_local volatile unsigned char tlsBlock[kTlsBytes];

TEST(RealtimeThreadTlsTest, thePrefaultStopsAtTheStackLeftBelowTheFirstFrame)
{
    // GIVEN a 256 KiB thread in a program with 96 KiB of static TLS
    constexpr ThreadConfig config{"dt-tls-test", SchedPolicy::Other, 0, 256 * 1024};
    RealtimeThreadOptions options;
    options.requireRt = false;
    options.lockMemory = false;
    options.prefaultStack = true;
    std::uintptr_t frame = 0;
    std::uintptr_t low = 0;
    RealtimeThread thread(config, options, [&](StopToken) {
        tlsBlock[0] = 1;
        tlsBlock[kTlsBytes - 1] = 1;
        frame = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0));
        pthread_attr_t attr;
        void *stackLow = nullptr;
        std::size_t size = 0;
        if (pthread_getattr_np(pthread_self(), &attr) == 0) {
            if (pthread_attr_getstack(&attr, &stackLow, &size) == 0)
                low = reinterpret_cast<std::uintptr_t>(stackLow);
            pthread_attr_destroy(&attr);
        }
    });
    // WHEN it runs (the pre-fault happens before the body)
    ASSERT_TRUE(thread.start());
    thread.join();
    ASSERT_NE(low, 0u);
    ASSERT_GT(frame, low);
    const RealtimeThreadReport &report = thread.report();
    // THEN it touched what lay below its frame less the margin (within the few frames between the
    // pre-fault and the body, 8 KiB), not stackBytes less the margin, which is 96 KiB more
    const std::size_t leftBelowBody = frame - low;
    ASSERT_LT(leftBelowBody + kTlsBytes, report.stackBytes + 1);
    EXPECT_GT(report.stackPrefaultedBytes, 0u);
    EXPECT_LE(report.stackPrefaultedBytes, leftBelowBody - 16 * 1024 + 8 * 1024)
        << "stack " << report.stackBytes << " B, " << leftBelowBody << " B below the body's frame";
}

} // namespace
} // namespace depthtouch::platform
