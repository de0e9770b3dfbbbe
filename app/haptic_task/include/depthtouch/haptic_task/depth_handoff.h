#pragma once
/// \file
/// \brief DepthHandoff: the lock-free hand-over of depth frames to the haptic thread
/// (docs/architecture.md §1 and §5): preallocated frame slots, published as pairs (frame i, frame
/// i+1) for the local surface interpolation of paper IV.B (Eq. 1). In the player the render thread
/// writes it: when frame i goes on screen it publishes (depth i, depth i+1) with publishPair(),
/// which copies each new depth frame once (app/playback, render_loop.cpp).
///
/// Thread-safety: one writer thread (the player's render thread: beginFrame(), publish(),
/// publishPair(), push(), finish(), restart(), setMediaOrigin()) and one reader thread (the haptic
/// task: acquire(), mediaOrigin()) at the same time; no other concurrent use. create() and the
/// destructor are for neither thread while the other runs. Real-time safety: every member function
/// except create() is wait-free or lock-free (a compare-exchange loop that only retries when the
/// other side changed the state), never allocates, never blocks and never logs.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptic_task {

/// \brief One preallocated depth frame: W×H samples, rows packed (stride W·bytesPerSample), and
/// its presentation time.
struct DepthSlot {
    std::uint8_t *data = nullptr; ///< W·H·bytesPerSample bytes, owned by the DepthHandoff.
    std::size_t bytes = 0;        ///< Size of data.
    double pts = 0.0;             ///< Presentation time, s (the media timeline).
    int index = -1;               ///< Slot number, 0 .. DepthHandoff::kSlots − 1.
    /// Samples below this are holes (scene::DepthFrameView::holeBelow, the slot's sample units);
    /// 0: none. Set by the writer, like pts.
    std::uint32_t holeBelow = 0;
    /// The slot's material codes (W·H RGB24, scene/material.h), null when the handoff carries no
    /// materials. The writer sets hasMaterial when it filled them.
    std::uint8_t *material = nullptr;
    bool hasMaterial = false;
};

/// \brief The pair the haptic thread renders: frame i and the buffered frame i+1 (paper IV.B).
struct DepthPair {
    scene::DepthFrameView current{};   ///< Frame i.
    scene::DepthFrameView next{};      ///< Frame i+1; meaningful when hasNext.
    bool hasNext = false;              ///< False at the end of the stream or before frame i+1.
    std::uint64_t sequence = 0;        ///< Publications taken by the reader so far (1 = first).
};

/// \brief Lock-free handoff of preallocated depth frames from one writer thread (the player's
/// render thread) to the haptic thread.
///
/// kSlots frames of a fixed size and format are allocated by create(). The writer fills a free
/// slot (beginFrame()) and publishes a pair of slots (publish()); or uses publishPair(), which
/// copies (frame i, frame i+1) and reuses the slot of a frame it published as "next" before; or
/// push(), which copies a frame and publishes (previous frame, this frame).
/// The reader's acquire() takes the newest published pair without waiting; the views stay valid
/// and unchanged until its next successful acquire(). When the writer stalls, acquire() returns
/// false and the reader keeps rendering the pair it holds. Pairs published between two acquire()
/// calls are skipped except the newest.
///
/// How it stays lock-free: one atomic word holds the published pair, the pair the reader holds and
/// a "fresh" bit. The reader swaps "held" for "published" with a compare-exchange; the writer only
/// ever writes into a slot that is in neither pair nor already handed out by beginFrame(). "Held"
/// can only change to "published", which the writer set itself, so the writer's choice stays safe
/// even when its view of the word is stale: 2 held + 2 published + 2 being filled = 6 slots.
class DepthHandoff {
public:
    /// Number of preallocated frames.
    static constexpr int kSlots = 6;

    /// \brief Allocates kSlots frames of \a width × \a height samples of \a format and, with
    /// \a material, a W×H RGB24 material image per slot (the material track, scene/material.h):
    /// a frame view's material is copied with its depth and handed to the reader with it.
    /// \return the handoff, or Errc::InvalidArgument (width or height < 2, or above 16384),
    /// Errc::OutOfResources (allocation failed).
    static Result<std::unique_ptr<DepthHandoff>>
    create(int width, int height, scene::SampleFormat format, bool material = false);

    [[nodiscard]] int width() const noexcept { return width_; }   ///< W, samples.
    [[nodiscard]] int height() const noexcept { return height_; } ///< H, rows.
    [[nodiscard]] scene::SampleFormat format() const noexcept { return format_; }
    /// \return bytes of one frame (W·H·bytesPerSample).
    [[nodiscard]] std::size_t frameBytes() const noexcept { return frameBytes_; }
    /// \return true when the slots carry material images (create()'s \a material).
    [[nodiscard]] bool carriesMaterial() const noexcept { return materialBytes_ > 0; }

    /// \name Writer (one thread: the player's render thread)
    ///@{
    /// \brief Hands out a slot the reader does not use and that is not part of the published pair.
    /// Fill all of data and set pts, then publish() it. Calling it twice before publishing hands
    /// out two different slots (for a pair of new frames).
    /// \pre at most two slots handed out and not yet published (DT_ASSERT). \return the slot.
    DepthSlot beginFrame() noexcept;
    /// \brief Publishes the pair (\a current, \a next); \a next may be null (frame i is the last).
    /// Both must come from beginFrame() or be part of the pair published last (e.g. the previous
    /// pair's next frame as the new current frame). Slots handed out by beginFrame() and not named
    /// here become free again.
    void publish(const DepthSlot &current, const DepthSlot *next) noexcept;
    /// \brief Publishes (\a current, \a next), \a next null when frame i is the last, copying each
    /// frame into a slot once: when \a current is the frame published as next by the previous
    /// publishPair() (the same source pixels, \a current.data, and PTS) its slot becomes the
    /// current one and only \a next is copied. Rows are copied as far as the frame and the handoff
    /// overlap (W samples of the handoff's sample size per row, at the view's stride); the views'
    /// format is not checked. Any other publication (publish(), push(), finish()) or restart() in
    /// between makes the next call copy both frames. Wait-free, no allocation.
    void publishPair(const scene::DepthFrameView &current,
                     const scene::DepthFrameView *next) noexcept;
    /// \brief Copies \a frame into a free slot and publishes (previously pushed frame, \a frame),
    /// or (\a frame, none) for the first frame since create() or restart().
    /// \return Errc::InvalidArgument (nothing published) when the frame is malformed or its size
    /// or sample format differ from the handoff's.
    [[nodiscard]] Result<void> push(const scene::DepthFrameView &frame) noexcept;
    /// \brief End of stream: publishes (last pushed frame, none), so the surface holds still.
    /// No-op before the first push().
    void finish() noexcept;
    /// \brief Forgets the last pushed frame and publishPair()'s next frame (after a seek): the
    /// next push() publishes (frame, none); the next publishPair() copies both of its frames.
    void restart() noexcept;
    /// \brief Sets the clock time at which the media timeline is at PTS 0: the haptic time of an
    /// update at clock time T is T − origin, in seconds. Thread-safe.
    void setMediaOrigin(platform::TimePoint origin) noexcept
    {
        origin_.store(origin.time_since_epoch().count(), std::memory_order_release);
    }
    ///@}

    /// \name Reader (haptic thread)
    ///@{
    /// \brief Takes the newest published pair if it is newer than the one held.
    /// \param[out] out written only when true is returned.
    /// \return true when \a out holds a newer pair (the previously held slots are released);
    /// false when nothing new was published (keep using the pair held).
    bool acquire(DepthPair &out) noexcept;
    /// \return the origin set by setMediaOrigin() (the clock's epoch before). Thread-safe.
    [[nodiscard]] platform::TimePoint mediaOrigin() const noexcept
    {
        return platform::TimePoint(platform::Duration(origin_.load(std::memory_order_acquire)));
    }
    ///@}

    /// \return the number of pairs published so far. Thread-safe.
    [[nodiscard]] std::uint64_t published() const noexcept
    {
        return published_.load(std::memory_order_relaxed);
    }

    ~DepthHandoff() = default;

    /// \return the memory the haptic thread reads: the slots' pixels (kSlots frames back to back),
    /// for RealtimeThreadOptions::regions (the object itself is sizeof(DepthHandoff) at this).
    /// Thread-safe (constant after create()).
    [[nodiscard]] platform::MemoryRegion pixelRegion() const noexcept
    {
        return {storage_.data(), storage_.size()};
    }

private:
    DepthHandoff(int width, int height, scene::SampleFormat format, bool material);
    DT_DISABLE_COPY_AND_MOVE(DepthHandoff)

    [[nodiscard]] DepthSlot slot(int index) noexcept;
    [[nodiscard]] scene::DepthFrameView view(int index) const noexcept;
    /// Writer: copies \a frame into a slot from beginFrame() (see publishPair()).
    [[nodiscard]] DepthSlot copyIn(const scene::DepthFrameView &frame) noexcept;

    const int width_;
    const int height_;
    const scene::SampleFormat format_;
    const std::size_t frameBytes_;
    const std::size_t materialBytes_;   ///< W·H·3 with materials, else 0.
    const std::size_t slotBytes_;       ///< frameBytes_ + materialBytes_.
    std::vector<std::uint8_t> storage_; ///< kSlots slots (depth, then material) back to back.
    double pts_[kSlots] = {};           ///< Written by the writer before publishing the slot.
    bool materialValid_[kSlots] = {};   ///< The slot's material was filled (as pts_).
    std::uint32_t holeBelow_[kSlots] = {}; ///< The slot's hole threshold (as pts_).

    /// Published pair, held pair and the fresh bit (layout in depth_handoff.cpp).
    alignas(platform::kCacheLineBytes) std::atomic<std::uint32_t> state_;
    std::atomic<std::int64_t> origin_{0};
    std::atomic<std::uint64_t> published_{0};
    // Writer-only.
    alignas(platform::kCacheLineBytes) std::uint32_t pendingMask_ = 0; ///< Handed out, unpublished.
    int lastPushed_ = -1;
    int pairNext_ = -1; ///< Slot of publishPair()'s last next frame, or -1 (see publishPair()).
    const std::uint8_t *pairNextSource_ = nullptr; ///< Its source pixels (identity only).
    double pairNextPts_ = 0.0;                     ///< Its PTS, s.
    // Reader-only.
    alignas(platform::kCacheLineBytes) std::uint64_t taken_ = 0;
};

} // namespace depthtouch::haptic_task
