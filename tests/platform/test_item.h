#pragma once
/// \file
/// \brief A multi-word test item whose contents are derived from its sequence number, so a reader
/// can tell a whole item from a torn or corrupted one.

#include <cstdint>

namespace depthtouch::platform::test {

/// Sequence number, a payload of six words derived from it, and a checksum over both.
struct SequencedItem {
    std::uint64_t seq = 0;
    std::uint64_t payload[6] = {};
    std::uint64_t checksum = 0;
};

constexpr std::uint64_t payloadWord(std::uint64_t seq, unsigned i) noexcept
{
    return (seq + 1) * 0x9E3779B97F4A7C15ull ^
           (static_cast<std::uint64_t>(i) * 0xBF58476D1CE4E5B9ull);
}

constexpr std::uint64_t checksumOf(const SequencedItem &item) noexcept
{
    std::uint64_t h = 0xCBF29CE484222325ull ^ item.seq;
    for (std::uint64_t word : item.payload)
        h = (h ^ word) * 0x100000001B3ull;
    return h;
}

/// Fills \a item (in place: no allocation) for sequence number \a seq.
inline void fillItem(SequencedItem &item, std::uint64_t seq) noexcept
{
    item.seq = seq;
    for (unsigned i = 0; i < 6; ++i)
        item.payload[i] = payloadWord(seq, i);
    item.checksum = checksumOf(item);
}

inline SequencedItem makeItem(std::uint64_t seq) noexcept
{
    SequencedItem item;
    fillItem(item, seq);
    return item;
}

/// \return true when every word of \a item matches its sequence number and the checksum.
inline bool isIntact(const SequencedItem &item) noexcept
{
    for (unsigned i = 0; i < 6; ++i) {
        if (item.payload[i] != payloadWord(item.seq, i))
            return false;
    }
    return item.checksum == checksumOf(item);
}

} // namespace depthtouch::platform::test
