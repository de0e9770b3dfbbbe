#pragma once
/// \file
/// \brief FrameStore: the receiver's preallocated pool of decoded frames, shared by reference
/// count.
///
/// The receiver copies each decoded frame out of the decoder's pool into a FrameStore slot at once,
/// so the decoder never stalls on frames held downstream. A slot is shared through FrameHandle: the
/// depth frame i is referenced by the paired frame i (current) and by the paired frame i-1 (next),
/// without a copy. Slots are allocated by allocate() when a file is opened; acquiring, sharing and
/// releasing never allocate, lock or block.
///
/// Memory: allocate() reserves every slot's pixels but writes none of them (no zero fill), and
/// acquire() hands out the lowest free slot, so a slot's pages become resident only when a frame is
/// first written into it: the store's resident size follows the most frames held at once, not its
/// count (docs/memory.md "4K"). Every written frame fills its planes whole before anyone reads it.
///
/// Zero-copy frames: a slot may instead hold the decoder's frame itself (StoredFrame::decoded, a
/// colour frame lent as dma-bufs); the last handle's release returns it to the decoder.
///
/// Thread-safety: allocate() and acquire() are thread-bound (the decode thread).
/// FrameHandle::share(), the release of a handle (destructor, reset()) and inUse() are thread-safe
/// and lock-free: a handle may be moved to the render or the haptic thread and dropped there. The
/// store must outlive every handle (checked by DT_ASSERT in its destructor).

#include <atomic>
#include <cstdint>
#include <memory>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/slot_ref.h"

namespace depthtouch::receiver {

/// \brief A decoded frame held by the receiver: tightly packed planes (strideBytes = row bytes), or
/// the decoder's own frame when it came as dma-bufs (zero-copy; see \a dmabuf).
struct StoredFrame {
    /// Pixels in the store's memory; read-only for every handle holder. For a zero-copy frame the
    /// decoder's image instead: size and format, and planes only if the decoder gave CPU planes
    /// too.
    hal::ImageView image;
    hal::StreamKind kind = hal::StreamKind::Color;
    hal::Pts pts = hal::kNoPts; ///< Presentation time on the stream timeline (ns).
    std::uint64_t sequence = 0; ///< Frames of this stream decoded before it since open().
    bool corrupt = false;       ///< The decoder concealed damage in this frame.
    /// Depth frames: samples below this are holes (ReceiverInfo::depthHoleBelow, in the units of
    /// \a image); 0 for colour and for depth without holes.
    std::uint32_t holeBelow = 0;
    /// Zero-copy colour frames: the decoder's dma-bufs (hal::DmaBufImage ownership: valid while a
    /// handle is held, never closed by a holder). Empty for a copied frame.
    hal::DmaBufImage dmabuf{};
    /// Zero-copy frames: the decoder's frame, kept until the last handle is dropped (its release
    /// returns it to the decoder). Empty for a copied frame.
    hal::FrameRef decoded;
};

class FrameStore;

/// \brief A counted reference to one StoredFrame. Move-only; share() makes another reference.
/// Destroying or reset()ting the last reference returns the slot to its store.
class FrameHandle {
public:
    FrameHandle() noexcept = default;

    /// \return another reference to the same frame (empty when this one is empty). Lock-free.
    [[nodiscard]] FrameHandle share() const noexcept;
    /// Drops this reference; the handle becomes empty. Lock-free.
    void reset() noexcept;

    explicit operator bool() const noexcept { return static_cast<bool>(ref_); }
    /// \return the frame, or nullptr when empty.
    [[nodiscard]] const StoredFrame *get() const noexcept;
    /// \pre not empty.
    const StoredFrame &operator*() const noexcept { return *get(); }
    /// \pre not empty.
    const StoredFrame *operator->() const noexcept { return get(); }

private:
    friend class FrameStore;
    FrameHandle(FrameStore *store, std::uint32_t slot) noexcept : ref_(store, slot) {}

    platform::SlotRef<FrameStore> ref_; ///< Move-only: so is the handle.
};

/// \brief A fixed number of frames of one format and size (see the file comment).
class FrameStore {
public:
    FrameStore() = default;
    ~FrameStore();

    /// \brief Makes \a count frames of \a format, \a width × \a height pixels, tightly packed.
    /// \return nothing on success. Errors: Busy (a handle is still held; nothing changes),
    /// InvalidArgument (count outside 1..1024, non-positive size, format without planes).
    Result<void> allocate(int count, hal::PixelFormat format, int width, int height);

    /// \brief Takes a free frame for filling.
    /// \param[out] writable The frame's storage, valid to write until the handle is first shared.
    /// \return a handle to it, or an empty handle when every frame is referenced.
    [[nodiscard]] FrameHandle acquire(StoredFrame *&writable) noexcept;

    /// \return the number of frames referenced now. Thread-safe.
    [[nodiscard]] int inUse() const noexcept { return inUse_.load(std::memory_order_acquire); }
    /// \return the number of frames.
    [[nodiscard]] int size() const noexcept { return count_; }
    /// \return the bytes of pixels of one frame.
    [[nodiscard]] std::size_t frameBytes() const noexcept { return frameBytes_; }

private:
    DT_DISABLE_COPY_AND_MOVE(FrameStore)
    friend class FrameHandle;
    friend class platform::SlotRef<FrameStore>; // calls release()

    struct Slot {
        std::unique_ptr<std::uint8_t[]> pixels;
        hal::ImageView view; ///< The slot's own planes, restored by acquire().
        StoredFrame frame;
        std::atomic<int> refs{0};
    };

    void addRef(std::uint32_t slot) noexcept;
    void release(std::uint32_t slot) noexcept;

    std::unique_ptr<Slot[]> slots_;
    int count_ = 0;
    std::size_t frameBytes_ = 0;
    std::atomic<int> inUse_{0};
};

/// \return another reference to \a h (PtsPairer payload sharing).
inline FrameHandle sharePayload(const FrameHandle &h) noexcept
{
    return h.share();
}

} // namespace depthtouch::receiver
