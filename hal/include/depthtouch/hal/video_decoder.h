#pragma once
/// \file
/// \brief VideoDecoder: turns the packets of one stream into frames lent from a backend-owned pool.
///
/// State machine (docs/style.md §2):
/// \verbatim
///   Closed --configure()--> Configured --queuePacket()--> Running
///     ^                       ^   |  ^                      |
///     |                       |   |  +------flush()---------+
///     +------close()----------+---+-------close()-----------+
///   configure() in Configured reconfigures; close() is allowed in every state.
/// \endverbatim
/// A call that is not allowed in the current state returns Errc::InvalidState and has no effect.
///
/// Data flow: queuePacket() never blocks; it copies what it needs from the packet, so the packet's
/// data may be reused when it returns. dequeueFrame() lends a decoded frame as a FrameRef;
/// destroying the FrameRef returns the frame to the pool. When every pool frame is lent, decoding
/// stalls: dequeueFrame() returns Busy until the caller drops a FrameRef. An end-of-stream packet
/// (Packet::endOfStream()) drains the decoder: once the last frame has been dequeued,
/// dequeueFrame() returns EndOfStream until flush() or configure().
///
/// Errors in the data: a damaged packet is either concealed (the frame comes out with
/// Frame::corrupt set and counts in DecoderStats::framesConcealed) or dropped (one call of
/// queuePacket() or dequeueFrame() returns Errc::Io and it counts in framesDropped). Either way the
/// decoder stays usable.
///
/// Ownership: the decoder owns its pool; it must outlive every FrameRef it lent. configure() needs
/// every frame back (Busy otherwise) because it may reallocate the pool. Thread-safety:
/// thread-bound (the decode thread), except stats(), which is thread-safe, and FrameRef release,
/// which may happen on any thread. Not real-time safe.

#include <cstdint>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/types.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \return the bit of \a codec in VideoDecoderCapabilities::codecs.
constexpr std::uint32_t codecBit(CodecId codec) noexcept
{
    return 1u << static_cast<unsigned>(codec);
}

/// \brief What a decoder can do. Constant for the decoder's lifetime.
struct VideoDecoderCapabilities {
    std::uint32_t codecs = 0; ///< Bitmask of codecBit(CodecId).
    int maxWidth = 0;         ///< Largest coded width in pixels.
    int maxHeight = 0;        ///< Largest coded height in pixels.
    int poolFrames = 0; ///< Frames in the output pool: the most FrameRefs that can be held at once.
    int queuePackets = 0;  ///< Packets queuePacket() accepts before it returns Busy.
    bool hardware = false; ///< Decodes on a hardware block (informational).

    [[nodiscard]] constexpr bool supports(CodecId codec) const noexcept
    {
        return (codecs & codecBit(codec)) != 0;
    }
};

/// \brief What configure() needs to know about the stream.
struct StreamConfig {
    CodecId codec = CodecId::Unknown;
    StreamKind kind = StreamKind::Color;
    PixelFormat format = PixelFormat::Unknown; ///< Decoded format the stream declares.
    int width = 0;                             ///< Pixels.
    int height = 0;                            ///< Pixels.
    Rational frameRate;
    std::vector<std::uint8_t> extradata; ///< Codec setup data, copied from the StreamInfo.

    /// \return the configuration for decoding \a stream.
    static StreamConfig fromStream(const StreamInfo &stream);
};

/// \brief Counters since the decoder was created. Read with stats() from any thread.
struct DecoderStats {
    std::uint64_t packetsQueued =
        0; ///< Packets accepted by queuePacket() (end-of-stream excluded).
    std::uint64_t framesDecoded = 0;   ///< Frames lent by dequeueFrame(), concealed ones included.
    std::uint64_t framesConcealed = 0; ///< Frames output with Frame::corrupt set.
    std::uint64_t framesDropped = 0;   ///< Packets that produced no frame (decode error, flush).
    std::uint64_t framesDmaBuf = 0;    ///< Frames lent as dma-bufs (Frame::dmabuf), no CPU copy.
    std::uint64_t framesHardware = 0;  ///< Frames a hardware decoder made (a libavcodec hwaccel
                                       ///< device, a V4L2 M2M device); the rest were software.
};

/// \brief Hardware or software video decoder for one stream.
class VideoDecoder {
public:
    enum class State : std::uint8_t { Closed, Configured, Running };

    virtual ~VideoDecoder() = default;

    /// \return what the decoder can do; constant for its whole lifetime.
    [[nodiscard]] virtual const VideoDecoderCapabilities &capabilities() const noexcept = 0;

    /// \return the current state.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Prepares decoding of one stream and allocates the frame pool.
    /// \pre Closed or Configured, and no frame lent.
    /// \param[in] cfg The stream to decode (StreamConfig::fromStream()).
    /// \return nothing on success (state Configured). Errors: InvalidState (Running), Busy (a
    /// FrameRef is still held), NotSupported (codec or format), InvalidArgument (size out of
    /// range), NoDevice or OutOfResources (the hardware or memory is not available). On error the
    /// state does not change.
    [[nodiscard]] virtual Result<void> configure(const StreamConfig &cfg) = 0;

    /// \brief Queues one compressed packet, or an end-of-stream packet to drain. Never blocks.
    /// \pre Configured or Running (the first packet moves Configured to Running).
    /// \param[in] pkt The packet; its data is copied before the call returns.
    /// \return nothing when accepted. Errors: InvalidState (Closed, or a packet after end-of-stream
    /// before flush()), Busy (input queue full: dequeue frames first), InvalidArgument (not a
    /// packet of the configured codec; counted as dropped), Io (the decoder rejected the data;
    /// counted as dropped).
    [[nodiscard]] virtual Result<void> queuePacket(const Packet &pkt) = 0;

    /// \brief Lends the next decoded frame, waiting on the backend clock until \a until at most.
    /// \pre Running.
    /// \param[in] until Absolute deadline; a deadline in the past polls without waiting.
    /// \return the frame. Errors: InvalidState (not Running), Timeout (no frame by the deadline),
    /// Busy (every pool frame is lent: drop a FrameRef), EndOfStream (drained), Io (the packet at
    /// the head failed to decode; counted as dropped; the next call goes on with the following
    /// packet).
    [[nodiscard]] virtual Result<FrameRef> dequeueFrame(Deadline until) = 0;

    /// \brief Drops queued packets and frames not yet dequeued (for seeking); lent frames stay
    /// valid. \pre Configured or Running (no-op when Configured). \return nothing on success (state
    /// Configured). Errors: InvalidState (Closed).
    [[nodiscard]] virtual Result<void> flush() = 0;

    /// \brief Stops decoding and drops queued data. Always allowed. Lent frames stay valid until
    /// returned; the pool is freed by the next configure() or the destructor.
    virtual void close() noexcept = 0;

    /// \return the counters. Thread-safe; real-time safe.
    [[nodiscard]] virtual DecoderStats stats() const noexcept = 0;

protected:
    VideoDecoder() = default;
    DT_DISABLE_COPY_AND_MOVE(VideoDecoder)
};

/// \return the name of \a s: "Closed", "Configured" or "Running" (a static string; "?" for another
/// value), for messages. Thread-safe.
[[nodiscard]] const char *toString(VideoDecoder::State s) noexcept;

} // namespace depthtouch::hal
