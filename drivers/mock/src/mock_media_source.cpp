#include "depthtouch/drivers/mock/mock_media_source.h"

#include <iterator>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"width", "height",     "fps",  "frames", "gop",     "color",
                                       "depth", "depth_bits", "near", "far",    "seekable"};

hal::Pts framePts(std::uint64_t frame, int fps) noexcept
{
    return hal::Pts(static_cast<std::int64_t>(frame) * 1'000'000'000 / fps);
}

} // namespace

Result<MockMediaSettings> MockMediaSettings::parse(hal::OptionList options,
                                                   const MockMediaSettings &base)
{
    DT_TRY(rejectUnknownOptions(options, kOptionKeys, std::size(kOptionKeys), kLogCategoryMock,
                                "Unknown mock media source option"));
    MockMediaSettings s = base;
    auto width = options.getInt("width", s.width);
    auto height = options.getInt("height", s.height);
    auto fps = options.getInt("fps", s.fps);
    auto frames = options.getInt("frames", s.frames);
    auto gop = options.getInt("gop", s.gop);
    auto color = options.getBool("color", s.color);
    auto depth = options.getBool("depth", s.depth);
    auto bits = options.getInt("depth_bits", s.depthBits);
    auto nearM = options.getDouble("near", s.nearMetres);
    auto farM = options.getDouble("far", s.farMetres);
    auto seekable = options.getBool("seekable", s.seekable);
    if (!width || !height || !fps || !frames || !gop || !color || !depth || !bits || !nearM ||
        !farM || !seekable)
        return unexpected(Errc::InvalidArgument, "Malformed mock media source option value");
    s.width = *width;
    s.height = *height;
    s.fps = *fps;
    s.frames = *frames;
    s.gop = *gop;
    s.color = *color;
    s.depth = *depth;
    s.depthBits = *bits;
    s.nearMetres = *nearM;
    s.farMetres = *farM;
    s.seekable = *seekable;
    if (s.width < 1 || s.width > 4096 || s.height < 1 || s.height > 4096 || s.fps < 1 ||
        s.fps > 240 || s.frames < 1 || s.frames > 1'000'000 || s.gop < 1 ||
        (!s.color && !s.depth) || (s.depthBits != 8 && s.depthBits != 16) ||
        !(s.nearMetres > 0.0) || !(s.farMetres > s.nearMetres))
        return unexpected(Errc::InvalidArgument, "Mock media source option out of range");
    return s;
}

Result<std::unique_ptr<hal::MediaSource>> MockMediaSource::create(const hal::BackendConfig &cfg)
{
    auto settings = MockMediaSettings::parse(cfg.options, MockMediaSettings{});
    if (!settings)
        return unexpected(settings.error());
    return std::unique_ptr<hal::MediaSource>(std::make_unique<MockMediaSource>(*settings));
}

MockMediaSource::MockMediaSource(const MockMediaSettings &settings)
    : settings_(settings), current_(settings)
{
}

Result<void> MockMediaSource::openDevice(const char *url)
{
    if (failOpenArmed_) {
        failOpenArmed_ = false;
        return unexpected(failOpen_, "Failed to open mock media (injected fault)");
    }
    const std::string_view u = url != nullptr ? url : "";
    if (u.substr(0, 5) != "mock:")
        return unexpected(Errc::NotSupported, "Mock media source reads only mock: URLs");
    const std::size_t query = u.find('?');
    auto settings = MockMediaSettings::parse(
        hal::OptionList(query == std::string_view::npos ? std::string_view{} : u.substr(query + 1)),
        settings_);
    if (!settings)
        return unexpected(settings.error());

    current_ = *settings;
    info_ = {};
    const hal::Rational rate{current_.fps, 1};
    const hal::Rational timeBase{1, current_.fps};
    if (current_.color) {
        hal::StreamInfo s;
        s.index = 0;
        s.kind = hal::StreamKind::Color;
        s.title = "color";
        s.codec = hal::CodecId::Mock;
        s.format = hal::PixelFormat::Yuv420p;
        s.width = current_.width;
        s.height = current_.height;
        s.frameRate = rate;
        s.timeBase = timeBase;
        info_.streams.push_back(std::move(s));
    }
    if (current_.depth) {
        hal::StreamInfo s;
        s.index = static_cast<int>(info_.streams.size());
        s.kind = hal::StreamKind::Depth;
        s.title = "depth";
        s.codec = hal::CodecId::Mock;
        s.format = current_.depthBits == 8 ? hal::PixelFormat::Gray8 : hal::PixelFormat::Gray16;
        s.width = current_.width;
        s.height = current_.height;
        s.frameRate = rate;
        s.timeBase = timeBase;
        s.depth.nearMetres = current_.nearMetres;
        s.depth.farMetres = current_.farMetres;
        s.depth.mapping = "inverse";
        s.depth.bits = current_.depthBits;
        info_.streams.push_back(std::move(s));
    }
    info_.duration = framePts(static_cast<std::uint64_t>(current_.frames), current_.fps);
    info_.seekable = current_.seekable;
    buffer_.assign(kMockPacketMaxBytes, 0);
    next_ = 0;
    packetsRead_ = 0;
    return ok();
}

void MockMediaSource::closeDevice() noexcept
{
    info_ = {};
}

Result<hal::Packet> MockMediaSource::readPacketDevice()
{
    const auto streams = static_cast<std::uint64_t>(streamCount());
    const std::uint64_t frame = next_ / streams;
    if (frame >= static_cast<std::uint64_t>(current_.frames))
        return unexpected(Errc::EndOfStream, "End of mock media");
    if (next_ >= truncateAt_)
        return unexpected(Errc::Io, "Failed to read packet: truncated file");

    const hal::StreamInfo &stream = info_.streams[static_cast<std::size_t>(next_ % streams)];
    const bool keyframe = frame % static_cast<std::uint64_t>(current_.gop) == 0;
    const std::size_t size =
        writeMockPacket(buffer_.data(), stream.kind, static_cast<std::uint32_t>(frame),
                        current_.width, current_.height, keyframe);
    if (next_ == corruptAt_)
        buffer_[size - 1] ^= 0x5a; // damage the payload, keep the header readable

    hal::Packet p;
    p.streamIndex = stream.index;
    p.data = buffer_.data();
    p.size = size;
    p.pts = framePts(frame, current_.fps) + (frame >= jumpFrame_ ? jumpOffset_ : hal::Pts{0});
    p.dts = p.pts;
    p.keyframe = keyframe;
    ++next_;
    ++packetsRead_;
    return p;
}

Result<void> MockMediaSource::seekDevice(hal::Pts position)
{
    const std::int64_t ns = position.count(); // within [0, duration] (the base clamps it)
    auto frame = static_cast<std::uint64_t>(ns / 1'000'000'000 * current_.fps +
                                            ns % 1'000'000'000 * current_.fps / 1'000'000'000);
    const auto last = static_cast<std::uint64_t>(current_.frames - 1);
    if (frame > last)
        frame = last;
    frame -= frame % static_cast<std::uint64_t>(current_.gop);
    next_ = frame * static_cast<std::uint64_t>(streamCount());
    return ok();
}

} // namespace depthtouch::drivers
