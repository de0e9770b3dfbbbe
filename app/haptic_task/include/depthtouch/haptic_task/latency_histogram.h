#pragma once
/// \file
/// \brief LatencyHistogram: a fixed-size histogram of durations (wake latency, update time, period
/// error) with percentiles, for the haptic telemetry and `depthtouch bench rt`.
///
/// Thread-safety: thread-bound (one thread records and reads; copy it to hand it over). add() is
/// real-time safe: no allocation (the bins are inside the object), no lock.

#include <array>
#include <cstddef>
#include <cstdint>

namespace depthtouch::haptic_task {

/// \brief Percentiles of a LatencyHistogram in microseconds.
struct LatencySummary {
    std::uint64_t count = 0;
    double p50Us = 0.0;
    double p90Us = 0.0;
    double p99Us = 0.0;
    double p999Us = 0.0;
    double maxUs = 0.0; ///< Exact largest value recorded.
    double meanUs = 0.0;
};

/// \brief Counts of durations in nanoseconds, in fixed bins: 0.5 µs wide up to 2 ms, 50 µs wide
/// up to 100 ms, then one overflow bin. Negative values count as 0. Percentiles are read at the
/// bin centre (so within ±0.25 µs below 2 ms); the maximum and the mean are exact.
class LatencyHistogram {
public:
    static constexpr std::int64_t kFineBinNs = 500;
    static constexpr std::int64_t kFineLimitNs = 2'000'000;
    static constexpr std::int64_t kCoarseBinNs = 50'000;
    static constexpr std::int64_t kCoarseLimitNs = 100'000'000;
    static constexpr std::size_t kFineBins = kFineLimitNs / kFineBinNs;
    static constexpr std::size_t kCoarseBins = (kCoarseLimitNs - kFineLimitNs) / kCoarseBinNs;
    static constexpr std::size_t kBins = kFineBins + kCoarseBins + 1;

    /// Records one duration of \a ns nanoseconds.
    void add(std::int64_t ns) noexcept;
    /// Forgets everything.
    void clear() noexcept;
    /// Adds the counts of \a other.
    void merge(const LatencyHistogram &other) noexcept;

    [[nodiscard]] std::uint64_t count() const noexcept { return count_; }
    /// \return the smallest value v (ns, bin centre) such that at least \a p percent of the
    /// recorded values are ≤ v; 0 when empty. \a p in [0, 100].
    [[nodiscard]] double percentileNs(double p) const noexcept;
    [[nodiscard]] std::int64_t maxNs() const noexcept { return max_; }
    [[nodiscard]] double meanNs() const noexcept;
    /// \return p50, p90, p99, p99.9, max and mean in microseconds.
    [[nodiscard]] LatencySummary summary() const noexcept;

    /// \return the lower edge of bin \a i, ns (for CDF charts).
    [[nodiscard]] static std::int64_t binLowerNs(std::size_t i) noexcept;
    /// \return the count in bin \a i.
    [[nodiscard]] std::uint64_t binCount(std::size_t i) const noexcept { return bins_[i]; }

private:
    [[nodiscard]] static std::size_t binOf(std::int64_t ns) noexcept;
    [[nodiscard]] static double binCentreNs(std::size_t i) noexcept;

    std::array<std::uint64_t, kBins> bins_{};
    std::uint64_t count_ = 0;
    std::int64_t max_ = 0;
    long double sum_ = 0.0L;
};

} // namespace depthtouch::haptic_task
