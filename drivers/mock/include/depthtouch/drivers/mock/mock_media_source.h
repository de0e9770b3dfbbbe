#pragma once
/// \file
/// \brief MockMediaSource: a deterministic synthetic "file" with a color and a depth stream (codec
/// Mock) for MockVideoDecoder, with fault injection. Backend name `mock`.
///
/// URL: "mock:" followed by anything; an optional query ("mock://clip?frames=10&fps=30") overrides
/// the settings with the same keys as the backend options (see MockMediaSettings::parse()). Layout:
/// stream 0 is "color" (when on), then "depth"; packets are interleaved frame by frame in stream
/// order, pts = frame / fps, dts = pts, a keyframe every `gop` frames. Packet data is a
/// MockPacketHeader (frame index, size, checksum) plus a payload (mock_pattern.h).
/// Thread-safety: thread-bound, as hal::MediaSource; the fault-injection calls too.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/drivers/mock/mock_pattern.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/media_source_base.h"

namespace depthtouch::drivers {

/// \brief The synthetic file's shape.
struct MockMediaSettings {
    int width = 64;          ///< Pixels (option `width`).
    int height = 48;         ///< Pixels (option `height`).
    int fps = 25;            ///< Frames per second (option `fps`).
    int frames = 50;         ///< Frames per stream (option `frames`).
    int gop = 10;            ///< Keyframe interval in frames (option `gop`).
    bool color = true;       ///< Has a color stream (option `color`).
    bool depth = true;       ///< Has a depth stream (option `depth`).
    int depthBits = 8;       ///< 8 (Gray8) or 16 (Gray16) nearness (option `depth_bits`).
    double nearMetres = 0.5; ///< Depth metadata (option `near`).
    double farMetres = 5.0;  ///< Depth metadata (option `far`).
    bool seekable = true;    ///< Whether seek() works (option `seekable`).

    /// \brief Reads the options over \a base. \return the settings; InvalidArgument for an unknown
    /// key or a value out of range (1..4096 pixels, 1..240 fps, 1..1000000 frames, gop ≥ 1, a
    /// stream on, 0 < near < far).
    static Result<MockMediaSettings> parse(hal::OptionList options, const MockMediaSettings &base);
};

class MockMediaSource final : public hal::MediaSourceBase {
public:
    /// Backend factory: settings from cfg.options.
    static Result<std::unique_ptr<hal::MediaSource>> create(const hal::BackendConfig &cfg);

    explicit MockMediaSource(const MockMediaSettings &settings = {});
    ~MockMediaSource() override = default;

    /// \name Fault injection (persist across open/close until changed)
    ///@{
    /// The next open() fails with \a code (once).
    void failNextOpen(Errc code) noexcept
    {
        failOpen_ = code;
        failOpenArmed_ = true;
    }
    /// Packet number \a ordinal (0-based, file order, counting every stream) gets a damaged
    /// payload: MockVideoDecoder conceals it.
    void corruptPacket(std::uint64_t ordinal) noexcept { corruptAt_ = ordinal; }
    /// The file is cut before packet \a ordinal: readPacket() returns Errc::Io from there on.
    void truncateAt(std::uint64_t ordinal) noexcept { truncateAt_ = ordinal; }
    /// Frames from \a frame on (every stream) get \a offset (ns) added to their PTS: a splice
    /// (forward), an encoder reset or a looped feed (back), a timestamp discontinuity.
    void jumpPtsAt(std::uint64_t frame, hal::Pts offset) noexcept
    {
        jumpFrame_ = frame;
        jumpOffset_ = offset;
    }
    ///@}

    /// \return packets returned by readPacket() since open().
    [[nodiscard]] std::uint64_t packetsRead() const noexcept { return packetsRead_; }
    /// \return the settings of the open file (URL query applied).
    [[nodiscard]] const MockMediaSettings &settings() const noexcept { return current_; }

protected:
    // hal::MediaSourceBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> openDevice(const char *url) override;
    void closeDevice() noexcept override;
    [[nodiscard]] const hal::MediaInfo &infoDevice() const noexcept override { return info_; }
    [[nodiscard]] Result<hal::Packet> readPacketDevice() override;
    [[nodiscard]] Result<void> seekDevice(hal::Pts position) override;

private:
    static constexpr std::uint64_t kNever = ~std::uint64_t{0};

    [[nodiscard]] int streamCount() const noexcept
    {
        return static_cast<int>(info_.streams.size());
    }

    MockMediaSettings settings_;
    MockMediaSettings current_;
    hal::MediaInfo info_;
    std::uint64_t next_ = 0; ///< Ordinal of the next packet.
    std::uint64_t packetsRead_ = 0;
    std::vector<std::uint8_t> buffer_; ///< Data of the last packet.

    Errc failOpen_ = Errc::Io;
    bool failOpenArmed_ = false;
    std::uint64_t corruptAt_ = kNever;
    std::uint64_t truncateAt_ = kNever;
    std::uint64_t jumpFrame_ = kNever;
    hal::Pts jumpOffset_{0};
};

} // namespace depthtouch::drivers
