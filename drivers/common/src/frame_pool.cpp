#include "depthtouch/drivers/common/frame_pool.h"

#include "depthtouch/platform/assert.h"

namespace depthtouch::drivers {

FramePool::~FramePool()
{
    // A FrameRef that outlives its backend would release into freed memory (HAL contract).
    DT_ASSERT(lent() == 0);
}

Result<void> FramePool::allocate(int count, hal::PixelFormat format, int width, int height)
{
    if (lent() != 0)
        return unexpected(Errc::Busy, "Frames are still lent");
    auto slots = std::make_unique<Slot[]>(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        Slot &s = slots[static_cast<std::size_t>(i)];
        s.pixels.assign(hal::imageBytes(format, width, height), 0);
        hal::ImageView &img = s.frame.image;
        img.width = width;
        img.height = height;
        img.format = format;
        std::uint8_t *p = s.pixels.data();
        for (int plane = 0; plane < hal::planeCount(format); ++plane) {
            const hal::PlaneLayout l = hal::planeLayout(format, width, height, plane);
            img.planes[static_cast<std::size_t>(plane)] = {p, l.rowBytes};
            p += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
        }
    }
    slots_ = std::move(slots);
    count_ = count;
    return ok();
}

hal::Frame *FramePool::acquire(std::uint32_t &slot) noexcept
{
    for (int i = 0; i < count_; ++i) {
        Slot &s = slots_[static_cast<std::size_t>(i)];
        bool expected = false;
        if (s.inUse.compare_exchange_strong(expected, true, std::memory_order_acq_rel)) {
            lent_.fetch_add(1, std::memory_order_acq_rel);
            slot = static_cast<std::uint32_t>(i);
            return &s.frame;
        }
    }
    return nullptr;
}

hal::FrameRef FramePool::lend(std::uint32_t slot) noexcept
{
    return hal::FrameRef(this, slot, &slots_[slot].frame);
}

void FramePool::releaseFrame(std::uint32_t slot) noexcept
{
    DT_DEBUG_ASSERT(slot < static_cast<std::uint32_t>(count_));
    if (slots_[slot].inUse.exchange(false, std::memory_order_acq_rel))
        lent_.fetch_sub(1, std::memory_order_acq_rel);
}

} // namespace depthtouch::drivers
