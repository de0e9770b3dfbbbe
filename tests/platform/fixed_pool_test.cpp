#include "depthtouch/platform/fixed_pool.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

struct Frame {
    std::uint64_t owner = 0;
    int value = 0;
};

TEST(FixedPoolTest, exhaustionReturnsEmptyHandle)
{
    // GIVEN a pool of 4
    FixedPool<Frame> pool(4);
    EXPECT_EQ(pool.capacity(), 4u);
    EXPECT_EQ(pool.available(), 4u);
    // WHEN 4 objects are taken
    std::vector<FixedPool<Frame>::Handle> held;
    std::set<Frame *> distinct;
    for (int i = 0; i < 4; ++i) {
        held.push_back(pool.acquire());
        ASSERT_TRUE(held.back());
        distinct.insert(held.back().get());
    }
    // THEN they are distinct, and a fifth acquire gives an empty handle and counts the failure
    EXPECT_EQ(distinct.size(), 4u);
    EXPECT_EQ(pool.available(), 0u);
    FixedPool<Frame>::Handle none = pool.acquire();
    EXPECT_FALSE(none);
    EXPECT_EQ(none.get(), nullptr);
    EXPECT_EQ(pool.exhausted(), 1u);
}

TEST(FixedPoolTest, releasedObjectIsReusedAsLeft)
{
    // GIVEN a pool of 2 with both objects taken
    FixedPool<Frame> pool(2);
    FixedPool<Frame>::Handle a = pool.acquire();
    FixedPool<Frame>::Handle b = pool.acquire();
    ASSERT_TRUE(a && b);
    a->value = 42;
    Frame *const object = a.get();
    // WHEN one handle is reset and the pool asked again
    a.reset();
    EXPECT_FALSE(a);
    EXPECT_EQ(pool.available(), 1u);
    FixedPool<Frame>::Handle c = pool.acquire();
    // THEN the same object comes back with the state its last user left (objects are reused)
    ASSERT_TRUE(c);
    EXPECT_EQ(c.get(), object);
    EXPECT_EQ(c->value, 42);
    EXPECT_EQ((*c).value, 42);
}

TEST(FixedPoolTest, handleDestructionReturnsTheObject)
{
    // GIVEN a pool of 1
    FixedPool<Frame> pool(1);
    // WHEN a handle goes out of scope
    {
        FixedPool<Frame>::Handle h = pool.acquire();
        ASSERT_TRUE(h);
        EXPECT_EQ(pool.available(), 0u);
    }
    // THEN the object is free again
    EXPECT_EQ(pool.available(), 1u);
    EXPECT_TRUE(pool.acquire());
}

TEST(FixedPoolTest, handlesMoveOwnership)
{
    // GIVEN a pool of 2 and two handles
    FixedPool<Frame> pool(2);
    FixedPool<Frame>::Handle a = pool.acquire();
    FixedPool<Frame>::Handle b = pool.acquire();
    const std::uint32_t aIndex = a.index();
    // WHEN a is moved into a new handle, then b is move-assigned from it
    FixedPool<Frame>::Handle moved(std::move(a));
    EXPECT_FALSE(a); // NOLINT(bugprone-use-after-move): checking the moved-from state
    EXPECT_EQ(moved.index(), aIndex);
    b = std::move(moved);
    // THEN b's previous object went back to the pool and b owns a's object
    EXPECT_FALSE(moved); // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(b.index(), aIndex);
    EXPECT_EQ(pool.available(), 1u);
}

TEST(FixedPoolTest, prototypeObjectsOwnPreallocatedStorage)
{
    // GIVEN a pool of 3 vectors sized at construction
    FixedPool<std::vector<std::uint8_t>> pool(3, std::vector<std::uint8_t>(1 << 16));
    // WHEN one is taken and used
    auto h = pool.acquire();
    ASSERT_TRUE(h);
    const std::uint8_t *data = h->data();
    (*h)[100] = 7;
    h.reset();
    // THEN its storage is already there and survives release and reacquire (LIFO reuse)
    auto again = pool.acquire();
    ASSERT_TRUE(again);
    EXPECT_EQ(again->size(), 1u << 16);
    EXPECT_EQ(again->data(), data);
    EXPECT_EQ((*again)[100], 7);
}

TEST(FixedPoolTest, concurrentAcquireReleaseNeverHandsOutTwice)
{
    // GIVEN a pool of 8 and 3 threads (more than the 2 cores) taking and returning objects
    constexpr int kThreads = 3;
    constexpr int kIterations = 200'000;
    FixedPool<Frame> pool(8);
    std::unique_ptr<std::atomic<int>[]> holders(new std::atomic<int>[8]);
    for (std::size_t i = 0; i < 8; ++i)
        holders[i] = 0;
    std::atomic<std::uint64_t> doubleHandOuts{0};
    std::atomic<std::uint64_t> overwritten{0};
    std::atomic<std::uint64_t> acquired{0};

    // WHEN each thread repeatedly acquires up to 3 objects, marks them, checks the marks and
    // releases them
    auto worker = [&](std::uint64_t id) {
        std::uint64_t got = 0;
        for (int it = 0; it < kIterations / 3; ++it) {
            FixedPool<Frame>::Handle h[3];
            for (auto &handle : h) {
                handle = pool.acquire();
                if (!handle)
                    continue;
                ++got;
                if (holders[handle.index()].fetch_add(1) != 0)
                    ++doubleHandOuts;
                handle->owner = id;
                handle->value = it;
            }
            for (auto &handle : h) {
                if (!handle)
                    continue;
                if (handle->owner != id || handle->value != it)
                    ++overwritten;
                holders[handle.index()].fetch_sub(1);
                handle.reset();
            }
        }
        acquired += got;
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back(worker, static_cast<std::uint64_t>(t + 1));
    for (auto &t : threads)
        t.join();

    // THEN no object was ever held by two handles at once or written by another thread
    EXPECT_EQ(doubleHandOuts.load(), 0u);
    EXPECT_EQ(overwritten.load(), 0u);
    // AND every object is back, with each one reachable exactly once from the free list
    EXPECT_EQ(pool.available(), pool.capacity());
    EXPECT_GT(acquired.load(), 0u);
    std::vector<FixedPool<Frame>::Handle> all;
    std::set<std::uint32_t> indices;
    for (std::size_t i = 0; i < pool.capacity(); ++i) {
        all.push_back(pool.acquire());
        ASSERT_TRUE(all.back());
        indices.insert(all.back().index());
    }
    EXPECT_EQ(indices.size(), pool.capacity());
    EXPECT_FALSE(pool.acquire());
}

TEST(FixedPoolDeathTest, destroyingPoolWithHandleOutIsABug)
{
    // GIVEN a pool with an object still held
    // THEN destroying the pool aborts (the handle would dangle)
    EXPECT_DEATH(
        {
            auto pool = std::make_unique<FixedPool<Frame>>(1);
            FixedPool<Frame>::Handle h = pool->acquire();
            pool.reset();
        },
        "assertion `available\\(\\) == capacity\\(\\)' failed");
}

} // namespace
} // namespace depthtouch::platform
