// YUYV → RGB with libswscale, MJPEG → RGB with libavcodec's mjpeg decoder and libswscale.
#include "color_converter.h"

#include <linux/videodev2.h>

#include <cstring>
#include <vector>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/pixfmt.h>
#include <libswscale/swscale.h>
}

#include "depthtouch/av/av_handles.h"

namespace depthtouch::drivers::v4l2 {

namespace {

class FfmpegColorConverter final : public ColorConverter {
public:
    FfmpegColorConverter(std::uint32_t fourcc, int width, int height)
        : fourcc_(fourcc), width_(width), height_(height)
    {
    }

    Result<void> init()
    {
        av_log_set_level(AV_LOG_FATAL);
        if (fourcc_ == V4L2_PIX_FMT_MJPEG) {
            const AVCodec *codec = avcodec_find_decoder(AV_CODEC_ID_MJPEG);
            if (codec == nullptr)
                return unexpected(Errc::NotSupported, "libavcodec has no MJPEG decoder");
            ctx_.reset(avcodec_alloc_context3(codec));
            packet_.reset(av_packet_alloc());
            frame_.reset(av_frame_alloc());
            if (!ctx_ || !packet_ || !frame_)
                return unexpected(Errc::OutOfResources, "Failed to allocate the MJPEG decoder");
            ctx_->thread_count = 1;
            if (avcodec_open2(ctx_.get(), codec, nullptr) < 0)
                return unexpected(Errc::NotSupported, "Failed to open the MJPEG decoder");
            return ok();
        }
        if (fourcc_ != V4L2_PIX_FMT_YUYV)
            return unexpected(Errc::NotSupported, "No RGB conversion for this V4L2 color format");
        return ok();
    }

    Result<void> convert(const std::uint8_t *data, std::size_t bytes, int bytesPerLine,
                         const hal::ImageView &dst) noexcept override
    {
        uint8_t *dstData[4] = {dst.planes[0].data, nullptr, nullptr, nullptr};
        int dstStride[4] = {dst.planes[0].strideBytes, 0, 0, 0};
        if (fourcc_ == V4L2_PIX_FMT_YUYV) {
            if (!scaler(AV_PIX_FMT_YUYV422, false))
                return unexpected(Errc::OutOfResources, "Failed to set up libswscale");
            const uint8_t *src[4] = {data, nullptr, nullptr, nullptr};
            const int srcStride[4] = {bytesPerLine, 0, 0, 0};
            if (bytes < static_cast<std::size_t>(bytesPerLine) * static_cast<std::size_t>(height_))
                return unexpected(Errc::Io, "YUYV buffer shorter than its format");
            sws_scale(sws_.get(), src, srcStride, 0, height_, dstData, dstStride);
            return ok();
        }
        // MJPEG: libavcodec reads up to AV_INPUT_BUFFER_PADDING_SIZE bytes past the payload.
        try {
            padded_.assign(data, data + bytes);
            padded_.resize(bytes + AV_INPUT_BUFFER_PADDING_SIZE, 0);
        } catch (...) {
            return unexpected(Errc::OutOfResources, "Failed to copy the JPEG");
        }
        packet_->data = padded_.data();
        packet_->size = static_cast<int>(bytes);
        const int sent = avcodec_send_packet(ctx_.get(), packet_.get());
        packet_->data = nullptr;
        packet_->size = 0;
        if (sent < 0)
            return unexpected(Errc::Io, "Failed to decode the MJPEG buffer");
        if (avcodec_receive_frame(ctx_.get(), frame_.get()) < 0)
            return unexpected(Errc::Io, "Failed to decode the MJPEG buffer");
        Result<void> r = ok();
        bool fullRange = false;
        const AVPixelFormat src = av::dejpeg(static_cast<AVPixelFormat>(frame_->format), fullRange);
        if (frame_->width != width_ || frame_->height != height_ ||
            (frame_->decode_error_flags != 0))
            r = unexpected(Errc::Io, "MJPEG buffer has the wrong size or is damaged");
        else if (!scaler(src, fullRange))
            r = unexpected(Errc::Io, "No conversion from the JPEG's pixel format");
        else
            sws_scale(sws_.get(), frame_->data, frame_->linesize, 0, height_, dstData, dstStride);
        av_frame_unref(frame_.get());
        return r;
    }

private:
    bool scaler(AVPixelFormat src, bool fullRange) noexcept
    {
        SwsContext *s =
            sws_getCachedContext(sws_.release(), width_, height_, src, width_, height_,
                                 AV_PIX_FMT_RGB24, SWS_BILINEAR, nullptr, nullptr, nullptr);
        sws_.reset(s);
        if (s == nullptr)
            return false;
        if (fullRange != fullRange_) {
            av::setSwsRanges(s, fullRange ? 1 : 0, 1);
            fullRange_ = fullRange;
        }
        return true;
    }

    const std::uint32_t fourcc_;
    const int width_;
    const int height_;
    av::CodecContextPtr ctx_;
    av::PacketPtr packet_;
    av::FramePtr frame_;
    av::SwsPtr sws_;
    bool fullRange_ = false;
    std::vector<std::uint8_t> padded_;
};

} // namespace

bool canConvertToRgb(std::uint32_t fourcc) noexcept
{
    return fourcc == V4L2_PIX_FMT_YUYV ||
           (fourcc == V4L2_PIX_FMT_MJPEG && avcodec_find_decoder(AV_CODEC_ID_MJPEG) != nullptr);
}

Result<std::unique_ptr<ColorConverter>> makeColorConverter(std::uint32_t fourcc, int width,
                                                           int height)
{
    auto c = std::make_unique<FfmpegColorConverter>(fourcc, width, height);
    DT_TRY(c->init());
    return std::unique_ptr<ColorConverter>(std::move(c));
}

} // namespace depthtouch::drivers::v4l2
