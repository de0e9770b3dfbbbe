#include "depthtouch/receiver/decoder_thread.h"

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Receiver)

namespace depthtouch::receiver {

DecoderThread::DecoderThread(Receiver &receiver) noexcept
    : receiver_(receiver), seekable_(receiver.source().info().seekable)
{
}

DecoderThread::~DecoderThread()
{
    stop();
}

Result<void> DecoderThread::start()
{
    if (thread_ && thread_->joinable())
        return unexpected(Errc::InvalidState, "The decoder thread already runs");
    stop_.store(false, std::memory_order_release);
    thread_.emplace(platform::kDecodeThread, platform::kPlainThreadOptions,
                    [this](platform::StopToken) { run(); });
    if (auto r = thread_->start(); !r) {
        thread_.reset();
        return r;
    }
    return ok();
}

void DecoderThread::stop() noexcept
{
    if (thread_ && thread_->joinable()) {
        stop_.store(true, std::memory_order_release);
        // A read blocked on a silent or stalled live stream returns within 100 ms, not at the
        // source's I/O timeout (seconds): stop means stop, whatever the network does.
        receiver_.source().interrupt();
        wake();
        thread_->join();
    }
    thread_.reset();
    PairedFrame f;
    while (queue_.tryPop(f))
        f = PairedFrame{};
}

void DecoderThread::wake() noexcept
{
    events_.fetch_add(1, std::memory_order_release);
    events_.notify_one();
}

bool DecoderThread::poll(PairedFrame &out) noexcept
{
    const std::uint32_t wanted = seekRequested_.load(std::memory_order_acquire);
    while (queue_.tryPop(out)) {
        wake(); // a slot is free
        if (out.generation == wanted)
            return true;
        out = PairedFrame{}; // decoded before the last seek
    }
    // The decoder thread waits for receiver frames the consumer may have dropped since.
    if (waitingForFrames_.load(std::memory_order_acquire))
        wake();
    return false;
}

void DecoderThread::seek(hal::Pts position) noexcept
{
    // A read waiting on a stalled input returns now, not at the source's time-out: the input ends
    // there and the seek that follows restarts it. Before the request, so that the decoder thread
    // cannot take the seek first and then lose a read to it.
    if (seekable_)
        receiver_.source().cancelRead();
    seekTarget_.store(position.count(), std::memory_order_relaxed);
    seekRequested_.fetch_add(1, std::memory_order_acq_rel);
    wake();
}

bool DecoderThread::finished() const noexcept
{
    return ended_.load(std::memory_order_acquire) &&
           generation_.load(std::memory_order_acquire) ==
               seekRequested_.load(std::memory_order_acquire) &&
           queue_.emptyApprox();
}

Error DecoderThread::error() const noexcept
{
    return failed() ? error_ : Error{};
}

ReceiverStats DecoderThread::stats() const
{
    std::lock_guard<std::mutex> lock(statsMutex_);
    return stats_;
}

void DecoderThread::publishStats()
{
    const ReceiverStats s = receiver_.stats();
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_ = s;
}

void DecoderThread::run() noexcept
{
    PairedFrame frame;
    bool haveFrame = false;
    std::uint32_t generation = generation_.load(std::memory_order_relaxed);
    for (;;) {
        const std::uint32_t seen = events_.load(std::memory_order_acquire);
        if (stop_.load(std::memory_order_acquire))
            break;
        const std::uint32_t requested = seekRequested_.load(std::memory_order_acquire);
        if (requested != generation) {
            frame = PairedFrame{};
            haveFrame = false;
            if (auto r = receiver_.seek(hal::Pts(seekTarget_.load(std::memory_order_relaxed)));
                !r) {
                seekFailures_.fetch_add(1, std::memory_order_relaxed);
                DT_LOG(Receiver, Warning, "Failed to seek: %s", r.error().what);
            }
            generation = requested;
            ended_.store(false, std::memory_order_release);
            generation_.store(generation, std::memory_order_release);
            continue;
        }
        if (!haveFrame && !ended_.load(std::memory_order_relaxed) &&
            !failed_.load(std::memory_order_relaxed)) {
            // Odd while inside next() (which blocks only on the source): see readProgress().
            progress_.fetch_add(1, std::memory_order_release);
            auto r = receiver_.next(frame);
            progress_.fetch_add(1, std::memory_order_release);
            if (r && *r) {
                frame.generation = generation;
                haveFrame = true;
            } else if (r) {
                publishStats();
                ended_.store(true, std::memory_order_release);
            } else if (r.error().code != Errc::Busy) {
                error_ = r.error();
                failed_.store(true, std::memory_order_release);
            }
            if (r || r.error().code != Errc::Busy)
                continue;
            waitingForFrames_.store(true, std::memory_order_release);
        }
        if (haveFrame && queue_.tryPush(std::move(frame))) {
            frame = PairedFrame{};
            haveFrame = false;
            // Published once the frame is queued: a consumer that reads framesOutput finds that
            // many frames given to it (taken, or waiting in the queue), none still held here.
            publishStats();
            continue;
        }
        // Queue full, consumer holding every frame, or nothing to do: wait for the consumer.
        events_.wait(seen, std::memory_order_acquire);
        waitingForFrames_.store(false, std::memory_order_release);
    }
    frame = PairedFrame{};
}

} // namespace depthtouch::receiver
