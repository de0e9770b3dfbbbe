/// \file
/// \brief The material track's frames, scaler, still source and stream settings (see
/// material_track.h).

#include "depthtouch/media/material_track.h"

#include <utility>

#include "media_libav.h"
#include "depthtouch/media/image_convert.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::media {

using namespace detail;

VideoEncoderConfig materialStreamConfig(const VideoEncoderConfig &base)
{
    VideoEncoderConfig mc = base;
    mc.codec = VideoCodec::H264Rgb;
    mc.lossless = true;
    mc.rate = {}; // lossless: no rate control
    mc.title = scene::kMaterialTitle;
    mc.tags = {{scene::kMaterialPlanesTag, scene::kMaterialPlanesValue},
               {scene::kMaterialScalesTag, scene::kMaterialScalesValue}};
    return mc;
}

// ---------------------------------------------------------------------------------------------
// MaterialScaler

struct MaterialScaler::Impl {
    SwsPtr sws;
    int srcW = 0, srcH = 0, dstW = 0, dstH = 0;
};

MaterialScaler::MaterialScaler() : impl_(std::make_unique<Impl>()) {}
MaterialScaler::~MaterialScaler() = default;

Result<Image> MaterialScaler::resize(const Image &src, int width, int height)
{
    if (src.empty() || src.format != PixelFormat::Rgb24 || width < 1 || height < 1)
        return unexpected(Errc::InvalidArgument, "Material resize needs an RGB24 picture");
    if (src.width == width && src.height == height)
        return src;
    Impl &s = *impl_;
    if (!s.sws || s.srcW != src.width || s.srcH != src.height || s.dstW != width ||
        s.dstH != height) {
        // Point sampling alone still filters RGB's chroma horizontally when shrinking; with full
        // chroma resolution in and out every output pixel is one input pixel (bit-exact).
        const int flags =
            SWS_POINT | SWS_FULL_CHR_H_INT | SWS_FULL_CHR_H_INP | SWS_BITEXACT | SWS_ACCURATE_RND;
        s.sws.reset(sws_getContext(src.width, src.height, AV_PIX_FMT_RGB24, width, height,
                                   AV_PIX_FMT_RGB24, flags, nullptr, nullptr, nullptr));
        if (!s.sws)
            return unexpected(Errc::NotSupported, "libswscale cannot resize the material");
        s.srcW = src.width;
        s.srcH = src.height;
        s.dstW = width;
        s.dstH = height;
    }
    Image out = Image::make(width, height, PixelFormat::Rgb24);
    const std::uint8_t *srcData[4] = {src.data.data(), nullptr, nullptr, nullptr};
    const int srcStride[4] = {static_cast<int>(src.stride), 0, 0, 0};
    std::uint8_t *dstData[4] = {out.data.data(), nullptr, nullptr, nullptr};
    const int dstStride[4] = {static_cast<int>(out.stride), 0, 0, 0};
    if (sws_scale(s.sws.get(), srcData, srcStride, 0, src.height, dstData, dstStride) != height)
        return unexpected(Errc::InvalidArgument, "libswscale failed to resize the material");
    return out;
}

// ---------------------------------------------------------------------------------------------
// MaterialTrack

Result<Image> MaterialTrack::next(int width, int height)
{
    if (!ended_) {
        auto f = source_.next(PixelFormat::Rgb24);
        if (f) {
            ++framesRead_;
            auto r = scaler_.resize(f->image, width, height);
            if (!r)
                return unexpected(r.error());
            last_ = std::move(*r);
            return last_;
        }
        if (f.error().code != Errc::EndOfStream)
            return unexpected(f.error());
        ended_ = true;
    }
    if (last_.empty())
        return unexpected(Errc::InvalidArgument, "The material input has no frame");
    // The last material holds; the output grid is fixed for the whole file.
    return last_;
}

Result<void> MaterialTrack::encodeNext(VideoEncoder &encoder, int width, int height,
                                       double ptsSeconds)
{
    auto codes = next(width, height);
    if (!codes)
        return unexpected(codes.error());
    return encoder.encode(*codes, ptsSeconds);
}

// ---------------------------------------------------------------------------------------------
// Still source

namespace {

class StillFrameSource final : public ConvertingFrameSource {
public:
    StillFrameSource(Image image, double fps, std::string description)
        : image_(std::move(image)), fps_(fps)
    {
        info_.width = image_.width;
        info_.height = image_.height;
        info_.fps = fps;
        info_.nativeFormat = image_.format;
        info_.frameCount = 0; // endless
        info_.description = std::move(description);
    }

    Result<SourceFrame> next(PixelFormat format, int width, int height) override
    {
        auto img = converter_.convert(image_, format, width, height);
        if (!img)
            return unexpected(img.error());
        SourceFrame f;
        f.image = std::move(*img);
        f.pts = static_cast<double>(frames_++) / fps_;
        return f;
    }

private:
    Image image_;
    double fps_;
    long long frames_ = 0;
};

} // namespace

std::unique_ptr<FrameSource> makeStillFrameSource(Image image, double fps, std::string description)
{
    return std::make_unique<StillFrameSource>(std::move(image), fps, std::move(description));
}

} // namespace depthtouch::media
