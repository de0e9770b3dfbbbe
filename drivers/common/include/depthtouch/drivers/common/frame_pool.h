#pragma once
/// \file
/// \brief A fixed pool of frames lent through hal::FrameRef, shared by the backends that lend
/// frames (mock decoder and camera, FFmpeg decoder).
///
/// allocate() (not real-time safe) sizes the pool; acquire()/lend() and the release by FrameRef do
/// not allocate or lock. Thread-safety: acquire(), lend(), allocate() and abandon() are
/// thread-bound (the backend's thread); releaseFrame() and lent() are thread-safe.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// Thread-safety: see the file comment.
class FramePool final : public hal::FrameOwner {
public:
    FramePool() = default;
    ~FramePool() override;

    /// When the pixel memory of each frame is allocated.
    enum class Pixels : std::uint8_t {
        Now,      ///< By allocate() (every frame has CPU planes).
        OnDemand, ///< By ensurePixels(), for frames that need CPU planes (dma-buf backends).
    };

    /// \brief Makes \a count frames of \a format, \a width × \a height, tightly packed.
    /// With Pixels::OnDemand the frames' images have the size and format but no planes until
    /// ensurePixels(). \return Busy when a frame is still lent (nothing changes).
    Result<void> allocate(int count, hal::PixelFormat format, int width, int height,
                          Pixels pixels = Pixels::Now);

    /// \brief Gives the acquired frame in \a slot its CPU planes (allocated on first use, then
    /// kept) and points its image at them. Not real-time safe. \pre \a slot is acquired.
    /// \return OutOfResources when the memory cannot be allocated.
    Result<void> ensurePixels(std::uint32_t slot) noexcept;

    /// \return whether the frame in \a slot is acquired or lent now. Thread-safe.
    [[nodiscard]] bool isLent(std::uint32_t slot) const noexcept
    {
        return slots_[slot].inUse.load(std::memory_order_acquire);
    }

    /// \brief Takes a free frame for filling. \return the frame, or nullptr when every frame is
    /// lent. \param[out] slot The frame's slot, for lend() or abandon().
    hal::Frame *acquire(std::uint32_t &slot) noexcept;
    /// Lends the acquired frame in \a slot.
    hal::FrameRef lend(std::uint32_t slot) noexcept;
    /// Gives back an acquired frame that will not be lent.
    void abandon(std::uint32_t slot) noexcept { releaseFrame(slot); }

    void releaseFrame(std::uint32_t slot) noexcept override;

    /// \return the number of frames acquired or lent and not yet returned.
    [[nodiscard]] int lent() const noexcept { return lent_.load(std::memory_order_acquire); }
    /// \return the number of frames.
    [[nodiscard]] int size() const noexcept { return count_; }
    /// \return whether acquire() would find a free frame now.
    [[nodiscard]] bool hasFree() const noexcept { return lent() < count_; }

private:
    struct Slot {
        /// Not zero-filled: its pages become resident when a frame is first written into it
        /// (acquire() takes the lowest free slot), as the receiver's FrameStore.
        std::unique_ptr<std::uint8_t[]> pixels;
        std::size_t pixelBytes = 0;
        hal::Frame frame;
        std::atomic<bool> inUse{false};
    };

    std::unique_ptr<Slot[]> slots_;
    int count_ = 0;
    hal::PixelFormat format_ = hal::PixelFormat::Unknown;
    int width_ = 0;
    int height_ = 0;
    std::atomic<int> lent_{0};
};

} // namespace depthtouch::drivers
