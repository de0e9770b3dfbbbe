/// \file
/// \brief The throughput estimate and the switching rule (see rendition_policy.h).

#include "rendition_policy.h"

#include <algorithm>
#include <cmath>

namespace depthtouch::drivers::ffmpeg {

namespace {

/// \return the tallest (highest BANDWIDTH) usable rung at most \a limit bits/s, or -1.
long tallestWithin(const std::vector<Rung> &rungs, double limit) noexcept
{
    long best = -1;
    for (std::size_t i = 0; i < rungs.size(); ++i) {
        const auto rate = static_cast<double>(rungs[i].bitRate);
        if (rungs[i].usable && rungs[i].bitRate > 0 && rate <= limit &&
            (best < 0 || rungs[i].bitRate > rungs[static_cast<std::size_t>(best)].bitRate))
            best = static_cast<long>(i);
    }
    return best;
}

} // namespace

bool ThroughputEstimate::add(std::size_t bytes, double waited, double now) noexcept
{
    const auto n = static_cast<long long>(std::floor(std::max(now, 0.0) / kBucket));
    bool closed = false;
    if (bucket_ < 0) {
        bucket_ = first_ = n;
    } else if (n > bucket_) { // empty the buckets passed over (at most the whole ring)
        for (long long b = bucket_ + 1; b <= std::min(n, bucket_ + kBuckets); ++b)
            ring_[b % kBuckets] = Bucket{};
        bucket_ = n;
        closed = true;
    }
    Bucket &open = ring_[bucket_ % kBuckets];
    open.bytes += static_cast<double>(bytes);
    open.waited += std::max(waited, 0.0);
    return closed;
}

double ThroughputEstimate::rate(int buckets) const noexcept
{
    double bytes = 0.0, waited = 0.0, recentBytes = 0.0, recentWaited = 0.0;
    int span = 0; // buckets back to where the newest reads had waited kRecentWaiting together
    for (int k = 0; k < buckets; ++k) {
        const Bucket &b = ring_[(bucket_ - k + kBuckets) % kBuckets];
        bytes += b.bytes;
        waited += b.waited;
        if (recentWaited < kRecentWaiting) {
            recentBytes += b.bytes;
            recentWaited += b.waited;
            span = k + 1;
        }
    }
    if (waited < kAmpleShare * buckets * kBucket)
        return kUnbounded;
    // The newest waiting counts once it filled at least kBusyShare of its own span: a span that
    // reaches back into a time of reading without waiting mixes a fast past into it.
    if (recentWaited >= kRecentWaiting && recentWaited >= kBusyShare * span * kBucket)
        return 8.0 * recentBytes / recentWaited;
    return 8.0 * bytes / waited;
}

double ThroughputEstimate::bitsPerSecond() const noexcept
{
    const auto fast = static_cast<int>(std::lround(kFastWindow / kBucket));
    if (bucket_ < 0 || bucket_ - first_ < fast)
        return 0.0;
    return std::min(rate(fast), rate(kBuckets));
}

std::size_t RenditionPolicy::choose(const std::vector<Rung> &rungs, std::size_t current,
                                    double throughput, double sinceSwitch) noexcept
{
    if (current >= rungs.size() || throughput <= 0.0 || rungs[current].bitRate <= 0)
        return current;
    const auto playing = static_cast<double>(rungs[current].bitRate);
    if (throughput < playing) {
        long down = tallestWithin(rungs, kDownShare * throughput);
        if (down < 0) // none fits: the shortest usable one
            for (std::size_t i = 0; i < rungs.size(); ++i)
                if (rungs[i].usable && rungs[i].bitRate > 0 &&
                    (down < 0 || rungs[i].bitRate < rungs[static_cast<std::size_t>(down)].bitRate))
                    down = static_cast<long>(i);
        return down < 0 ? current : static_cast<std::size_t>(down);
    }
    if (sinceSwitch < kUpHoldSeconds)
        return current;
    const long up = tallestWithin(rungs, kUpShare * throughput);
    if (up >= 0 && rungs[static_cast<std::size_t>(up)].bitRate > rungs[current].bitRate)
        return static_cast<std::size_t>(up);
    return current;
}

} // namespace depthtouch::drivers::ffmpeg
