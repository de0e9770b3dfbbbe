#pragma once
/// \file
/// \brief When an adaptive (HLS multivariant) input changes rendition: the network's throughput
/// as the demuxer meets it, and the rung of the ladder it can carry. Pure logic, no libav: the
/// switch itself is rendition_switch.h's.
///
/// The throughput is the bytes of the packets read over the time spent waiting for them in
/// av_read_frame(), within the last kFastWindow and within the last kSlowWindow seconds of wall
/// time (buckets of kBucket seconds); the lower of the two counts: a fall is seen within about a
/// second, a rise only once it lasts (the two windows of hls.js's and Shaka Player's estimators,
/// as sums rather than averages of rates). Within a window, the newest reads that waited
/// kRecentWaiting seconds together count alone when that waiting filled at least kBusyShare of
/// the wall time they span (the reader was held by the link): a fast past neither outweighs a
/// slow present nor, while the estimate falls, decides a change down to a rendition the link
/// cannot carry either. A window that waited less than kAmpleShare of its length did not meet the
/// network's limit: its rate is unbounded (a fast link, a paused or full player), and the tallest
/// rung stays. Before kFastWindow has passed the estimate is unknown.
///
/// The rule (RenditionPolicy::choose()): down as soon as the throughput is below the playing
/// rung's BANDWIDTH, to the tallest rung whose BANDWIDTH is at most kDownShare of it (the
/// shortest when none is); up only kUpHoldSeconds after the last switch, to the tallest rung
/// whose BANDWIDTH is at most kUpShare of it. kUpShare < kDownShare, so a rung chosen on the way
/// down is not left upward at the same throughput (no flapping). Packet bytes leave out the
/// MPEG-TS overhead that BANDWIDTH counts, which errs towards the lower rung.
/// Thread-safety: none (one media source's reading thread).

#include <cstddef>
#include <vector>

namespace depthtouch::drivers::ffmpeg {

/// \brief The network's throughput, bits/s, from (bytes, seconds waited, when) readings.
class ThroughputEstimate {
public:
    static constexpr double kBucket = 0.1;     ///< Seconds of wall time.
    static constexpr double kFastWindow = 2.0; ///< Seconds of wall time.
    static constexpr double kSlowWindow = 8.0;
    static constexpr double kAmpleShare = 0.05;
    static constexpr double kRecentWaiting = 1.0; ///< Seconds.
    static constexpr double kBusyShare = 0.5;
    /// What bitsPerSecond() returns for a window that did not meet the limit.
    static constexpr double kUnbounded = 1e15;

    /// \brief Adds one read: \a bytes delivered after waiting \a waited seconds (>= 0), ending
    /// at \a now (seconds, a steady clock; not decreasing).
    /// \return whether a bucket closed (the estimate may have changed).
    bool add(std::size_t bytes, double waited, double now) noexcept;
    /// \return the lower rate of the two windows, bits/s (kUnbounded when both are ample); 0
    /// while unknown.
    [[nodiscard]] double bitsPerSecond() const noexcept;

private:
    static constexpr int kBuckets = 80; ///< kSlowWindow / kBucket
    struct Bucket {
        double bytes = 0.0;
        double waited = 0.0;
    };
    [[nodiscard]] double rate(int buckets) const noexcept;

    Bucket ring_[kBuckets]{};
    long long bucket_ = -1; ///< The open bucket's number (now / kBucket); -1 before any.
    long long first_ = -1;  ///< The first bucket's number.
};

/// \brief One rung of the ladder: its BANDWIDTH (bits/s, 0 when the playlist gives none), and
/// whether the playing streams' decoders decode it (rendition_match.h): a rung that is not
/// usable is never chosen.
struct Rung {
    long long bitRate = 0;
    bool usable = true;
};

/// \brief The switching rule above.
struct RenditionPolicy {
    static constexpr double kDownShare = 0.8;
    static constexpr double kUpShare = 0.7;
    static constexpr double kUpHoldSeconds = 10.0;

    /// \param rungs the ladder, any order; \a current an index into it.
    /// \param throughput bits/s (ThroughputEstimate::bitsPerSecond(); 0: unknown, no change).
    /// \param sinceSwitch seconds since the last switch (or the start).
    /// \return the rung to play, a usable one (or \a current): \a current when nothing calls for
    /// a change. A ladder whose rungs give no BANDWIDTH never changes.
    static std::size_t choose(const std::vector<Rung> &rungs, std::size_t current,
                              double throughput, double sinceSwitch) noexcept;
};

} // namespace depthtouch::drivers::ffmpeg
