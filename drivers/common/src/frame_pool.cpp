#include "depthtouch/drivers/common/frame_pool.h"

#include <new>

#include "depthtouch/platform/assert.h"

namespace depthtouch::drivers {

FramePool::~FramePool()
{
    // A FrameRef that outlives its backend would release into freed memory (HAL contract).
    DT_ASSERT(lent() == 0);
}

namespace {

/// Points \a img (\a format, \a width × \a height) at the tightly packed planes in \a pixels.
void pointPlanes(hal::ImageView &img, std::uint8_t *pixels, hal::PixelFormat format, int width,
                 int height) noexcept
{
    img.width = width;
    img.height = height;
    img.format = format;
    img.planes = {};
    std::uint8_t *p = pixels;
    for (int plane = 0; plane < hal::planeCount(format); ++plane) {
        const hal::PlaneLayout l = hal::planeLayout(format, width, height, plane);
        img.planes[static_cast<std::size_t>(plane)] = {p, l.rowBytes};
        p += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
    }
}

} // namespace

Result<void> FramePool::allocate(int count, hal::PixelFormat format, int width, int height,
                                 Pixels pixels)
{
    if (lent() != 0)
        return unexpected(Errc::Busy, "Frames are still lent");
    auto slots = std::make_unique<Slot[]>(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        Slot &s = slots[static_cast<std::size_t>(i)];
        if (pixels == Pixels::Now) {
            s.pixelBytes = hal::imageBytes(format, width, height);
            s.pixels = std::make_unique_for_overwrite<std::uint8_t[]>(s.pixelBytes);
            pointPlanes(s.frame.image, s.pixels.get(), format, width, height);
        } else {
            s.frame.image.width = width;
            s.frame.image.height = height;
            s.frame.image.format = format;
        }
    }
    slots_ = std::move(slots);
    count_ = count;
    format_ = format;
    width_ = width;
    height_ = height;
    return ok();
}

Result<void> FramePool::ensurePixels(std::uint32_t slot) noexcept
{
    DT_DEBUG_ASSERT(slot < static_cast<std::uint32_t>(count_));
    Slot &s = slots_[slot];
    const std::size_t bytes = hal::imageBytes(format_, width_, height_);
    if (s.pixelBytes != bytes || !s.pixels) {
        try {
            s.pixels = std::make_unique_for_overwrite<std::uint8_t[]>(bytes);
            s.pixelBytes = bytes;
        } catch (const std::bad_alloc &) {
            return unexpected(Errc::OutOfResources, "Failed to allocate a frame's pixels");
        }
    }
    pointPlanes(s.frame.image, s.pixels.get(), format_, width_, height_);
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
