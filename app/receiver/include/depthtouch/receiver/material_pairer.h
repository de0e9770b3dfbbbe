#pragma once
/// \file
/// \brief MaterialPairer: finds the material frame (scene/material.h: per-pixel haptic material on
/// the depth grid) of each depth frame by presentation time (docs/architecture.md §4).
///
/// Pure logic on (PTS, payload) items, like PtsPairer: the receiver feeds it the decoded frames of
/// the material track and asks for the material of the depth frames i and i+1 of each paired
/// frame. No I/O, no clock.
///
/// Rules (tolerance τ: the pairing tolerance, half the color frame period):
/// - The material of a depth frame at PTS t is the material frame nearest to t within
///   [t − τ, t + τ] (Match::Same); else the newest material frame before t − τ, which holds until
///   the next one (Match::Held: a still material, one frame at the first PTS, holds for the whole
///   video); else none (Match::Missing).
/// - ready(t): the answer for t is final: a material frame at or after t − τ has arrived, or the
///   material stream has ended (endOfStream()). The receiver holds a paired frame back until both
///   of its depth frames are ready, or decides early when the material lags (bounded waiting).
/// - Timestamps: a missing PTS becomes previous + period (ptsMissing); a frame whose PTS is not
///   after the previous one is refused (ptsDuplicates, ptsNonMonotonic).
/// - Bounded memory: at most `window` + 3 frames are kept; release(t) drops the frames no depth
///   frame at or after t can use, and a push() into a full queue drops the oldest frame.
/// - reset(position) (a seek) keeps the newest frame at or before \a position as a carried frame,
///   so that a still material holds after a seek forward (the demuxer does not read its packet
///   again); any frame decoded after the seek replaces it when it is not after it.
///
/// Memory: the queue is allocated by the constructor; push(), find() and release() never allocate
/// (when the payload's move and copy do not). Thread-safety: thread-bound.

#include <cstdint>
#include <utility>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/assert.h"
#include "depthtouch/receiver/pts_pairer.h" // sharePayload(const int &)

namespace depthtouch::receiver {

/// Timestamp counters of the material track since construction (reset() keeps them).
struct MaterialPairerStats {
    std::uint64_t ptsMissing = 0;      ///< Frames without PTS (given previous + period).
    std::uint64_t ptsDuplicates = 0;   ///< Frames refused: same PTS as the previous one.
    std::uint64_t ptsNonMonotonic = 0; ///< Frames refused: PTS before the previous one.
    std::uint64_t dropped = 0;         ///< Frames dropped unused from a full queue.
};

/// \tparam P payload: movable; `P sharePayload(const P &)` (found by ADL or in this namespace)
/// makes another reference for find().
template <class P> class MaterialPairer {
public:
    /// How find() chose the material of a depth frame.
    enum class Match : std::uint8_t {
        Same,   ///< A material frame within τ of the depth frame.
        Held,   ///< An older material frame (the newest one before t − τ) holds.
        Missing ///< No material frame at or before the depth frame.
    };

    /// \param window frames the material may run ahead of the depth (≥ 1).
    /// \param tolerance τ (ns, > 0). \param period assumed frame period for a missing PTS (ns).
    MaterialPairer(int window, hal::Pts tolerance, hal::Pts period)
        : tolerance_(tolerance > hal::Pts{0} ? tolerance : hal::Pts(1)), period_(period)
    {
        DT_ASSERT(window >= 1);
        slots_.resize(static_cast<std::size_t>(window) + 3);
    }

    [[nodiscard]] const MaterialPairerStats &stats() const noexcept { return stats_; }
    /// \return the frames kept now.
    [[nodiscard]] std::size_t size() const noexcept { return count_; }

    /// \brief Offers the next decoded material frame (decode order = presentation order).
    /// \return true when taken; false when refused for its PTS (the payload is left as is).
    bool push(hal::Pts pts, P &&payload)
    {
        if (pts == hal::kNoPts) {
            pts = last_ == hal::kNoPts ? hal::Pts{0} : last_ + period_;
            ++stats_.ptsMissing;
        }
        while (count_ > 0 && back().carried && back().pts >= pts)
            popBack(); // a frame carried over a seek gives way to the frames read after it
        if (last_ != hal::kNoPts) {
            if (pts == last_) {
                ++stats_.ptsDuplicates;
                return false;
            }
            if (pts < last_) {
                ++stats_.ptsNonMonotonic;
                return false;
            }
        }
        if (count_ == slots_.size()) {
            popFront();
            ++stats_.dropped;
        }
        slots_[(head_ + count_) % slots_.size()] = Slot{pts, std::move(payload), false};
        ++count_;
        last_ = pts;
        return true;
    }

    /// Marks the end of the material stream: every depth frame is ready.
    void endOfStream() noexcept { ended_ = true; }
    [[nodiscard]] bool ended() const noexcept { return ended_; }
    /// Undoes endOfStream(): material frames come again.
    void resume() noexcept { ended_ = false; }

    /// \return whether find(\a t) is final (see the file comment).
    [[nodiscard]] bool ready(hal::Pts t) const noexcept
    {
        return ended_ || (count_ > 0 && back().pts >= t - tolerance_);
    }

    /// \brief The material of the depth frame at \a t with what has arrived.
    /// \param[out] out Another reference to the chosen frame's payload (untouched when Missing).
    /// \param[out] pts The chosen frame's PTS (untouched when Missing).
    Match find(hal::Pts t, P &out, hal::Pts &pts) const
    {
        const Slot *best = nullptr;
        const Slot *before = nullptr;
        for (std::size_t i = 0; i < count_; ++i) {
            const Slot &s = at(i);
            const hal::Pts d = s.pts > t ? s.pts - t : t - s.pts;
            if (d <= tolerance_) {
                if (best == nullptr || d < (best->pts > t ? best->pts - t : t - best->pts))
                    best = &s;
            } else if (s.pts < t) {
                before = &s;
            }
        }
        const Slot *chosen = best != nullptr ? best : before;
        if (chosen == nullptr)
            return Match::Missing;
        out = sharePayload(chosen->payload);
        pts = chosen->pts;
        return best != nullptr ? Match::Same : Match::Held;
    }

    /// Drops the frames no depth frame at or after \a t can use (the oldest frame that may still
    /// hold is kept).
    void release(hal::Pts t)
    {
        while (count_ >= 2 && at(0).pts < t - tolerance_ && at(1).pts <= t + tolerance_)
            popFront();
    }

    /// \brief After a seek to \a position: keeps the newest frame at or before \a position (as a
    /// carried frame), drops the others, and forgets the end of stream and the PTS history.
    void reset(hal::Pts position)
    {
        while (count_ > 0 && back().pts > position)
            popBack();
        while (count_ > 1)
            popFront();
        if (count_ > 0)
            at(0).carried = true;
        ended_ = false;
        last_ = hal::kNoPts; // the carried frame is ordered by push() itself
    }

private:
    struct Slot {
        hal::Pts pts = hal::kNoPts;
        P payload{};
        bool carried = false; ///< Kept over a seek.
    };

    Slot &at(std::size_t i) noexcept { return slots_[(head_ + i) % slots_.size()]; }
    const Slot &at(std::size_t i) const noexcept { return slots_[(head_ + i) % slots_.size()]; }
    const Slot &back() const noexcept { return at(count_ - 1); }
    void popFront()
    {
        slots_[head_] = Slot{};
        head_ = (head_ + 1) % slots_.size();
        --count_;
    }
    void popBack()
    {
        at(count_ - 1) = Slot{};
        --count_;
    }

    hal::Pts tolerance_;
    hal::Pts period_;
    std::vector<Slot> slots_;
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    hal::Pts last_ = hal::kNoPts;
    bool ended_ = false;
    MaterialPairerStats stats_;
};

} // namespace depthtouch::receiver
