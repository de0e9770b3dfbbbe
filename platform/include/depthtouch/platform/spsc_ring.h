#pragma once
/// \file
/// \brief SpscRing: lock-free, wait-free ring buffer for one producer thread and one consumer
/// thread. The hand-over between the haptic thread and the rest of the stack (docs/style.md §4.5).
///
/// The header is C++17-clean.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// \brief Fixed-capacity single-producer/single-consumer FIFO of \a T with \a N slots.
///
/// - Storage is inside the object (no allocation, ever). Construct it before the real-time thread
///   starts, e.g. as a member of a long-lived object.
/// - tryPush() never blocks: on a full ring it returns false and counts the item in dropped().
/// - tryPop() never blocks: on an empty ring it returns false.
/// - Ordering: the producer publishes a slot with a release store of its index, the consumer
///   reads it after an acquire load, so the item's contents are visible without a lock. The
///   producer's and the consumer's indices are on separate cache lines; each side caches the
///   other's index to touch the shared line only when the ring looks full (producer) or empty
///   (consumer).
///
/// Thread-safety: one producer thread may call tryPush()/tryEmplace(), one consumer thread may call
/// tryPop() at the same time; sizeApprox(), dropped() and capacity() are thread-safe from any
/// thread. Two producers (or two consumers) at once are a bug. Real-time safety: every member
/// function is real-time safe and wait-free (when T's move is).
///
/// \tparam T item type; moving it must not throw (a trivially copyable struct is ideal).
/// \tparam N number of slots, a power of two >= 2.
template <class T, std::size_t N>
class SpscRing {
    static_assert(N >= 2 && (N & (N - 1)) == 0, "SpscRing capacity must be a power of two >= 2");
    static_assert(std::is_nothrow_move_constructible_v<T> && std::is_nothrow_destructible_v<T>,
                  "SpscRing items must be nothrow move-constructible and destructible");

public:
    SpscRing() noexcept = default;
    /// Destroys the items still queued. Neither thread may use the ring any more.
    ~SpscRing()
    {
        if constexpr (!std::is_trivially_destructible_v<T>) {
            const std::size_t tail = tail_.value.load(std::memory_order_acquire);
            for (std::size_t i = head_.value.load(std::memory_order_relaxed); i != tail; ++i)
                std::launder(slot(i))->~T();
        }
    }

    /// \brief Appends a copy of \a item. Producer only.
    /// \return true when queued; false when the ring was full (the item is dropped and counted).
    bool tryPush(const T &item) noexcept(std::is_nothrow_copy_constructible_v<T>)
    {
        return tryEmplace(item);
    }

    /// \brief Appends \a item by move. Producer only.
    /// \return true when queued; false when the ring was full (\a item is left untouched and
    /// counted).
    bool tryPush(T &&item) noexcept { return tryEmplace(std::move(item)); }

    /// \brief Constructs an item in place from \a args. Producer only.
    /// \return true when queued; false when the ring was full (nothing constructed, dropped() + 1).
    template <class... Args>
    bool tryEmplace(Args &&...args) noexcept(std::is_nothrow_constructible_v<T, Args &&...>)
    {
        const std::size_t tail = tail_.value.load(std::memory_order_relaxed);
        if (tail - headCache_ >= N) {
            headCache_ = head_.value.load(std::memory_order_acquire);
            if (tail - headCache_ >= N) {
                dropped_.fetch_add(1, std::memory_order_relaxed);
                return false;
            }
        }
        new (slot(tail)) T(std::forward<Args>(args)...);
        tail_.value.store(tail + 1, std::memory_order_release);
        return true;
    }

    /// \brief Removes the oldest item into \a out (move-assigned). Consumer only.
    /// \return true when an item was removed; false when the ring was empty (\a out untouched).
    bool tryPop(T &out) noexcept(std::is_nothrow_move_assignable_v<T>)
    {
        const std::size_t head = head_.value.load(std::memory_order_relaxed);
        if (head == tailCache_) {
            tailCache_ = tail_.value.load(std::memory_order_acquire);
            if (head == tailCache_)
                return false;
        }
        T *item = std::launder(slot(head));
        out = std::move(*item);
        item->~T();
        head_.value.store(head + 1, std::memory_order_release);
        return true;
    }

    /// \return the number of queued items; exact when called by the producer or the consumer with
    /// the other side idle, otherwise a snapshot that may already be stale. Thread-safe.
    [[nodiscard]] std::size_t sizeApprox() const noexcept
    {
        // head first: tail can only have grown since, so tail - head never underflows. Pops and
        // pushes between the two loads can make it exceed N: clamp.
        const std::size_t head = head_.value.load(std::memory_order_acquire);
        const std::size_t tail = tail_.value.load(std::memory_order_acquire);
        const std::size_t size = tail - head;
        return size > N ? N : size;
    }

    /// \return true when sizeApprox() is 0. Thread-safe.
    [[nodiscard]] bool emptyApprox() const noexcept { return sizeApprox() == 0; }

    /// \return the number of items refused by tryPush()/tryEmplace() because the ring was full
    /// since construction. Thread-safe.
    [[nodiscard]] std::uint64_t dropped() const noexcept
    {
        return dropped_.load(std::memory_order_relaxed);
    }

    /// \return N, the number of slots.
    [[nodiscard]] static constexpr std::size_t capacity() noexcept { return N; }

private:
    DT_DISABLE_COPY_AND_MOVE(SpscRing)

    /// An index alone on its cache line.
    struct alignas(kCacheLineBytes) PaddedIndex {
        std::atomic<std::size_t> value{0};
    };
    struct alignas(T) Slot {
        unsigned char bytes[sizeof(T)];
    };

    T *slot(std::size_t index) noexcept
    {
        return reinterpret_cast<T *>(slots_[index & (N - 1)].bytes);
    }

    // Indices grow without bound and wrap modulo 2^bits; N divides 2^bits, so tail - head and
    // index & (N - 1) stay correct across the wrap.
    PaddedIndex head_; ///< Next slot to pop. Written by the consumer.
    alignas(kCacheLineBytes) std::size_t tailCache_ = 0; ///< Consumer's copy of tail_.
    PaddedIndex tail_; ///< Next slot to fill. Written by the producer.
    alignas(kCacheLineBytes) std::size_t headCache_ = 0; ///< Producer's copy of head_.
    std::atomic<std::uint64_t> dropped_{0};              ///< Written by the producer.
    alignas(kCacheLineBytes) Slot slots_[N];
};

} // namespace depthtouch::platform
