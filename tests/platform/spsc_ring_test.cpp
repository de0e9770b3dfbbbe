#include "depthtouch/platform/spsc_ring.h"

#include <cstdint>
#include <memory>
#include <thread>
#include <type_traits>

#include <gtest/gtest.h>

#include "platform/test_item.h"

namespace depthtouch::platform {
namespace {

using test::isIntact;
using test::makeItem;
using test::SequencedItem;

static_assert(std::is_trivially_copyable_v<SequencedItem>);

/// Counts live instances, to check that the ring destroys what it holds.
struct Counted {
    static inline int live = 0;
    int value = 0;
    Counted() noexcept { ++live; }
    explicit Counted(int v) noexcept : value(v) { ++live; }
    Counted(Counted &&o) noexcept : value(o.value) { ++live; }
    Counted &operator=(Counted &&o) noexcept
    {
        value = o.value;
        return *this;
    }
    ~Counted() { --live; }
};

TEST(SpscRingTest, popsInPushOrder)
{
    // GIVEN an empty ring of 8
    SpscRing<int, 8> ring;
    EXPECT_EQ(ring.sizeApprox(), 0u);
    int out = -1;
    EXPECT_FALSE(ring.tryPop(out));
    EXPECT_EQ(out, -1);
    // WHEN 5 items are pushed
    for (int i = 0; i < 5; ++i)
        EXPECT_TRUE(ring.tryPush(i));
    // THEN they come out in order
    EXPECT_EQ(ring.sizeApprox(), 5u);
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(ring.tryPop(out));
        EXPECT_EQ(out, i);
    }
    EXPECT_TRUE(ring.emptyApprox());
}

TEST(SpscRingTest, fullRingRefusesAndCountsDrops)
{
    // GIVEN a full ring of 4
    SpscRing<int, 4> ring;
    for (int i = 0; i < 4; ++i)
        ASSERT_TRUE(ring.tryPush(i));
    EXPECT_EQ(ring.sizeApprox(), (SpscRing<int, 4>::capacity()));
    // WHEN 3 more pushes are tried
    // THEN each fails at once and is counted, and the queued items are untouched
    EXPECT_FALSE(ring.tryPush(100));
    EXPECT_FALSE(ring.tryPush(101));
    EXPECT_FALSE(ring.tryEmplace(102));
    EXPECT_EQ(ring.dropped(), 3u);
    int out = -1;
    ASSERT_TRUE(ring.tryPop(out));
    EXPECT_EQ(out, 0);
    // AND one pop makes room for exactly one push
    EXPECT_TRUE(ring.tryPush(4));
    EXPECT_FALSE(ring.tryPush(5));
    EXPECT_EQ(ring.dropped(), 4u);
}

TEST(SpscRingTest, wrapsAroundManyTimes)
{
    // GIVEN a ring of 4 used for 1000 push/pop pairs in groups of 3
    SpscRing<std::uint32_t, 4> ring;
    std::uint32_t next = 0;
    std::uint32_t expected = 0;
    int mismatches = 0;
    for (int round = 0; round < 1000; ++round) {
        for (int i = 0; i < 3; ++i)
            ASSERT_TRUE(ring.tryPush(next++));
        for (int i = 0; i < 3; ++i) {
            std::uint32_t out = 0;
            ASSERT_TRUE(ring.tryPop(out));
            mismatches += out == expected++ ? 0 : 1;
        }
    }
    // THEN the order survived the index wrap
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(ring.dropped(), 0u);
}

TEST(SpscRingTest, moveOnlyItemsAndDestruction)
{
    // GIVEN a ring of unique_ptr
    {
        SpscRing<std::unique_ptr<Counted>, 4> ring;
        // WHEN items are moved in and one is popped
        ASSERT_TRUE(ring.tryPush(std::make_unique<Counted>(1)));
        ASSERT_TRUE(ring.tryEmplace(std::make_unique<Counted>(2)));
        ASSERT_TRUE(ring.tryPush(std::make_unique<Counted>(3)));
        std::unique_ptr<Counted> out;
        ASSERT_TRUE(ring.tryPop(out));
        // THEN the popped one is the first
        ASSERT_NE(out, nullptr);
        EXPECT_EQ(out->value, 1);
        EXPECT_EQ(Counted::live, 3);
    }
    // AND destroying the ring destroyed the items still queued
    EXPECT_EQ(Counted::live, 0);
}

TEST(SpscRingTest, twoThreadsTransferAMillionItemsIntact)
{
    // GIVEN a ring of 64 multi-word items, one producer and one consumer thread
    constexpr std::uint64_t kItems = 1'000'000;
    static SpscRing<SequencedItem, 64> ring; // static: too big for a comfortable stack frame
    std::uint64_t refusedPushes = 0;

    // WHEN the producer pushes 10^6 sequenced items, retrying when the ring is full
    std::thread producer([&] {
        for (std::uint64_t seq = 0; seq < kItems; ++seq) {
            const SequencedItem item = makeItem(seq);
            while (!ring.tryPush(item)) {
                ++refusedPushes;
                std::this_thread::yield();
            }
        }
    });
    // AND the consumer pops until it has them all
    std::uint64_t received = 0;
    std::uint64_t outOfOrder = 0;
    std::uint64_t corrupted = 0;
    std::uint64_t maxSize = 0;
    while (received < kItems) {
        SequencedItem item;
        if (!ring.tryPop(item)) {
            std::this_thread::yield();
            continue;
        }
        if (item.seq != received)
            ++outOfOrder;
        if (!isIntact(item))
            ++corrupted;
        const std::uint64_t size = ring.sizeApprox();
        maxSize = size > maxSize ? size : maxSize;
        ++received;
    }
    producer.join();

    // THEN every item arrived once, in order, intact (no loss, duplicate, reorder or tearing)
    EXPECT_EQ(received, kItems);
    EXPECT_EQ(outOfOrder, 0u);
    EXPECT_EQ(corrupted, 0u);
    SequencedItem extra;
    EXPECT_FALSE(ring.tryPop(extra));
    // AND the drop counter counted exactly the refused pushes; the size never exceeded the capacity
    EXPECT_EQ(ring.dropped(), refusedPushes);
    EXPECT_LE(maxSize, ring.capacity());
}

} // namespace
} // namespace depthtouch::platform
