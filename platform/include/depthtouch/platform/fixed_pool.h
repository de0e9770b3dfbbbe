#pragma once
/// \file
/// \brief FixedPool: a fixed set of pre-constructed objects handed out and returned without locks
/// or allocation, e.g. frame buffers shared between the decoder and the renderer.
///
/// The header is C++17-clean.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "depthtouch/platform/assert.h"
#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/slot_ref.h"

namespace depthtouch::platform {

/// \brief Pool of \a capacity objects of type T, all constructed by the pool's constructor.
///
/// acquire() takes a free object and returns a move-only Handle; destroying (or reset()ting) the
/// handle returns the object. Objects are reused as they are: the next acquirer sees what the
/// previous user left, so T may own preallocated storage. acquire() on an empty pool returns an
/// empty Handle and counts the failure in exhausted(); it never allocates or blocks.
///
/// The free list is a Treiber stack of indices whose head carries a 32-bit tag incremented on every
/// change, so a compare-exchange cannot succeed on a head that was popped and pushed back in
/// between (ABA), unless one thread stalls across exactly 2^32 pool operations.
///
/// Thread-safety: acquire(), Handle::reset() and the Handle destructor are thread-safe and
/// lock-free (any number of threads). A Handle itself is thread-bound: hand it to another thread by
/// moving it. All handles must be gone before the pool is destroyed (checked by DT_ASSERT).
/// Real-time safety: everything but the constructor and destructor is real-time safe.
template <class T>
class FixedPool {
public:
    /// \brief Owning reference to one object of the pool; returns it on destruction. Move-only.
    class Handle {
    public:
        /// An empty handle.
        Handle() noexcept = default;

        /// Returns the object to the pool now; the handle becomes empty. No-op on an empty handle.
        void reset() noexcept { ref_.reset(); }

        /// \return true when the handle holds an object.
        explicit operator bool() const noexcept { return static_cast<bool>(ref_); }
        /// \return the object, or nullptr for an empty handle.
        [[nodiscard]] T *get() const noexcept
        {
            return ref_ ? &ref_.owner()->objects_[ref_.slot()] : nullptr;
        }
        /// \pre the handle is not empty.
        T &operator*() const noexcept
        {
            DT_DEBUG_ASSERT(ref_.owner() != nullptr);
            return ref_.owner()->objects_[ref_.slot()];
        }
        /// \pre the handle is not empty.
        T *operator->() const noexcept
        {
            DT_DEBUG_ASSERT(ref_.owner() != nullptr);
            return &ref_.owner()->objects_[ref_.slot()];
        }
        /// \return the object's slot in the pool, 0 .. capacity() - 1. \pre the handle is not
        /// empty.
        [[nodiscard]] std::uint32_t index() const noexcept { return ref_.slot(); }

    private:
        friend class FixedPool;
        Handle(FixedPool *pool, std::uint32_t index) noexcept : ref_(pool, index) {}

        SlotRef<FixedPool> ref_; ///< Move-only: so is the handle.
    };

    /// \brief Allocates and default-constructs \a capacity objects (the only allocation of the
    /// pool). \pre 0 < capacity < 2^32 - 1 (DT_ASSERT).
    explicit FixedPool(std::size_t capacity)
        : objects_(capacity), next_(new std::atomic<std::uint32_t>[capacity])
    {
        initFreeList();
    }

    /// \brief Allocates \a capacity copies of \a prototype (the only allocation of the pool).
    /// \pre 0 < capacity < 2^32 - 1 (DT_ASSERT).
    FixedPool(std::size_t capacity, const T &prototype)
        : objects_(capacity, prototype), next_(new std::atomic<std::uint32_t>[capacity])
    {
        initFreeList();
    }

    /// \pre every Handle has been destroyed or reset (DT_ASSERT).
    ~FixedPool() { DT_ASSERT(available() == capacity()); }

    /// \brief Takes a free object.
    /// \return a handle to it, or an empty handle when every object is in use (exhausted() + 1).
    [[nodiscard]] Handle acquire() noexcept
    {
        std::uint64_t head = head_.load(std::memory_order_acquire);
        for (;;) {
            const std::uint32_t index = indexOf(head);
            if (index == kNil) {
                exhausted_.fetch_add(1, std::memory_order_relaxed);
                return Handle();
            }
            // May read a stale link if another thread takes `index` meanwhile: then the head's tag
            // has changed and the compare-exchange fails and retries.
            const std::uint32_t next = next_[index].load(std::memory_order_relaxed);
            if (head_.compare_exchange_weak(head, pack(tagOf(head) + 1, next),
                                            std::memory_order_acq_rel, std::memory_order_acquire)) {
                available_.fetch_sub(1, std::memory_order_relaxed);
                return Handle(this, index);
            }
        }
    }

    /// \return the number of objects, fixed at construction.
    [[nodiscard]] std::size_t capacity() const noexcept { return objects_.size(); }
    /// \return the number of free objects (a snapshot while other threads use the pool).
    /// Thread-safe.
    [[nodiscard]] std::size_t available() const noexcept
    {
        return available_.load(std::memory_order_relaxed);
    }
    /// \return how many acquire() calls found the pool empty since construction. Thread-safe.
    [[nodiscard]] std::uint64_t exhausted() const noexcept
    {
        return exhausted_.load(std::memory_order_relaxed);
    }

private:
    DT_DISABLE_COPY_AND_MOVE(FixedPool)
    friend class SlotRef<FixedPool>; // calls release()

    static constexpr std::uint32_t kNil = 0xFFFFFFFFu;

    static constexpr std::uint64_t pack(std::uint32_t tag, std::uint32_t index) noexcept
    {
        return (static_cast<std::uint64_t>(tag) << 32) | index;
    }
    static constexpr std::uint32_t tagOf(std::uint64_t head) noexcept
    {
        return static_cast<std::uint32_t>(head >> 32);
    }
    static constexpr std::uint32_t indexOf(std::uint64_t head) noexcept
    {
        return static_cast<std::uint32_t>(head);
    }

    void initFreeList() noexcept
    {
        DT_ASSERT(!objects_.empty() && objects_.size() < kNil);
        const auto count = static_cast<std::uint32_t>(objects_.size());
        for (std::uint32_t i = 0; i < count; ++i)
            next_[i].store(i + 1 < count ? i + 1 : kNil, std::memory_order_relaxed);
        available_.store(count, std::memory_order_relaxed);
        head_.store(pack(0, 0), std::memory_order_release);
    }

    void release(std::uint32_t index) noexcept
    {
        available_.fetch_add(1, std::memory_order_relaxed);
        std::uint64_t head = head_.load(std::memory_order_relaxed);
        for (;;) {
            next_[index].store(indexOf(head), std::memory_order_relaxed);
            // release: the user's writes to the object and the link above happen before the next
            // acquire() that pops this index.
            if (head_.compare_exchange_weak(head, pack(tagOf(head) + 1, index),
                                            std::memory_order_release, std::memory_order_relaxed))
                return;
        }
    }

    std::vector<T> objects_;
    std::unique_ptr<std::atomic<std::uint32_t>[]> next_; ///< Free-list links, one per object.
    alignas(kCacheLineBytes) std::atomic<std::uint64_t> head_{
        pack(0, kNil)}; ///< Tag << 32 | first free.
    std::atomic<std::size_t> available_{0};
    std::atomic<std::uint64_t> exhausted_{0};
};

} // namespace depthtouch::platform
