#pragma once
/// \file
/// \brief SeqLockArray: a snapshot of N doubles written by one thread and read whole by others
/// (a sequence lock), e.g. the force a real-time thread last commanded, read by a UI or a test.
///
/// Thread-safety: one writer thread at a time; any number of concurrent readers. store() is
/// wait-free and load() lock-free (a reader retries while a store is in progress); neither
/// allocates, so both are real-time safe. A reader never sees a mix of two stores.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace depthtouch::platform {

template <std::size_t N>
class SeqLockArray {
public:
    /// Publishes \a values (single writer).
    void store(const std::array<double, N> &values) noexcept
    {
        const std::uint32_t seq = seq_.load(std::memory_order_relaxed);
        seq_.store(seq + 1, std::memory_order_relaxed); // odd: a store is in progress
        std::atomic_thread_fence(std::memory_order_release);
        for (std::size_t i = 0; i < N; ++i)
            values_[i].store(values[i], std::memory_order_relaxed);
        seq_.store(seq + 2, std::memory_order_release);
    }

    /// \return the last complete store (all zeros before the first).
    [[nodiscard]] std::array<double, N> load() const noexcept
    {
        std::array<double, N> out{};
        std::uint32_t before = 0;
        std::uint32_t after = 0;
        do {
            before = seq_.load(std::memory_order_acquire);
            for (std::size_t i = 0; i < N; ++i)
                out[i] = values_[i].load(std::memory_order_relaxed);
            std::atomic_thread_fence(std::memory_order_acquire);
            after = seq_.load(std::memory_order_relaxed);
        } while (before != after || (before & 1u) != 0);
        return out;
    }

private:
    std::atomic<std::uint32_t> seq_{0};
    std::array<std::atomic<double>, N> values_{};
};

} // namespace depthtouch::platform
