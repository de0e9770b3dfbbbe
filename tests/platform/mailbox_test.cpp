#include "depthtouch/platform/mailbox.h"

#include <cstdint>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "platform/test_item.h"

namespace depthtouch::platform {
namespace {

using test::fillItem;
using test::isIntact;
using test::SequencedItem;

TEST(MailboxTest, nothingNewBeforeFirstPublish)
{
    // GIVEN a fresh mailbox
    Mailbox<int> box;
    // THEN the reader has no update and reads the default value
    EXPECT_FALSE(box.hasUpdate());
    EXPECT_FALSE(box.update());
    EXPECT_EQ(box.readBuffer(), 0);
}

TEST(MailboxTest, readerGetsTheLatestValueOnce)
{
    // GIVEN a mailbox where the writer published 1, 2 and 3
    TripleBuffer<int> box;
    for (int v = 1; v <= 3; ++v) {
        box.writeBuffer() = v;
        box.publish();
    }
    // WHEN the reader updates twice
    const bool first = box.update();
    const int value = box.readBuffer();
    const bool second = box.update();
    // THEN it gets only the newest value, once, and keeps reading it
    EXPECT_TRUE(first);
    EXPECT_EQ(value, 3);
    EXPECT_FALSE(second);
    EXPECT_EQ(box.readBuffer(), 3);
}

TEST(MailboxTest, readBufferStaysStableWhileWriterContinues)
{
    // GIVEN a reader holding value 10
    TripleBuffer<int> box;
    box.writeBuffer() = 10;
    box.publish();
    ASSERT_TRUE(box.update());
    // WHEN the writer publishes many more values without the reader updating
    for (int v = 11; v < 100; ++v) {
        box.writeBuffer() = v;
        box.publish();
        // THEN the reader's buffer is never the one being written
        EXPECT_NE(&box.writeBuffer(), &box.readBuffer());
        EXPECT_EQ(box.readBuffer(), 10);
    }
    ASSERT_TRUE(box.update());
    EXPECT_EQ(box.readBuffer(), 99);
}

TEST(MailboxTest, buffersArePreallocatedAndNeverCopied)
{
    // GIVEN a mailbox of vectors sized at construction
    TripleBuffer<std::vector<float>> box(std::vector<float>(4096, 0.0f));
    std::set<const float *> storage;
    storage.insert(box.writeBuffer().data());
    storage.insert(box.readBuffer().data());
    // WHEN values are published and fetched many times
    for (int i = 0; i < 100; ++i) {
        box.writeBuffer()[0] = static_cast<float>(i);
        box.publish();
        if (i % 3 == 0) {
            ASSERT_TRUE(box.update());
            EXPECT_EQ(box.readBuffer()[0], static_cast<float>(i));
        }
        storage.insert(box.writeBuffer().data());
        storage.insert(box.readBuffer().data());
    }
    // THEN only the three original vector buffers were ever used (indices swapped, no copy, no
    // reallocation)
    EXPECT_EQ(storage.size(), 3u);
    EXPECT_EQ(box.readBuffer().size(), 4096u);
}

TEST(MailboxTest, twoThreadsNeverTearAndNeverGoBackwards)
{
    // GIVEN a mailbox of multi-word items, one writer and one reader thread
    constexpr std::uint64_t kItems = 1'000'000;
    static TripleBuffer<SequencedItem> box;

    // WHEN the writer publishes 10^6 sequenced items (filled in place, field by field)
    std::thread writer([&] {
        for (std::uint64_t seq = 1; seq <= kItems; ++seq) {
            fillItem(box.writeBuffer(), seq);
            box.publish();
        }
    });
    // AND the reader fetches until it sees the last one
    std::uint64_t last = 0;
    std::uint64_t updates = 0;
    std::uint64_t torn = 0;
    std::uint64_t notNewer = 0;
    std::uint64_t changedUnderReader = 0;
    while (last < kItems) {
        if (!box.update()) {
            std::this_thread::yield();
            continue;
        }
        ++updates;
        const SequencedItem &item = box.readBuffer();
        if (!isIntact(item))
            ++torn;
        if (item.seq <= last)
            ++notNewer;
        last = item.seq;
        // The buffer must not change while the reader holds it.
        const SequencedItem copy = item;
        if (!isIntact(box.readBuffer()) || box.readBuffer().seq != copy.seq)
            ++changedUnderReader;
    }
    writer.join();

    // THEN every value read was whole, each update was newer than the last, and the final value
    // arrived
    EXPECT_EQ(torn, 0u);
    EXPECT_EQ(notNewer, 0u);
    EXPECT_EQ(changedUnderReader, 0u);
    EXPECT_EQ(last, kItems);
    EXPECT_GE(updates, 1u);
    EXPECT_LE(updates, kItems);
    EXPECT_FALSE(box.update());
}

} // namespace
} // namespace depthtouch::platform
