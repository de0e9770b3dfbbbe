#include "depthtouch/platform/seqlock.h"

#include <atomic>
#include <thread>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

TEST(SeqLockArrayTest, loadReturnsZerosThenTheLastStore)
{
    // GIVEN a fresh seqlock
    SeqLockArray<3> s;
    // THEN it reads all zeros, and after two stores the second one
    EXPECT_EQ(s.load(), (std::array<double, 3>{0.0, 0.0, 0.0}));
    s.store({1.0, 2.0, 3.0});
    s.store({-4.0, 5.5, 6.25});
    EXPECT_EQ(s.load(), (std::array<double, 3>{-4.0, 5.5, 6.25}));
}

TEST(SeqLockArrayTest, aReaderNeverSeesAMixOfTwoStores)
{
    // GIVEN a writer storing (k, 2k, 3k) for k = 1..200000 while a reader loads
    SeqLockArray<3> s;
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (int k = 1; k <= 200000; ++k) {
            const double v = k;
            s.store({v, 2.0 * v, 3.0 * v});
        }
        done.store(true);
    });
    long torn = 0;
    long reads = 0;
    double last = 0.0;
    bool backwards = false;
    while (!done.load()) {
        const auto a = s.load();
        ++reads;
        torn += (a[1] != 2.0 * a[0] || a[2] != 3.0 * a[0]) ? 1 : 0;
        backwards = backwards || a[0] < last;
        last = a[0];
    }
    writer.join();
    // THEN every snapshot is one whole store, and snapshots never go back in time
    EXPECT_EQ(torn, 0) << "of " << reads << " reads";
    EXPECT_FALSE(backwards);
    EXPECT_EQ(s.load()[0], 200000.0);
}

} // namespace
} // namespace depthtouch::platform
