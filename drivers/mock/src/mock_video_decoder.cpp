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

Result<void> MockVideoDecoder::configureDevice(const hal::StreamConfig &cfg)
{
    if (failConfigureArmed_) {
        failConfigureArmed_ = false;
        return unexpected(failConfigure_, "Failed to configure mock decoder (injected fault)");
    }
    if (!outputFormatSupported(cfg.kind, cfg.format))
        return unexpected(Errc::NotSupported, "Mock decoder cannot output this pixel format");
    DT_TRY(pool_->allocate(settings_.poolFrames, cfg.format, cfg.width, cfg.height));
    config_ = cfg;
    dropQueue();
    queuedSinceConfigure_ = 0;
    sequence_ = 0;
    return ok();
}

void MockVideoDecoder::dropQueue() noexcept
{
    counters_.framesDropped.fetch_add(count_, std::memory_order_relaxed);
    head_ = 0;
    count_ = 0;
}

Result<void> MockVideoDecoder::queuePacketDevice(const hal::Packet &pkt)
{
    if (count_ == queue_.size())
        return unexpected(Errc::Busy, "Decoder input queue full");
    MockPacketHeader header;
    if (pkt.size > sizeof(QueuedPacket::data) ||
        parseMockPacket(pkt.data, pkt.size, header) == MockPacketCheck::Malformed) {
        counters_.framesDropped.fetch_add(1, std::memory_order_relaxed);
        return unexpected(Errc::InvalidArgument, "Not a Mock codec packet");
    }
    QueuedPacket &q = queue_[(head_ + count_) % queue_.size()];
    std::memcpy(q.data, pkt.data, pkt.size);
    q.size = pkt.size;
    q.pts = pkt.pts;
    q.ordinal = queuedSinceConfigure_++;
    ++count_;
    counters_.packetsQueued.fetch_add(1, std::memory_order_relaxed);
    return ok();
}

Result<hal::FrameRef> MockVideoDecoder::dequeueFrameDevice(hal::Deadline until)
{
    if (count_ == 0) {
        if (draining())
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
        counters_.framesDropped.fetch_add(1, std::memory_order_relaxed);
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
        counters_.framesConcealed.fetch_add(1, std::memory_order_relaxed);
    }
    frame->kind = config_.kind;
    frame->pts = q.pts;
    frame->time = clock_.now();
    frame->sequence = sequence_++;
    head_ = (head_ + 1) % queue_.size();
    --count_;
    counters_.framesDecoded.fetch_add(1, std::memory_order_relaxed);
    return pool_->lend(slot);
}

void MockVideoDecoder::flushDevice() noexcept
{
    dropQueue();
}

void MockVideoDecoder::closeDevice() noexcept
{
    dropQueue();
}

hal::DecoderStats MockVideoDecoder::stats() const noexcept
{
    return counters_.snapshot();
}

int MockVideoDecoder::framesLent() const noexcept
{
    return pool_->lent();
}

} // namespace depthtouch::drivers
