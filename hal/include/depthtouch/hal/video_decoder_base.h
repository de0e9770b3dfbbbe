#pragma once
/// \file
/// \brief VideoDecoderBase: the hal::VideoDecoder state machine in one place, for every decoder
/// backend.
///
/// A backend derives from VideoDecoderBase and implements only the device work (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract of video_decoder.h
/// around them, as DisplayBase does for displays (libcamera's queueRequest() and
/// queueRequestDevice()):
/// - configure(): InvalidState when Running; NotSupported for a codec capabilities() does not list;
///   InvalidArgument for a size outside 1..maxWidth × 1..maxHeight; then configureDevice();
///   Configured on success, the state unchanged on error.
/// - queuePacket(): InvalidState when Closed or after an end-of-stream packet until flush(); an
///   end-of-stream packet is a flag (never a queue slot: always accepted) that moves to Running and
///   makes draining() true; a packet with data goes to queuePacketDevice() and moves to Running
///   when accepted.
/// - dequeueFrame(): InvalidState unless Running, then dequeueFrameDevice().
/// - flush(): InvalidState when Closed; a no-op when Configured; from Running flushDevice(), then
///   Configured and no longer draining.
/// - close(): a no-op when Closed; else closeDevice(), then Closed and no longer draining.
/// Every InvalidState is logged (category HalDecoder, debug) with the call and the state.
///
/// Thread-safety: thread-bound, as hal::VideoDecoder (stats() stays the backend's, thread-safe).

#include <atomic>
#include <cstdint>

#include "depthtouch/hal/video_decoder.h"

namespace depthtouch::hal {

/// \brief The counts of DecoderStats as atomics, for a backend's stats(): the backend counts on the
/// thread that decodes while stats() is read from any other. Thread-safe; real-time safe (relaxed,
/// lock-free counters).
struct DecoderCounters {
    std::atomic<std::uint64_t> packetsQueued{0};   ///< DecoderStats::packetsQueued.
    std::atomic<std::uint64_t> framesDecoded{0};   ///< DecoderStats::framesDecoded.
    std::atomic<std::uint64_t> framesConcealed{0}; ///< DecoderStats::framesConcealed.
    std::atomic<std::uint64_t> framesDropped{0};   ///< DecoderStats::framesDropped.
    std::atomic<std::uint64_t> framesDmaBuf{0};    ///< DecoderStats::framesDmaBuf.
    std::atomic<std::uint64_t> framesHardware{0};  ///< DecoderStats::framesHardware.

    /// \return the counts, each read once (not one instant across the counters).
    [[nodiscard]] DecoderStats snapshot() const noexcept;
};

/// \brief The base of every video decoder backend: owns the state, the end-of-stream flag and the
/// contract (see the file comment); the backend implements the hooks.
class VideoDecoderBase : public VideoDecoder {
public:
    ~VideoDecoderBase() override = default;

    [[nodiscard]] const VideoDecoderCapabilities &capabilities() const noexcept final
    {
        return caps_;
    }
    [[nodiscard]] State state() const noexcept final { return state_; }
    [[nodiscard]] Result<void> configure(const StreamConfig &cfg) final;
    [[nodiscard]] Result<void> queuePacket(const Packet &pkt) final;
    [[nodiscard]] Result<FrameRef> dequeueFrame(Deadline until) final;
    [[nodiscard]] Result<void> flush() final;
    void close() noexcept final;

protected:
    VideoDecoderBase() = default;

    /// \brief Prepares decoding of \a cfg (called Closed or Configured, with a codec caps_ lists
    /// and a size within caps_). \return Errors: as configure() (NotSupported, InvalidArgument,
    /// Busy, NoDevice, OutOfResources), with nothing changed.
    [[nodiscard]] virtual Result<void> configureDevice(const StreamConfig &cfg) = 0;
    /// \brief Queues \a pkt, a packet with data (called Configured or Running, not draining).
    /// \return Errors: as queuePacket() (Busy, InvalidArgument, Io).
    [[nodiscard]] virtual Result<void> queuePacketDevice(const Packet &pkt) = 0;
    /// \brief Lends the next frame (called Running; draining() says whether the end of the stream
    /// was queued). \return Errors: as dequeueFrame() (Timeout, Busy, EndOfStream, Io).
    [[nodiscard]] virtual Result<FrameRef> dequeueFrameDevice(Deadline until) = 0;
    /// \brief Drops the queued packets and the frames not yet dequeued (called Running).
    virtual void flushDevice() noexcept = 0;
    /// \brief Stops decoding and drops queued data (called Configured or Running).
    virtual void closeDevice() noexcept = 0;

    /// \return whether an end-of-stream packet was queued since the last configure() or flush().
    [[nodiscard]] bool draining() const noexcept { return draining_; }

    VideoDecoderCapabilities caps_; ///< Set by the backend's constructor; constant afterwards.

private:
    /// InvalidState (logged) unless \a allowed.
    [[nodiscard]] Result<void> check(bool allowed, const char *call, const char *required,
                                     const char *message) const noexcept;

    State state_ = State::Closed;
    bool draining_ = false;
};

} // namespace depthtouch::hal
