#pragma once
/// \file
/// \brief MockVideoDecoder: decodes Mock codec packets (MockMediaSource) into deterministic
/// synthetic frames from a preallocated pool, with fault injection. Backend name `mock`.
///
/// Output: depth streams (Gray8/Gray10/Gray16) get renderMockDepth() at the frame's time (frame
/// index / frame rate), color streams (Yuv420p/Rgb24/Gray8) renderMockColor() with the frame index.
/// A packet whose payload is damaged is concealed (mid-gray frame, Frame::corrupt). Decoding
/// happens inside dequeueFrame(), so it is instant on the clock; waiting for a deadline sleeps on
/// the injected clock. Thread-safety: as hal::VideoDecoder; the fault-injection calls are
/// thread-bound too.

#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/drivers/mock/mock_pattern.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/video_decoder_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

class FramePool;

/// \brief Sizes of the mock decoder.
struct MockDecoderSettings {
    int poolFrames = 4;   ///< Output frames (option `pool`, 1..64).
    int queuePackets = 8; ///< Input packets (option `queue`, 1..256).

    /// \return the settings from \a options over the defaults; InvalidArgument for an unknown key
    /// or a value out of range.
    static Result<MockDecoderSettings> parse(hal::OptionList options);
};

class MockVideoDecoder final : public hal::VideoDecoderBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::VideoDecoder>> create(const hal::BackendConfig &cfg);

    explicit MockVideoDecoder(platform::Clock &clock, const MockDecoderSettings &settings = {});
    ~MockVideoDecoder() override;

    [[nodiscard]] hal::DecoderStats stats() const noexcept override;

    /// \name Fault injection
    ///@{
    /// The next configure() fails with \a code and changes nothing (once).
    void failNextConfigure(Errc code) noexcept
    {
        failConfigure_ = code;
        failConfigureArmed_ = true;
    }
    /// The packet queued as number \a ordinal (0-based, counted since configure()) fails to decode:
    /// dequeueFrame() returns Errc::Io for it and counts it as dropped.
    void failPacket(std::uint64_t ordinal) noexcept { failPacketAt_ = ordinal; }
    /// While \a exhausted, the pool behaves as if every frame were lent: dequeueFrame() returns
    /// Busy.
    void exhaustPool(bool exhausted) noexcept { poolExhausted_ = exhausted; }
    ///@}

    /// \return frames lent and not yet returned. Thread-safe.
    [[nodiscard]] int framesLent() const noexcept;

protected:
    // hal::VideoDecoderBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> configureDevice(const hal::StreamConfig &cfg) override;
    [[nodiscard]] Result<void> queuePacketDevice(const hal::Packet &pkt) override;
    [[nodiscard]] Result<hal::FrameRef> dequeueFrameDevice(hal::Deadline until) override;
    void flushDevice() noexcept override;
    void closeDevice() noexcept override;

private:
    struct QueuedPacket {
        std::uint8_t data[kMockPacketMaxBytes];
        std::size_t size = 0;
        hal::Pts pts = hal::kNoPts;
        std::uint64_t ordinal = 0;
    };

    void dropQueue() noexcept;

    platform::Clock &clock_;
    const MockDecoderSettings settings_;
    std::unique_ptr<FramePool> pool_;
    hal::StreamConfig config_;

    std::vector<QueuedPacket> queue_; ///< Ring of settings_.queuePackets packets.
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint64_t queuedSinceConfigure_ = 0;
    std::uint64_t sequence_ = 0;

    hal::DecoderCounters counters_; ///< stats() (never a dma-buf or hardware frame).

    Errc failConfigure_ = Errc::NoDevice;
    bool failConfigureArmed_ = false;
    std::uint64_t failPacketAt_ = ~std::uint64_t{0};
    bool poolExhausted_ = false;
};

} // namespace depthtouch::drivers
