#pragma once
/// \file
/// \brief DecoderThread: runs a Receiver (demux → decode → pair) on its own normal-priority thread
/// and hands paired frames to a consumer through a bounded lock-free SPSC queue
/// (docs/architecture.md §5, the decode thread).
///
/// The consumer never blocks: poll() takes a frame or returns false at once. Backpressure blocks
/// only the decoder thread: with the queue full (or the consumer holding every receiver frame) it
/// waits on an atomic counter the consumer bumps when it takes a frame (std::atomic::wait/notify,
/// no lock on the consumer side). seek() is a request: the decoder thread seeks the Receiver
/// (flushing decoders and pairing) and every frame queued before it is discarded by poll(), so the
/// consumer sees only frames of the new position.
///
/// Thread-safety: start(), stop() and the destructor from the owning thread; poll(), seek(),
/// finished(), failed() and stats() from one consumer thread (may be the owner). The Receiver is
/// used only by the decoder thread while it runs and must outlive the DecoderThread.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>

#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/spsc_ring.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::receiver {

class DecoderThread {
public:
    /// Paired frames queued between the threads; keep ReceiverConfig::consumerFrames above it.
    static constexpr std::size_t kQueueFrames = 4;

    explicit DecoderThread(Receiver &receiver) noexcept;
    ~DecoderThread(); ///< stop().

    /// \brief Starts the thread from the thread table's kDecodeThread row. \return InvalidState
    /// when already started; OutOfResources when the thread cannot be created.
    Result<void> start();
    /// \brief Stops and joins the thread and drops the queued frames. Idempotent. A read blocked
    /// in the source is interrupted (hal::MediaSource::interrupt(): within 100 ms); the source
    /// then fails every read until it is closed, so the Receiver is not run again.
    void stop() noexcept;

    /// \brief Takes the next paired frame. Never blocks.
    /// \return true with \a out filled; false when nothing is ready.
    bool poll(PairedFrame &out) noexcept;

    /// \brief Asks the decoder thread to restart at \a position. Never blocks; later poll()s return
    /// only frames decoded after the seek. A read blocked on a stalled seekable input is cancelled
    /// (hal::MediaSource::cancelRead()), so the seek does not wait for the source's time-out.
    void seek(hal::Pts position) noexcept;

    /// \return true when the input ended (and no seek is pending) and every frame was polled.
    [[nodiscard]] bool finished() const noexcept;
    /// \return true when the Receiver failed (error()) and the thread stopped producing.
    [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
    /// \return the Receiver's error after failed().
    [[nodiscard]] Error error() const noexcept;
    /// \return a snapshot of the Receiver's counters, taken by the decoder thread after each frame
    /// it queued (framesOutput counts frames given to the consumer, none held back) and at the end.
    [[nodiscard]] ReceiverStats stats() const;
    /// \brief What the decoder thread is doing, for telling a silent live stream: bumped when it
    /// enters and when it leaves Receiver::next() (which waits only on the source), so the value is
    /// odd while it waits there; a consumer that sees the same odd value for seconds knows that
    /// nothing came from the source for as long. Thread-safe.
    [[nodiscard]] std::uint64_t readProgress() const noexcept
    {
        return progress_.load(std::memory_order_acquire);
    }
    /// \return seek() requests that failed (the source was not seekable).
    [[nodiscard]] std::uint64_t seekFailures() const noexcept
    {
        return seekFailures_.load(std::memory_order_relaxed);
    }

private:
    DT_DISABLE_COPY_AND_MOVE(DecoderThread)
    void run() noexcept;
    void wake() noexcept;
    void publishStats();

    Receiver &receiver_;
    const bool seekable_; ///< The source can seek: seek() cancels a blocked read.
    std::optional<platform::RealtimeThread> thread_; ///< kDecodeThread, from start().
    platform::SpscRing<PairedFrame, kQueueFrames> queue_;

    std::atomic<std::uint32_t> events_{0}; ///< Bumped on poll, seek and stop; waited on.
    std::atomic<bool> stop_{false};
    std::atomic<std::uint32_t> seekRequested_{0}; ///< Generation the consumer asked for.
    std::atomic<std::int64_t> seekTarget_{0};     ///< ns
    std::atomic<std::uint32_t> generation_{0};    ///< Generation the decoder thread produces.
    std::atomic<bool> ended_{false};
    std::atomic<bool> waitingForFrames_{
        false}; ///< The Receiver said Busy: poll() wakes the thread.
    std::atomic<bool> failed_{false};
    std::atomic<std::uint64_t> seekFailures_{0};
    std::atomic<std::uint64_t> progress_{0}; ///< readProgress().
    Error error_{};

    mutable std::mutex statsMutex_; ///< Guards stats_.
    ReceiverStats stats_;
};

} // namespace depthtouch::receiver
