#pragma once
/// \file
/// \brief PtsPairer: pairs the color and depth frames of a 3D video by presentation time, keeping
/// the depth frame after the current one buffered (docs/architecture.md §1, §3 "Time"; paper IV.B:
/// the haptic renderer interpolates the surface between depth frames i and i+1, Eq. 1).
///
/// Pure logic on (PTS, payload) items: the receiver feeds it decoded frames (payload: FrameHandle),
/// `depthtouch probe` feeds it packet timestamps (payload: an index). No I/O, no clock.
///
/// Rules (tolerance τ = half the color frame period):
/// - Timeline: one output per color frame, in PTS order. Without a color stream, one output per
///   depth frame; without a depth stream, one output per color frame flagged depthMissing.
/// - Partner: the depth frame nearest to the color PTS t within [t − τ, t + τ] (ties: the earlier).
///   Its successor in the depth stream is the output's depthNext. An output is held back until that
///   successor has arrived or the depth stream has ended.
/// - No depth frame within τ (different frame rates, a gap, a lost frame): the latest depth frame
///   before t is reused (depthDuplicated; depthNext = the first depth frame after t when known);
///   with no earlier depth frame the output has no depth (depthMissing).
/// - Depth frames no color frame chose are dropped and counted (depthUnpaired).
/// - Bounded buffering: when more than `window` color frames wait (depth late, lost or ended), the
///   oldest is decided as if the depth stream had ended (pairingForced); when more than `window`
///   depth frames wait with no color frame, the oldest is dropped as unpaired. Each queue holds at
///   most window + 2 items, so push() after a pull() that returned false always has room.
/// - Timestamps per stream: a missing PTS (kNoPts) becomes previous + period (ptsMissing); a PTS
///   equal to the previous one (ptsDuplicates) or at most τ before it (ptsNonMonotonic) is
///   refused; a step above 1.5 periods is accepted and counted (ptsGaps).
/// - Discontinuities (a broadcast splice, an encoder restart, a looped feed, a 33-bit MPEG-TS
///   wrap the demuxer did not correct): a step back by more than τ, or forward by more than
///   PairerConfig::maxStep, is a jump. Its first frame is refused (ptsNonMonotonic backward,
///   ptsJumps forward), so that a lone stray timestamp changes nothing; when the next frame
///   continues from it (after it, within maxStep) the stream re-bases (ptsDiscontinuities): its
///   frames are offset so that the confirming frame comes one period after the previous one,
///   and Output::discontinuity marks the first output after it. The other stream re-bases at the
///   same splice with the same offset, so the pairs stay aligned. Output PTS are therefore the
///   re-based timeline: increasing over the whole input (cf. ffplay's max_frame_duration, 10 s
///   for AVFMT_TS_DISCONT formats; mpv's "Invalid video timestamp" reset).
///
/// Memory: the queues are allocated by the constructor; push() and pull() never allocate (when the
/// payload's move and copy do not). Thread-safety: thread-bound.

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/assert.h"

namespace depthtouch::receiver {

/// The frame period of a stream whose rate is unknown: 30 fps, ns.
constexpr hal::Pts kDefaultFramePeriod{33'333'333};

/// A PTS step forward beyond which a stream re-bases (PairerConfig::maxStep): 10 s, ns.
constexpr hal::Pts kMaxPtsStep{10'000'000'000};

/// Which streams exist and how they are timed.
struct PairerConfig {
    bool color = true;                          ///< The input has a color stream.
    bool depth = true;                          ///< The input has a depth stream.
    hal::Pts colorPeriod = kDefaultFramePeriod; ///< Color frame period (ns).
    hal::Pts depthPeriod = kDefaultFramePeriod; ///< Depth frame period (ns).
    int window = 8;                             ///< Frames a stream may wait for the other, ≥ 1.
    /// A step forward above this (ns) is a timestamp discontinuity, not a gap (see the file
    /// comment): ffplay's bound for AVFMT_TS_DISCONT formats (MPEG-TS), 10 s.
    hal::Pts maxStep = kMaxPtsStep;

    /// \return the configuration of an input with the streams \a color and \a depth, whose frame
    /// periods (ns) are \a colorPeriod and \a depthPeriod, 0 where a stream gives none: a missing
    /// period is the other stream's, and with neither both are kDefaultFramePeriod.
    static PairerConfig forStreams(bool color, bool depth, hal::Pts colorPeriod,
                                   hal::Pts depthPeriod, int window = 8) noexcept
    {
        if (colorPeriod == hal::Pts{0})
            colorPeriod = depthPeriod != hal::Pts{0} ? depthPeriod : kDefaultFramePeriod;
        if (depthPeriod == hal::Pts{0})
            depthPeriod = colorPeriod;
        return {color, depth, colorPeriod, depthPeriod, window, kMaxPtsStep};
    }
};

/// Counters of the pairing and of the timestamp checks since construction (reset() keeps them).
struct PairerStats {
    std::uint64_t outputs = 0;         ///< Paired frames output.
    std::uint64_t depthMissing = 0;    ///< Outputs of a two-stream input without any depth frame.
    std::uint64_t depthDuplicated = 0; ///< Outputs whose depth frame was reused (no partner in τ).
    std::uint64_t depthUnpaired = 0;   ///< Depth frames no color frame was paired with.
    std::uint64_t pairingForced = 0; ///< Outputs decided early because a stream lagged by > window.
    std::uint64_t ptsMissing = 0;    ///< Items without PTS (given previous + period).
    std::uint64_t ptsDuplicates = 0; ///< Items refused: same PTS as the previous one.
    std::uint64_t ptsNonMonotonic = 0; ///< Items refused: PTS before the previous one.
    std::uint64_t ptsGaps = 0;         ///< Steps of more than 1.5 frame periods.
    std::uint64_t ptsJumps = 0; ///< Items refused: more than maxStep ahead, not (yet) confirmed.
    std::uint64_t ptsDiscontinuities = 0; ///< Re-bases of a stream's timeline (jumps confirmed).
};

enum class PairStream : std::uint8_t { Color = 0, Depth = 1 };

/// How push() took an item.
/// NonMonotonic: before the previous PTS; Jump: more than PairerConfig::maxStep after it (the
/// first frame of a discontinuity, which the next frame confirms).
enum class PushOutcome : std::uint8_t { Accepted, Duplicate, NonMonotonic, Jump };

/// Payload sharing for plain values (packet indices in `depthtouch probe`).
constexpr int sharePayload(const int &v) noexcept
{
    return v;
}

/// \tparam P payload: movable; `P sharePayload(const P &)` (found by ADL or in this namespace)
/// makes the extra reference a depth frame needs when it is both "current" and "next".
template <class P> class PtsPairer {
public:
    /// One frame of one stream.
    struct Item {
        hal::Pts pts = hal::kNoPts;
        bool corrupt = false; ///< Carried to Output::concealed.
        P payload{};
        bool discontinuity = false; ///< Set by push(): the first item after a re-base.
    };

    /// One paired frame. Items that do not exist are left default (hasX false).
    struct Output {
        hal::Pts pts = hal::kNoPts; ///< Color PTS, or depth PTS without a color stream.
        std::uint64_t index = 0;    ///< Outputs before this one since construction or reset().
        bool hasColor = false;
        bool hasDepth = false;
        bool hasNext = false;
        Item color;
        Item depth;     ///< Depth frame i (current).
        Item depthNext; ///< Depth frame i+1.
        bool depthMissing = false;
        bool depthDuplicated = false;
        bool concealed = false; ///< The color or the current depth item was corrupt.
        /// The first output after a timestamp discontinuity (the file comment): the media clock
        /// and the haptic clock restart here, as after a seek.
        bool discontinuity = false;
    };

    explicit PtsPairer(const PairerConfig &cfg)
        : cfg_(cfg), tolerance_((cfg.color ? cfg.colorPeriod : cfg.depthPeriod) / 2)
    {
        DT_ASSERT(cfg.window >= 1 && (cfg.color || cfg.depth));
        const auto cap = static_cast<std::size_t>(cfg.window) + 2;
        queues_[0].init(cap);
        queues_[1].init(cap);
        if (tolerance_ <= hal::Pts{0})
            tolerance_ = hal::Pts(1);
    }

    /// \return the pairing tolerance τ.
    [[nodiscard]] hal::Pts tolerance() const noexcept { return tolerance_; }
    [[nodiscard]] const PairerStats &stats() const noexcept { return stats_; }

    /// \return the frames of \a s waiting to be decided.
    [[nodiscard]] std::size_t waiting(PairStream s) const noexcept { return q(s).size(); }
    /// \return whether push() on \a s has room (always true after pull() returned false).
    [[nodiscard]] bool canPush(PairStream s) const noexcept { return !q(s).full(); }

    /// \brief Offers the next decoded frame of stream \a s (decode order = presentation order).
    /// \return Accepted (the pairer owns the item), or why it refused it (the item is left as is).
    /// \pre canPush(s), and the stream exists in the config.
    PushOutcome push(PairStream s, Item &&item)
    {
        StreamTime &st = time_[idx(s)];
        const hal::Pts period = s == PairStream::Color ? cfg_.colorPeriod : cfg_.depthPeriod;
        if (item.pts == hal::kNoPts) {
            item.pts = st.last == hal::kNoPts ? hal::Pts{0} : st.last + period;
            ++stats_.ptsMissing;
        }
        item.discontinuity = false;
        if (st.last != hal::kNoPts) {
            const hal::Pts step = item.pts - st.last;
            if (step == hal::Pts{0}) {
                ++stats_.ptsDuplicates;
                return PushOutcome::Duplicate;
            }
            if (step < -(period / 2) || step > cfg_.maxStep) {
                if (!confirmsJump(st, item.pts))
                    return refuseJump(st, item.pts, step);
                rebase(st, item.pts, period);
                item.discontinuity = true;
            } else if (step < hal::Pts{0}) {
                ++stats_.ptsNonMonotonic;
                return PushOutcome::NonMonotonic;
            } else if (step > period + period / 2) {
                ++stats_.ptsGaps;
            }
        }
        st.candidate = hal::kNoPts;
        st.last = item.pts;
        item.pts += st.offset;
        DT_ASSERT(!q(s).full());
        q(s).push(Slot{std::move(item), false});
        return PushOutcome::Accepted;
    }

    /// \return the offset (ns) push() adds to the PTS of stream \a s now (0 until a re-base):
    /// its PTS on the timeline of the outputs.
    [[nodiscard]] hal::Pts offset(PairStream s) const noexcept { return time_[idx(s)].offset; }

    /// Marks the end of stream \a s: the waiting frames are decided without it.
    void endOfStream(PairStream s) noexcept { ended_[idx(s)] = true; }
    [[nodiscard]] bool ended(PairStream s) const noexcept { return ended_[idx(s)]; }
    /// Undoes endOfStream(): frames of \a s come again (a stream that only paused).
    void resume(PairStream s) noexcept { ended_[idx(s)] = false; }

    /// \brief Takes the next decided output. \return false when nothing can be decided yet (push
    /// more, or end the streams) or everything has been output.
    bool pull(Output &out)
    {
        if (!cfg_.color)
            return pullDepthOnly(out);
        if (!cfg_.depth)
            return pullColorOnly(out);
        return pullPaired(out);
    }

    /// \return true when both streams ended and every item was output or dropped.
    [[nodiscard]] bool finished() const noexcept
    {
        return (!cfg_.color || (ended_[0] && queues_[0].empty())) &&
               (!cfg_.depth || (ended_[1] && queues_[1].empty()));
    }

    /// Drops every waiting item and the timestamp history (after a seek). Counters stay.
    void reset()
    {
        for (auto &qq : queues_)
            qq.clear();
        prev_ = Item{};
        hasPrev_ = false;
        ended_[0] = ended_[1] = false;
        time_[0] = time_[1] = StreamTime{};
        splice_ = Splice{};
        index_ = 0;
    }

private:
    struct Slot {
        Item item;
        bool used = false; ///< Chosen as the partner of a color frame.
    };
    struct StreamTime {
        hal::Pts last = hal::kNoPts;      ///< Input PTS of the last accepted item.
        hal::Pts offset{0};               ///< Added to the input PTS: the output timeline.
        hal::Pts candidate = hal::kNoPts; ///< Input PTS of a refused jump, waiting for a sequel.
        std::uint32_t epoch = 0;          ///< Re-bases of this stream.
    };
    /// The latest re-base of either stream: the other one re-bases with the same offset.
    struct Splice {
        std::uint32_t epoch = 0;
        hal::Pts offset{0};
    };

    /// \return whether \a pts (input, ns) continues a refused jump of \a st: after it, within
    /// maxStep.
    [[nodiscard]] bool confirmsJump(const StreamTime &st, hal::Pts pts) const noexcept
    {
        return st.candidate != hal::kNoPts && pts > st.candidate &&
               pts - st.candidate <= cfg_.maxStep;
    }

    /// Refuses the item of input PTS \a pts, \a step (ns) after the last, as a jump's first frame.
    PushOutcome refuseJump(StreamTime &st, hal::Pts pts, hal::Pts step) noexcept
    {
        st.candidate = pts;
        if (step < hal::Pts{0}) {
            ++stats_.ptsNonMonotonic;
            return PushOutcome::NonMonotonic;
        }
        ++stats_.ptsJumps;
        return PushOutcome::Jump;
    }

    /// Re-bases \a st so that the item of input PTS \a pts comes one \a period (ns) after the
    /// last one on the output timeline, or takes the offset of the other stream's re-base at the
    /// same splice (an epoch it reached first) when that keeps the stream increasing.
    void rebase(StreamTime &st, hal::Pts pts, hal::Pts period) noexcept
    {
        const hal::Pts lastOut = st.last + st.offset;
        const hal::Pts own = lastOut + period - pts;
        if (splice_.epoch > st.epoch && pts + splice_.offset > lastOut) {
            st.offset = splice_.offset;
            st.epoch = splice_.epoch;
        } else {
            st.offset = own;
            st.epoch = std::max(st.epoch, splice_.epoch) + 1;
            splice_ = Splice{st.epoch, own};
        }
        ++stats_.ptsDiscontinuities;
    }
    /// A ring of Slots with a capacity fixed by init().
    class Queue {
    public:
        void init(std::size_t cap) { slots_.resize(cap); }
        [[nodiscard]] std::size_t size() const noexcept { return count_; }
        [[nodiscard]] bool empty() const noexcept { return count_ == 0; }
        [[nodiscard]] bool full() const noexcept { return count_ == slots_.size(); }
        Slot &operator[](std::size_t i) noexcept { return slots_[(head_ + i) % slots_.size()]; }
        const Slot &operator[](std::size_t i) const noexcept
        {
            return slots_[(head_ + i) % slots_.size()];
        }
        void push(Slot &&s)
        {
            slots_[(head_ + count_) % slots_.size()] = std::move(s);
            ++count_;
        }
        Slot pop()
        {
            Slot s = std::move(slots_[head_]);
            slots_[head_] = Slot{};
            head_ = (head_ + 1) % slots_.size();
            --count_;
            return s;
        }
        void clear()
        {
            while (!empty())
                (void)pop();
            head_ = 0;
        }

    private:
        std::vector<Slot> slots_;
        std::size_t head_ = 0;
        std::size_t count_ = 0;
    };

    static constexpr std::size_t idx(PairStream s) noexcept { return static_cast<std::size_t>(s); }
    Queue &q(PairStream s) noexcept { return queues_[idx(s)]; }
    const Queue &q(PairStream s) const noexcept { return queues_[idx(s)]; }

    static Item shareItem(const Item &i)
    {
        Item c;
        c.pts = i.pts;
        c.corrupt = i.corrupt;
        c.payload = sharePayload(i.payload);
        return c;
    }

    /// Removes the oldest depth frame; it becomes the "previous" depth frame.
    void retireDepth()
    {
        Slot s = q(PairStream::Depth).pop();
        if (!s.used)
            ++stats_.depthUnpaired;
        prev_ = std::move(s.item);
        hasPrev_ = true;
    }

    void begin(Output &out, hal::Pts pts)
    {
        out = Output{};
        out.pts = pts;
        out.index = index_++;
        ++stats_.outputs;
    }

    /// Pops the head of \a from and begins \a out at its PTS, concealed when the item is corrupt.
    /// \return the popped slot, whose item the caller places in \a out.
    Slot beginWithHead(Queue &from, Output &out)
    {
        Slot s = from.pop();
        begin(out, s.item.pts);
        out.concealed = s.item.corrupt;
        out.discontinuity = s.item.discontinuity;
        return s;
    }

    bool pullColorOnly(Output &out)
    {
        Queue &c = q(PairStream::Color);
        if (c.empty())
            return false;
        Slot s = beginWithHead(c, out);
        out.color = std::move(s.item);
        out.hasColor = true;
        out.depthMissing = true;
        return true;
    }

    bool pullDepthOnly(Output &out)
    {
        Queue &d = q(PairStream::Depth);
        if (d.empty() || (d.size() < 2 && !ended_[1]))
            return false;
        Slot s = beginWithHead(d, out);
        out.depth = std::move(s.item);
        out.hasDepth = true;
        if (!d.empty()) {
            out.depthNext = shareItem(d[0].item);
            out.hasNext = true;
        }
        return true;
    }

    static hal::Pts distance(hal::Pts a, hal::Pts b) noexcept { return a > b ? a - b : b - a; }

    bool pullPaired(Output &out)
    {
        Queue &c = q(PairStream::Color);
        Queue &d = q(PairStream::Depth);
        if (c.empty()) {
            // Color lags or has ended: bound what waits for it.
            const std::size_t keep = ended_[0] ? 0 : static_cast<std::size_t>(cfg_.window);
            while (d.size() > keep)
                retireDepth();
            return false;
        }
        const hal::Pts t = c[0].item.pts;
        const bool forced = c.size() > static_cast<std::size_t>(cfg_.window);
        const bool depthDone = ended_[1] || forced;
        while (!d.empty() && d[0].item.pts < t - tolerance_)
            retireDepth();
        if (!d.empty() && d[0].item.pts <= t + tolerance_) {
            while (d.size() >= 2 && d[1].item.pts <= t + tolerance_ &&
                   distance(d[1].item.pts, t) < distance(d[0].item.pts, t))
                retireDepth();
            if (d.size() < 2 && !depthDone)
                return false; // wait for depth frame i+1
            if (forced && d.size() < 2 && !ended_[1])
                ++stats_.pairingForced;
            Slot cs = c.pop();
            begin(out, t);
            out.discontinuity = cs.item.discontinuity;
            d[0].used = true;
            out.depth = shareItem(d[0].item);
            out.hasDepth = true;
            if (d.size() >= 2) {
                out.depthNext = shareItem(d[1].item);
                out.hasNext = true;
            }
            out.concealed = cs.item.corrupt || out.depth.corrupt;
            out.color = std::move(cs.item);
            out.hasColor = true;
            return true;
        }
        if (d.empty() && !depthDone)
            return false; // the partner may still come
        if (forced && d.empty() && !ended_[1])
            ++stats_.pairingForced;
        Slot cs = c.pop();
        begin(out, t);
        out.discontinuity = cs.item.discontinuity;
        if (hasPrev_) {
            out.depth = shareItem(prev_);
            out.hasDepth = true;
            out.depthDuplicated = true;
            ++stats_.depthDuplicated;
            if (!d.empty()) {
                out.depthNext = shareItem(d[0].item);
                out.hasNext = true;
            }
        } else {
            out.depthMissing = true;
            ++stats_.depthMissing;
        }
        out.concealed = cs.item.corrupt || (out.hasDepth && out.depth.corrupt);
        out.color = std::move(cs.item);
        out.hasColor = true;
        return true;
    }

    const PairerConfig cfg_;
    hal::Pts tolerance_;
    Queue queues_[2];
    StreamTime time_[2];
    Splice splice_;
    bool ended_[2] = {false, false};
    Item prev_;
    bool hasPrev_ = false;
    std::uint64_t index_ = 0;
    PairerStats stats_;
};

} // namespace depthtouch::receiver
