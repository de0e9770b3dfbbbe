#include "depthtouch/receiver/frame_store.h"

#include "depthtouch/platform/assert.h"

namespace depthtouch::receiver {

FrameHandle FrameHandle::share() const noexcept
{
    if (!ref_)
        return {};
    ref_.owner()->addRef(ref_.slot());
    return FrameHandle(ref_.owner(), ref_.slot());
}

void FrameHandle::reset() noexcept
{
    ref_.reset();
}

const StoredFrame *FrameHandle::get() const noexcept
{
    return ref_ ? &ref_.owner()->slots_[ref_.slot()].frame : nullptr;
}

FrameStore::~FrameStore()
{
    DT_ASSERT(inUse() == 0);
}

Result<void> FrameStore::allocate(int count, hal::PixelFormat format, int width, int height)
{
    if (inUse() != 0)
        return unexpected(Errc::Busy, "A receiver frame is still referenced");
    const std::size_t bytes = hal::imageBytes(format, width, height);
    if (count < 1 || count > 1024 || bytes == 0)
        return unexpected(Errc::InvalidArgument, "Receiver frame pool size or format out of range");
    auto slots = std::make_unique<Slot[]>(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        Slot &s = slots[static_cast<std::size_t>(i)];
        s.pixels = std::make_unique_for_overwrite<std::uint8_t[]>(bytes);
        s.frame.image.width = width;
        s.frame.image.height = height;
        s.frame.image.format = format;
        std::uint8_t *base = s.pixels.get();
        for (int p = 0; p < hal::planeCount(format); ++p) {
            const hal::PlaneLayout l = hal::planeLayout(format, width, height, p);
            s.frame.image.planes[static_cast<std::size_t>(p)] = {base, l.rowBytes};
            base += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
        }
        s.view = s.frame.image;
    }
    slots_ = std::move(slots);
    count_ = count;
    frameBytes_ = bytes;
    return ok();
}

FrameHandle FrameStore::acquire(StoredFrame *&writable) noexcept
{
    for (int i = 0; i < count_; ++i) {
        Slot &s = slots_[static_cast<std::size_t>(i)];
        int expected = 0;
        if (s.refs.load(std::memory_order_relaxed) == 0 &&
            s.refs.compare_exchange_strong(expected, 1, std::memory_order_acquire,
                                           std::memory_order_relaxed)) {
            inUse_.fetch_add(1, std::memory_order_relaxed);
            s.frame.image = s.view; // a zero-copy frame may have pointed it elsewhere
            s.frame.dmabuf = hal::DmaBufImage{};
            writable = &s.frame;
            return FrameHandle(this, static_cast<std::uint32_t>(i));
        }
    }
    writable = nullptr;
    return {};
}

void FrameStore::addRef(std::uint32_t slot) noexcept
{
    slots_[slot].refs.fetch_add(1, std::memory_order_relaxed);
}

void FrameStore::release(std::uint32_t slot) noexcept
{
    // acq_rel: the holders' reads of the pixels happen before the next acquire() rewrites them.
    // The last reference (count 1: no other handle exists to share it, and acquire() takes only
    // free slots) first returns a zero-copy frame to its decoder, then frees the slot.
    Slot &s = slots_[slot];
    int refs = s.refs.load(std::memory_order_acquire);
    for (;;) {
        if (refs == 1) {
            s.frame.decoded.reset();
            s.refs.store(0, std::memory_order_release);
            inUse_.fetch_sub(1, std::memory_order_release);
            return;
        }
        if (s.refs.compare_exchange_weak(refs, refs - 1, std::memory_order_acq_rel,
                                         std::memory_order_acquire))
            return;
    }
}

} // namespace depthtouch::receiver
