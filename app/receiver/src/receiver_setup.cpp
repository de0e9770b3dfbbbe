#include <cstdint>
#include <string>
#include <utility>

#include "depthtouch/platform/log.h"
#include "receiver_impl.h"

DT_LOG_CATEGORY(Receiver)

// The receiver's setup: which streams are color, depth and material, and their decoders and stores.

namespace depthtouch::receiver {

namespace {

bool isGray(hal::PixelFormat f) noexcept
{
    return f == hal::PixelFormat::Gray8 || f == hal::PixelFormat::Gray10 ||
           f == hal::PixelFormat::Gray16;
}

hal::Pts periodOf(const hal::Rational &rate) noexcept
{
    if (rate.num <= 0 || rate.den <= 0)
        return hal::Pts{0};
    const double p = 1e9 * static_cast<double>(rate.den) / static_cast<double>(rate.num);
    return p >= 1e5 && p <= 1e10 ? hal::Pts(static_cast<std::int64_t>(p + 0.5)) : hal::Pts{0};
}

} // namespace

void Receiver::Impl::note(std::string text)
{
    DT_LOG(Receiver, Warning, "%s", text.c_str());
    info.notes.push_back(std::move(text));
}

Result<void> Receiver::Impl::setUpStream(Stream &s, int index, PairStream which,
                                         const DecoderFactory &makeDecoder)
{
    const hal::StreamInfo &si = source->info().streams[static_cast<std::size_t>(index)];
    const bool material = s.material; // set by setUpMaterial()
    const bool depth = !material && which == PairStream::Depth;
    s.name = material ? "material" : depth ? "depth" : "color";
    const std::string name = std::string(s.name) + " stream " + std::to_string(index) + " (" +
                             hal::codecName(si.codec) + ", " + std::to_string(si.width) + "x" +
                             std::to_string(si.height) + ")";
    if (si.width < 1 || si.height < 1 || si.width > cfg.maxWidth || si.height > cfg.maxHeight) {
        note(name + " left out: frame size outside 1x1.." + std::to_string(cfg.maxWidth) + "x" +
             std::to_string(cfg.maxHeight));
        return unexpected(Errc::InvalidArgument, "Frame size of the stream is zero or too large");
    }
    hal::StreamConfig sc = hal::StreamConfig::fromStream(si);
    sc.kind = depth ? hal::StreamKind::Depth : hal::StreamKind::Color;
    // Gray H.264 decodes as 4:2:0: its luma is the depth. Depth of 9 to 16 bits comes out as Gray16
    // (10-bit nearness scaled to the full 16-bit range), the format the player, the stereo renderer
    // and the haptic renderer read.
    if (depth && (!isGray(sc.format) || sc.format == hal::PixelFormat::Gray10))
        sc.format = si.depth.bits > 8 || sc.format == hal::PixelFormat::Gray10
                        ? hal::PixelFormat::Gray16
                        : hal::PixelFormat::Gray8;
    if (!depth && sc.format == hal::PixelFormat::Unknown)
        sc.format = hal::PixelFormat::Yuv420p;
    if (material) // RGB24 codes (scene/material.h); H.264 gbrp converts bit-exact
        sc.format = hal::PixelFormat::Rgb24;

    // Material: the track's queue (window + 3), the frame being filled, and two per paired frame
    // held by the receiver (pending) or downstream.
    const int frames = material ? cfg.pairingWindow + 6 + 2 * cfg.consumerFrames
                       : depth  ? cfg.pairingWindow + 5 + 2 * cfg.consumerFrames
                                : cfg.pairingWindow + 4 + cfg.consumerFrames;
    const std::size_t bytes =
        hal::imageBytes(sc.format, sc.width, sc.height) * static_cast<std::size_t>(frames);
    if (bytes == 0 || bytes > cfg.maxPoolBytes) {
        note(name + " left out: its frames need " + std::to_string(bytes >> 20) +
             " MiB, more than the receiver's bound");
        return unexpected(Errc::OutOfResources, "The stream's frames exceed the memory bound");
    }
    auto dec = makeDecoder(si);
    if (!dec) {
        note(name + " left out: no decoder (" + dec.error().what + ")");
        return unexpected(dec.error());
    }
    if (auto r = (*dec)->configure(sc); !r) {
        note(name + " left out: the decoder refused it (" + r.error().what + ")");
        return r;
    }
    if (auto r = s.store.allocate(frames, sc.format, sc.width, sc.height); !r) {
        note(name + " left out: cannot allocate its frames");
        return r;
    }
    s.used = true;
    s.which = which;
    s.info = si;
    s.decoder = std::move(*dec);
    if (!material)
        (depth ? info.depthFormat : info.colorFormat) = sc.format;
    if (depth)
        info.depthHoleBelow = depthHoleBelow(si, sc.format);
    return ok();
}

void Receiver::Impl::setUpMaterial(const DecoderFactory &makeDecoder)
{
    const int index = info.roles.material;
    if (index < 0)
        return;
    const hal::StreamInfo &si = source->info().streams[static_cast<std::size_t>(index)];
    const std::string name = "material stream " + std::to_string(index);
    if (!info.hasDepth) {
        note(name + " left out: no depth stream to lay it on");
        return;
    }
    if (si.width != info.depth.width || si.height != info.depth.height) {
        note(name + " left out: its size " + std::to_string(si.width) + "x" +
             std::to_string(si.height) + " differs from the depth's " +
             std::to_string(info.depth.width) + "x" + std::to_string(info.depth.height) +
             " (playing without materials)");
        return;
    }
    Stream &s = streams[2];
    s.material = true;
    if (!setUpStream(s, index, PairStream::Depth, makeDecoder))
        return; // noted by setUpStream(): the file plays without materials
    info.hasMaterial = true;
    info.material = s.info;
}

Result<void> Receiver::Impl::setUp(const DecoderFactory &makeDecoder)
{
    const hal::MediaInfo &mi = source->info();
    info.duration = mi.duration;
    info.roles = identifyStreams(mi, cfg.single);
    for (const std::string &n : info.roles.notes)
        note(n);
    if (info.roles.color >= 0)
        if (auto r = setUpStream(streams[0], info.roles.color, PairStream::Color, makeDecoder); !r)
            lastRejection = r.error();
    if (info.roles.depth >= 0)
        if (auto r = setUpStream(streams[1], info.roles.depth, PairStream::Depth, makeDecoder); !r)
            lastRejection = r.error();
    info.hasColor = streams[0].used;
    info.hasDepth = streams[1].used;
    if (!info.hasColor && !info.hasDepth)
        return unexpected(lastRejection);
    if (cfg.requireDepth && !info.hasDepth)
        return unexpected(Errc::NotSupported, "The input has no usable depth stream");
    if (cfg.requireColor && !info.hasColor)
        return unexpected(Errc::NotSupported, "The input has no usable color stream");
    if (info.hasColor)
        info.color = streams[0].info;
    if (info.hasDepth)
        info.depth = streams[1].info;
    setUpMaterial(makeDecoder);
    info.mode = info.hasColor && info.hasDepth ? ReceiverMode::ColorAndDepth
                : info.hasColor                ? ReceiverMode::ColorOnly
                                               : ReceiverMode::DepthOnly;
    if (info.mode == ReceiverMode::ColorOnly)
        note("no depth stream: color only (play shows flat 2D, haptics off)");
    if (info.mode == ReceiverMode::DepthOnly)
        note("no color stream: depth only");

    const PairerConfig pc = PairerConfig::forStreams(
        info.hasColor, info.hasDepth, info.hasColor ? periodOf(info.color.frameRate) : hal::Pts{0},
        info.hasDepth ? periodOf(info.depth.frameRate) : hal::Pts{0}, cfg.pairingWindow);
    const hal::Pts cp = pc.colorPeriod;
    const hal::Pts dp = pc.depthPeriod;
    if (info.hasColor && info.hasDepth && info.color.frameRate.den != 0 &&
        info.depth.frameRate.den != 0 && cp != dp)
        note("color and depth frame rates differ (" +
             std::to_string(info.color.frameRate.toDouble()) + " and " +
             std::to_string(info.depth.frameRate.toDouble()) +
             " fps): depth frames are reused or skipped to follow the color");
    info.colorPeriod = cp;
    info.depthPeriod = dp;
    pairer = std::make_unique<Pairer>(pc);
    info.tolerance = pairer->tolerance();
    if (info.hasMaterial)
        materials = std::make_unique<MaterialTrack>(cfg.pairingWindow, info.tolerance, dp);
    return ok();
}

} // namespace depthtouch::receiver
