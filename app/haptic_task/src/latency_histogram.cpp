#include "depthtouch/haptic_task/latency_histogram.h"

#include <algorithm>
#include <cmath>

namespace depthtouch::haptic_task {

std::size_t LatencyHistogram::binOf(std::int64_t ns) noexcept
{
    if (ns < 0)
        ns = 0;
    if (ns < kFineLimitNs)
        return static_cast<std::size_t>(ns / kFineBinNs);
    if (ns < kCoarseLimitNs)
        return kFineBins + static_cast<std::size_t>((ns - kFineLimitNs) / kCoarseBinNs);
    return kBins - 1;
}

std::int64_t LatencyHistogram::binLowerNs(std::size_t i) noexcept
{
    if (i < kFineBins)
        return static_cast<std::int64_t>(i) * kFineBinNs;
    if (i < kFineBins + kCoarseBins)
        return kFineLimitNs + static_cast<std::int64_t>(i - kFineBins) * kCoarseBinNs;
    return kCoarseLimitNs;
}

double LatencyHistogram::binCentreNs(std::size_t i) noexcept
{
    if (i < kFineBins)
        return static_cast<double>(binLowerNs(i)) + 0.5 * kFineBinNs;
    if (i < kFineBins + kCoarseBins)
        return static_cast<double>(binLowerNs(i)) + 0.5 * kCoarseBinNs;
    return static_cast<double>(kCoarseLimitNs);
}

void LatencyHistogram::add(std::int64_t ns) noexcept
{
    const std::int64_t v = std::max<std::int64_t>(ns, 0);
    ++bins_[binOf(v)];
    ++count_;
    max_ = std::max(max_, v);
    sum_ += static_cast<long double>(v);
}

void LatencyHistogram::clear() noexcept
{
    bins_.fill(0);
    count_ = 0;
    max_ = 0;
    sum_ = 0.0L;
}

void LatencyHistogram::merge(const LatencyHistogram &other) noexcept
{
    for (std::size_t i = 0; i < kBins; ++i)
        bins_[i] += other.bins_[i];
    count_ += other.count_;
    max_ = std::max(max_, other.max_);
    sum_ += other.sum_;
}

double LatencyHistogram::percentileNs(double p) const noexcept
{
    if (count_ == 0)
        return 0.0;
    const double clamped = std::clamp(p, 0.0, 100.0);
    // Rank of the wanted value, 1-based: at least this many values are at or below it.
    auto rank =
        static_cast<std::uint64_t>(std::ceil(clamped / 100.0 * static_cast<double>(count_)));
    rank = std::clamp<std::uint64_t>(rank, 1, count_);
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
        seen += bins_[i];
        if (seen >= rank)
            return std::min(binCentreNs(i), static_cast<double>(max_));
    }
    return static_cast<double>(max_);
}

double LatencyHistogram::meanNs() const noexcept
{
    return count_ == 0 ? 0.0 : static_cast<double>(sum_ / static_cast<long double>(count_));
}

LatencySummary LatencyHistogram::summary() const noexcept
{
    LatencySummary s;
    s.count = count_;
    s.p50Us = percentileNs(50.0) * 1e-3;
    s.p90Us = percentileNs(90.0) * 1e-3;
    s.p99Us = percentileNs(99.0) * 1e-3;
    s.p999Us = percentileNs(99.9) * 1e-3;
    s.maxUs = static_cast<double>(max_) * 1e-3;
    s.meanUs = meanNs() * 1e-3;
    return s;
}

} // namespace depthtouch::haptic_task
