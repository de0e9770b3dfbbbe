#include "depthtouch/haptic_task/depth_handoff.h"

#include <algorithm>
#include <cstring>
#include <new>

#include "depthtouch/platform/assert.h"

namespace depthtouch::haptic_task {

namespace {

// state_ layout: 4 bits per slot index, kNone when there is none.
constexpr std::uint32_t kNone = 0xF;
constexpr std::uint32_t kPubCurShift = 0;
constexpr std::uint32_t kPubNextShift = 4;
constexpr std::uint32_t kHeldCurShift = 8;
constexpr std::uint32_t kHeldNextShift = 12;
constexpr std::uint32_t kFresh = 1u << 16;
constexpr std::uint32_t kPubMask = 0xFFu;
constexpr std::uint32_t kHeldMask = 0xFF00u;
constexpr std::uint32_t kInitialState = (kNone << kPubCurShift) | (kNone << kPubNextShift) |
                                        (kNone << kHeldCurShift) | (kNone << kHeldNextShift);

constexpr std::uint32_t field(std::uint32_t state, std::uint32_t shift) noexcept
{
    return (state >> shift) & 0xFu;
}

/// Bit mask of the slots named in the 4-bit field at \a shift.
constexpr std::uint32_t bitOf(std::uint32_t state, std::uint32_t shift) noexcept
{
    const std::uint32_t index = field(state, shift);
    return index == kNone ? 0u : 1u << index;
}

static_assert(DepthHandoff::kSlots < static_cast<int>(kNone), "slot indices must fit in 4 bits");

} // namespace

Result<std::unique_ptr<DepthHandoff>>
DepthHandoff::create(int width, int height, scene::SampleFormat format, bool material)
{
    if (width < 2 || height < 2 || width > 16384 || height > 16384)
        return unexpected(Errc::InvalidArgument,
                          "Depth handoff frames must be 2x2 to 16384x16384 samples");
    try {
        return std::unique_ptr<DepthHandoff>(new DepthHandoff(width, height, format, material));
    } catch (const std::bad_alloc &) {
        return unexpected(Errc::OutOfResources, "Not enough memory for the depth handoff frames");
    }
}

DepthHandoff::DepthHandoff(int width, int height, scene::SampleFormat format, bool material)
    : width_(width), height_(height), format_(format),
      frameBytes_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                  scene::bytesPerSample(format)),
      materialBytes_(
          material ? static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3 : 0),
      slotBytes_(frameBytes_ + materialBytes_), storage_(slotBytes_ * kSlots, 0),
      state_(kInitialState)
{
}

DepthSlot DepthHandoff::slot(int index) noexcept
{
    DepthSlot s;
    s.data = storage_.data() + static_cast<std::size_t>(index) * slotBytes_;
    s.bytes = frameBytes_;
    s.pts = pts_[index];
    s.holeBelow = holeBelow_[index];
    s.index = index;
    if (materialBytes_ > 0) {
        s.material = s.data + frameBytes_;
        s.hasMaterial = materialValid_[index];
    }
    return s;
}

scene::DepthFrameView DepthHandoff::view(int index) const noexcept
{
    scene::DepthFrameView v;
    v.data = storage_.data() + static_cast<std::size_t>(index) * slotBytes_;
    v.width = width_;
    v.height = height_;
    v.strideBytes = static_cast<std::size_t>(width_) * scene::bytesPerSample(format_);
    v.format = format_;
    v.pts = pts_[index];
    v.holeBelow = holeBelow_[index];
    if (materialBytes_ > 0 && materialValid_[index])
        v.material = {v.data + frameBytes_, static_cast<std::size_t>(width_) * 3};
    return v;
}

DepthSlot DepthHandoff::beginFrame() noexcept
{
    // acquire: the reader's last reads of the slots it released happen before our writes.
    const std::uint32_t state = state_.load(std::memory_order_acquire);
    const std::uint32_t used = bitOf(state, kPubCurShift) | bitOf(state, kPubNextShift) |
                               bitOf(state, kHeldCurShift) | bitOf(state, kHeldNextShift) |
                               pendingMask_;
    for (int i = 0; i < kSlots; ++i) {
        if ((used & (1u << i)) == 0) {
            pendingMask_ |= 1u << i;
            DepthSlot s = slot(i);
            s.hasMaterial = false; // until the writer fills it
            s.holeBelow = 0;
            return s;
        }
    }
    DT_ASSERT(false && "DepthHandoff::beginFrame() called more than twice without publish()");
    return slot(0);
}

void DepthHandoff::publish(const DepthSlot &current, const DepthSlot *next) noexcept
{
    DT_ASSERT(current.index >= 0 && current.index < kSlots);
    DT_ASSERT(next == nullptr || (next->index >= 0 && next->index < kSlots));
    // Only slots still being filled get their PTS: a slot already published may be read right now.
    if ((pendingMask_ & (1u << current.index)) != 0) {
        pts_[current.index] = current.pts;
        holeBelow_[current.index] = current.holeBelow;
        materialValid_[current.index] = current.hasMaterial && materialBytes_ > 0;
    }
    if (next != nullptr && (pendingMask_ & (1u << next->index)) != 0) {
        pts_[next->index] = next->pts;
        holeBelow_[next->index] = next->holeBelow;
        materialValid_[next->index] = next->hasMaterial && materialBytes_ > 0;
    }
    const std::uint32_t pub =
        (static_cast<std::uint32_t>(current.index) << kPubCurShift) |
        ((next != nullptr ? static_cast<std::uint32_t>(next->index) : kNone) << kPubNextShift);
    std::uint32_t state = state_.load(std::memory_order_relaxed);
    // release: the slot contents and PTS are visible to the reader that takes this pair. Retries
    // only when the reader took the previous pair meanwhile.
    while (!state_.compare_exchange_weak(state, (state & kHeldMask) | pub | kFresh,
                                         std::memory_order_acq_rel, std::memory_order_relaxed)) {
    }
    pendingMask_ = 0;
    pairNext_ = -1;
    published_.fetch_add(1, std::memory_order_relaxed);
}

DepthSlot DepthHandoff::copyIn(const scene::DepthFrameView &frame) noexcept
{
    DepthSlot s = beginFrame();
    const std::size_t bytesPerSample = scene::bytesPerSample(format_);
    const std::size_t rowBytes = static_cast<std::size_t>(width_) * bytesPerSample;
    const int rows = std::min(height_, frame.height);
    const std::size_t copyBytes =
        std::min(rowBytes, static_cast<std::size_t>(frame.width) * bytesPerSample);
    for (int y = 0; y < rows; ++y)
        std::memcpy(s.data + static_cast<std::size_t>(y) * rowBytes,
                    frame.data + static_cast<std::size_t>(y) * frame.strideBytes, copyBytes);
    s.pts = frame.pts;
    s.holeBelow = frame.holeBelow;
    s.hasMaterial = s.material != nullptr && frame.material.present();
    if (s.hasMaterial) {
        const std::size_t materialRow = static_cast<std::size_t>(width_) * 3;
        const std::size_t materialCopy =
            std::min(materialRow, static_cast<std::size_t>(frame.width) * 3);
        for (int y = 0; y < rows; ++y)
            std::memcpy(s.material + static_cast<std::size_t>(y) * materialRow,
                        frame.material.data +
                            static_cast<std::size_t>(y) * frame.material.strideBytes,
                        materialCopy);
    }
    return s;
}

void DepthHandoff::publishPair(const scene::DepthFrameView &current,
                               const scene::DepthFrameView *next) noexcept
{
    // The previous pair's next frame is on screen now: its slot already holds it.
    const bool held =
        pairNext_ >= 0 && current.data == pairNextSource_ && current.pts == pairNextPts_;
    const DepthSlot cur = held ? slot(pairNext_) : copyIn(current);
    if (next == nullptr) {
        publish(cur, nullptr);
        return;
    }
    const DepthSlot nxt = copyIn(*next);
    publish(cur, &nxt);
    pairNext_ = nxt.index;
    pairNextSource_ = next->data;
    pairNextPts_ = next->pts;
}

Result<void> DepthHandoff::push(const scene::DepthFrameView &frame) noexcept
{
    DT_TRY(frame.validate());
    if (frame.width != width_ || frame.height != height_ || frame.format != format_)
        return unexpected(Errc::InvalidArgument,
                          "Depth frame size or sample format differs from the handoff's");
    const DepthSlot s = copyIn(frame);
    if (lastPushed_ >= 0) {
        const DepthSlot previous = slot(lastPushed_);
        publish(previous, &s);
    } else {
        publish(s, nullptr);
    }
    lastPushed_ = s.index;
    return ok();
}

void DepthHandoff::finish() noexcept
{
    if (lastPushed_ >= 0)
        publish(slot(lastPushed_), nullptr);
}

void DepthHandoff::restart() noexcept
{
    lastPushed_ = -1;
    pairNext_ = -1;
}

bool DepthHandoff::acquire(DepthPair &out) noexcept
{
    std::uint32_t state = state_.load(std::memory_order_acquire);
    for (;;) {
        if ((state & kFresh) == 0)
            return false;
        const std::uint32_t held = (field(state, kPubCurShift) << kHeldCurShift) |
                                   (field(state, kPubNextShift) << kHeldNextShift);
        // acq_rel: acquire the published contents; release our reads of the slots we give back.
        if (state_.compare_exchange_weak(state, (state & kPubMask) | held,
                                         std::memory_order_acq_rel, std::memory_order_acquire))
            break;
    }
    const std::uint32_t cur = field(state, kPubCurShift);
    const std::uint32_t next = field(state, kPubNextShift);
    out.current = view(static_cast<int>(cur));
    out.hasNext = next != kNone;
    out.next = out.hasNext ? view(static_cast<int>(next)) : scene::DepthFrameView{};
    out.sequence = ++taken_;
    return true;
}

} // namespace depthtouch::haptic_task
