#pragma once
/// \file
/// \brief TripleBuffer (alias Mailbox): latest-value hand-over from one writer thread to one reader
/// thread that never blocks either side, e.g. the newest depth frame from the decoder to the haptic
/// task.
///
/// The header is C++17-clean.

#include <atomic>
#include <cstdint>
#include <type_traits>

#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// \brief Three pre-constructed T objects rotated between a writer, a reader and a shared middle
/// slot.
///
/// Writer: fill writeBuffer() completely, then publish(). Reader: update() (true when something
/// newer was published since the last update()), then read readBuffer(), which stays unchanged
/// until the reader's next update(). The reader only ever sees whole published values (no tearing),
/// the values it sees are in publication order (never older than one seen before), and values
/// published between two update() calls are skipped except for the newest one.
///
/// Objects are never copied or reallocated: publish() and update() swap buffer indices with one
/// atomic exchange, so T may own preallocated storage (a std::vector sized at construction). After
/// publish(), writeBuffer() refers to a buffer holding an older value: the writer must overwrite
/// all of it.
///
/// Thread-safety: one writer thread (writeBuffer(), publish()) and one reader thread (update(),
/// readBuffer()) at the same time; no other concurrent use.
/// Real-time safety: every member function except the constructors is real-time and wait-free.
template <class T>
class TripleBuffer {
public:
    /// Default-constructs the three buffers. Allocates only what T's default constructor allocates.
    TripleBuffer() = default;
    /// Copies \a prototype into the three buffers (e.g. a vector already sized for the largest
    /// frame).
    explicit TripleBuffer(const T &prototype) : buffers_{{prototype}, {prototype}, {prototype}} {}

    /// \return the buffer the writer fills next. Writer only.
    [[nodiscard]] T &writeBuffer() noexcept { return buffers_[writeIndex_].value; }

    /// \brief Makes the filled writeBuffer() the latest value and hands the writer another buffer.
    /// Writer only; never waits for the reader.
    void publish() noexcept
    {
        // acq_rel: release makes the written contents visible to the reader that takes this index;
        // acquire makes sure the reader has finished with the buffer we get back.
        const std::uint8_t previous = middle_.value.exchange(
            static_cast<std::uint8_t>(writeIndex_ | kFreshBit), std::memory_order_acq_rel);
        writeIndex_ = static_cast<std::uint8_t>(previous & kIndexMask);
    }

    /// \brief Takes the latest published value, if newer than the one in readBuffer(). Reader only.
    /// \return true when readBuffer() now holds a newer value; false when nothing was published
    /// since the last call (readBuffer() unchanged).
    bool update() noexcept
    {
        if ((middle_.value.load(std::memory_order_relaxed) & kFreshBit) == 0)
            return false;
        // Only the reader clears kFreshBit, so the slot is still fresh (possibly even newer) here.
        const std::uint8_t previous = middle_.value.exchange(readIndex_, std::memory_order_acq_rel);
        readIndex_ = static_cast<std::uint8_t>(previous & kIndexMask);
        return true;
    }

    /// \return true when a value newer than readBuffer() is waiting. Thread-safe (a snapshot).
    [[nodiscard]] bool hasUpdate() const noexcept
    {
        return (middle_.value.load(std::memory_order_relaxed) & kFreshBit) != 0;
    }

    /// \return the value taken by the last update() that returned true (a default or prototype
    /// value before the first one). Reader only; stable until the reader's next update().
    [[nodiscard]] const T &readBuffer() const noexcept { return buffers_[readIndex_].value; }
    /// \copydoc readBuffer() const
    [[nodiscard]] T &readBuffer() noexcept { return buffers_[readIndex_].value; }

private:
    DT_DISABLE_COPY_AND_MOVE(TripleBuffer)

    static constexpr std::uint8_t kIndexMask = 0x3;
    static constexpr std::uint8_t kFreshBit = 0x4;

    /// One buffer per cache line, so the writer filling one does not slow the reader reading
    /// another.
    struct alignas(kCacheLineBytes) Slot {
        T value;
    };
    struct alignas(kCacheLineBytes) PaddedState {
        std::atomic<std::uint8_t> value{1}; ///< Index of the middle buffer, plus kFreshBit.
    };

    Slot buffers_[3]{}; ///< Value-initialised: a fresh mailbox reads T{}.
    alignas(kCacheLineBytes) std::uint8_t writeIndex_ = 0; ///< Owned by the writer.
    PaddedState middle_;
    alignas(kCacheLineBytes) std::uint8_t readIndex_ = 2; ///< Owned by the reader.
};

/// Latest-value mailbox: the name used by the application for TripleBuffer.
template <class T>
using Mailbox = TripleBuffer<T>;

} // namespace depthtouch::platform
