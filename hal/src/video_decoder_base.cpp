/// \file
/// \brief The hal::VideoDecoder contract around a backend's hooks (see video_decoder_base.h).

#include "depthtouch/hal/video_decoder_base.h"

#include "depthtouch/platform/log.h"
#include "session_state.h"

DT_LOG_CATEGORY(HalDecoder)

namespace depthtouch::hal {

DecoderStats DecoderCounters::snapshot() const noexcept
{
    DecoderStats s;
    s.packetsQueued = packetsQueued.load(std::memory_order_relaxed);
    s.framesDecoded = framesDecoded.load(std::memory_order_relaxed);
    s.framesConcealed = framesConcealed.load(std::memory_order_relaxed);
    s.framesDropped = framesDropped.load(std::memory_order_relaxed);
    s.framesDmaBuf = framesDmaBuf.load(std::memory_order_relaxed);
    s.framesHardware = framesHardware.load(std::memory_order_relaxed);
    return s;
}

Result<void> VideoDecoderBase::check(bool allowed, const char *call, const char *required,
                                     const char *message) const noexcept
{
    if (allowed)
        return ok();
    DT_LOG(HalDecoder, Debug, "In state %s%s trying %s() requiring %s", toString(state_),
           draining_ ? " (draining)" : "", call, required);
    return unexpected(Errc::InvalidState, message);
}

Result<void> VideoDecoderBase::configure(const StreamConfig &cfg)
{
    DT_TRY(check(state_ != State::Running, "configure", "Closed or Configured",
                 "configure() is not allowed while decoding: flush() first"));
    if (!caps_.supports(cfg.codec))
        return unexpected(Errc::NotSupported, "The decoder does not decode this codec");
    if (cfg.width < 1 || cfg.height < 1 || cfg.width > caps_.maxWidth ||
        cfg.height > caps_.maxHeight)
        return unexpected(Errc::InvalidArgument, "Frame size out of the decoder's range");
    DT_TRY(configureDevice(cfg));
    state_ = State::Configured;
    draining_ = false;
    return ok();
}

Result<void> VideoDecoderBase::queuePacket(const Packet &pkt)
{
    DT_TRY(check(state_ != State::Closed, "queuePacket", "Configured or Running",
                 "queuePacket() needs a configured decoder"));
    DT_TRY(check(!draining_, "queuePacket", "no end of stream queued",
                 "Packet after end of stream: flush() first"));
    if (pkt.isEndOfStream()) {
        draining_ = true;
        state_ = State::Running;
        return ok();
    }
    DT_TRY(queuePacketDevice(pkt));
    state_ = State::Running;
    return ok();
}

Result<FrameRef> VideoDecoderBase::dequeueFrame(Deadline until)
{
    DT_TRY(check(state_ == State::Running, "dequeueFrame", "Running",
                 "dequeueFrame() needs a packet queued since configure() or flush()"));
    return dequeueFrameDevice(until);
}

Result<void> VideoDecoderBase::flush()
{
    DT_TRY(check(state_ != State::Closed, "flush", "Configured or Running",
                 "flush() needs a configured decoder"));
    if (state_ == State::Running)
        flushDevice();
    state_ = State::Configured;
    draining_ = false;
    return ok();
}

void VideoDecoderBase::close() noexcept
{
    detail::closeSession(state_, [this]() noexcept {
        closeDevice();
        draining_ = false;
    });
}

} // namespace depthtouch::hal
