#include "depthtouch/drivers/mock/mock_video_decoder.h"

#include <cstring>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/drivers/mock/mock_pattern.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/drivers/common/frame_pool.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr NumericOption<MockDecoderSettings> kOptions[] = {
    {.key = "pool", .integer = &MockDecoderSettings::poolFrames, .min = 1, .max = 64},
    {.key = "queue", .integer = &MockDecoderSettings::queuePackets, .min = 1, .max = 256},
};
constexpr int kMaxSize = 4096;

bool outputFormatSupported(hal::StreamKind kind, hal::PixelFormat f) noexcept
{
    if (kind == hal::StreamKind::Depth)
        return f == hal::PixelFormat::Gray8 || f == hal::PixelFormat::Gray10 ||
               f == hal::PixelFormat::Gray16;
    return f == hal::PixelFormat::Yuv420p || f == hal::PixelFormat::Rgb24 ||
           f == hal::PixelFormat::Gray8;
}

} // namespace

Result<MockDecoderSettings> MockDecoderSettings::parse(hal::OptionList options)
{
    return parseNumericOptions(options, kOptions, kLogCategoryMock,
                               "Unknown mock video decoder option",
                               "Mock video decoder option out of range");
}

Result<std::unique_ptr<hal::VideoDecoder>> MockVideoDecoder::create(const hal::BackendConfig &cfg)
{
    return createFromSettings<hal::VideoDecoder, MockVideoDecoder, MockDecoderSettings>(cfg);
}

MockVideoDecoder::MockVideoDecoder(platform::Clock &clock, const MockDecoderSettings &settings)
    : clock_(clock), settings_(settings), pool_(std::make_unique<FramePool>()),
      queue_(static_cast<std::size_t>(settings.queuePackets))
{
    caps_.codecs = hal::codecBit(hal::CodecId::Mock);
    caps_.maxWidth = kMaxSize;
    caps_.maxHeight = kMaxSize;
    caps_.poolFrames = settings.poolFrames;
    caps_.queuePackets = settings.queuePackets;
    caps_.hardware = false;
}

MockVideoDecoder::~MockVideoDecoder() = default;

Result<void> MockVideoDecoder::checkState(bool allowed, const char *call,
                                          const char *required) const noexcept
{
    if (allowed)
        return ok();
    DT_LOG(Mock, Error, "In state %s trying %s() requiring %s", hal::toString(state_), call,
           required);
    return unexpected(Errc::InvalidState, "Call not allowed in the decoder's state");
}

Result<void> MockVideoDecoder::configure(const hal::StreamConfig &cfg)
{
    DT_TRY(checkState(state_ != State::Running, "configure", "Closed or Configured"));
    if (failConfigureArmed_) {
        failConfigureArmed_ = false;
        return unexpected(failConfigure_, "Failed to configure mock decoder (injected fault)");
    }
    if (!caps_.supports(cfg.codec))
        return unexpected(Errc::NotSupported, "Mock decoder decodes only the Mock codec");
    if (cfg.width < 1 || cfg.height < 1 || cfg.width > caps_.maxWidth ||
        cfg.height > caps_.maxHeight)
        return unexpected(Errc::InvalidArgument, "Stream size out of range");
    if (!outputFormatSupported(cfg.kind, cfg.format))
        return unexpected(Errc::NotSupported, "Mock decoder cannot output this pixel format");
    DT_TRY(pool_->allocate(settings_.poolFrames, cfg.format, cfg.width, cfg.height));
    config_ = cfg;
    dropQueue();
    queuedSinceConfigure_ = 0;
    sequence_ = 0;
    draining_ = false;
    state_ = State::Configured;
    return ok();
}

void MockVideoDecoder::dropQueue() noexcept
{
    framesDropped_.fetch_add(count_, std::memory_order_relaxed);
    head_ = 0;
    count_ = 0;
}

Result<void> MockVideoDecoder::queuePacket(const hal::Packet &pkt)
{
    DT_TRY(checkState(state_ != State::Closed, "queuePacket", "Configured or Running"));
    if (draining_)
        return unexpected(Errc::InvalidState, "Packet after end of stream: flush() first");
    if (pkt.isEndOfStream()) {
        draining_ = true;
        state_ = State::Running;
        return ok();
    }
    if (count_ == queue_.size())
        return unexpected(Errc::Busy, "Decoder input queue full");
    MockPacketHeader header;
    if (pkt.size > sizeof(QueuedPacket::data) ||
        parseMockPacket(pkt.data, pkt.size, header) == MockPacketCheck::Malformed) {
        framesDropped_.fetch_add(1, std::memory_order_relaxed);
        return unexpected(Errc::InvalidArgument, "Not a Mock codec packet");
    }
    QueuedPacket &q = queue_[(head_ + count_) % queue_.size()];
    std::memcpy(q.data, pkt.data, pkt.size);
    q.size = pkt.size;
    q.pts = pkt.pts;
    q.ordinal = queuedSinceConfigure_++;
    ++count_;
    packetsQueued_.fetch_add(1, std::memory_order_relaxed);
    state_ = State::Running;
    return ok();
}

Result<hal::FrameRef> MockVideoDecoder::dequeueFrame(hal::Deadline until)
{
    DT_TRY(checkState(state_ == State::Running, "dequeueFrame", "Running"));
    if (count_ == 0) {
        if (draining_)
            return unexpected(Errc::EndOfStream, "Decoder drained");
        // Nothing can arrive while the caller waits here (queuePacket() runs on the same thread).
        if (until > clock_.now())
            clock_.sleepUntil(until);
        return unexpected(Errc::Timeout, "No decoded frame before the deadline");
    }
    QueuedPacket &q = queue_[head_];
    if (q.ordinal == failPacketAt_) {
        head_ = (head_ + 1) % queue_.size();
        --count_;
        framesDropped_.fetch_add(1, std::memory_order_relaxed);
        return unexpected(Errc::Io, "Failed to decode packet (injected fault)");
    }
    std::uint32_t slot = 0;
    hal::Frame *frame = poolExhausted_ ? nullptr : pool_->acquire(slot);
    if (frame == nullptr)
        return unexpected(Errc::Busy, "Every decoder frame is lent");

    MockPacketHeader header;
    const MockPacketCheck check = parseMockPacket(q.data, q.size, header);
    if (check == MockPacketCheck::Ok) {
        if (config_.kind == hal::StreamKind::Depth) {
            const double fps = config_.frameRate.den != 0 ? config_.frameRate.toDouble() : 25.0;
            renderMockDepth(frame->image, static_cast<double>(header.frameIndex) / fps);
        } else {
            renderMockColor(frame->image, header.frameIndex);
        }
        frame->corrupt = false;
    } else {
        renderMockConcealed(frame->image);
        frame->corrupt = true;
        framesConcealed_.fetch_add(1, std::memory_order_relaxed);
    }
    frame->kind = config_.kind;
    frame->pts = q.pts;
    frame->time = clock_.now();
    frame->sequence = sequence_++;
    head_ = (head_ + 1) % queue_.size();
    --count_;
    framesDecoded_.fetch_add(1, std::memory_order_relaxed);
    return pool_->lend(slot);
}

Result<void> MockVideoDecoder::flush()
{
    DT_TRY(checkState(state_ != State::Closed, "flush", "Configured or Running"));
    dropQueue();
    draining_ = false;
    state_ = State::Configured;
    return ok();
}

void MockVideoDecoder::close() noexcept
{
    dropQueue();
    draining_ = false;
    state_ = State::Closed;
}

hal::DecoderStats MockVideoDecoder::stats() const noexcept
{
    hal::DecoderStats s;
    s.packetsQueued = packetsQueued_.load(std::memory_order_relaxed);
    s.framesDecoded = framesDecoded_.load(std::memory_order_relaxed);
    s.framesConcealed = framesConcealed_.load(std::memory_order_relaxed);
    s.framesDropped = framesDropped_.load(std::memory_order_relaxed);
    return s;
}

int MockVideoDecoder::framesLent() const noexcept
{
    return pool_->lent();
}

} // namespace depthtouch::drivers
