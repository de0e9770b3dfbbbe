/// \file
/// \brief Image file I/O through libavformat, libavcodec and libswscale (see image_io.h).

#include "depthtouch/media/image_io.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "media_libav.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Media)

namespace depthtouch::media {

namespace {

using detail::AvErrorText;
using detail::CodecContextPtr;
using detail::FramePtr;
using detail::nativeLayout;
using detail::PacketPtr;
using detail::SwsPtr;
using FormatContextPtr = detail::InputContextPtr;

/// Converts (or copies, when the layouts match) a picture between two buffers of the same size.
Result<void> convert(const std::uint8_t *const srcData[4], const int srcStride[4],
                     AVPixelFormat srcFmt, bool srcFullRange, std::uint8_t *const dstData[4],
                     const int dstStride[4], AVPixelFormat dstFmt, int width, int height)
{
    if (srcFmt == dstFmt) {
        // Only our packed single-plane layouts reach here (dstFmt is always one of them).
        const int rowBytes = av_image_get_linesize(dstFmt, width, 0);
        if (rowBytes < 0)
            return unexpected(Errc::InvalidArgument, "Invalid image size");
        av_image_copy_plane(dstData[0], dstStride[0], srcData[0], srcStride[0], rowBytes, height);
        return ok();
    }
    // Exact sizes, so SWS_POINT only selects the cheapest unscaled path; BITEXACT + ACCURATE_RND
    // keep it deterministic across CPUs.
    SwsPtr sws(sws_getContext(width, height, srcFmt, width, height, dstFmt,
                              SWS_POINT | SWS_BITEXACT | SWS_ACCURATE_RND, nullptr, nullptr,
                              nullptr));
    if (!sws) {
        DT_LOG(Media, Warning, "Failed to convert %s to %s", av_get_pix_fmt_name(srcFmt),
               av_get_pix_fmt_name(dstFmt));
        return unexpected(Errc::NotSupported, "No pixel format conversion for this image");
    }
    if (srcFullRange)
        detail::setSwsRanges(sws.get(), 1);
    const int lines = sws_scale(sws.get(), srcData, srcStride, 0, height, dstData, dstStride);
    if (lines != height)
        return unexpected(Errc::InvalidArgument, "Failed to convert the image's pixel format");
    return ok();
}

/// Receives one decoded frame, draining the decoder at end of input.
int receiveFrame(AVCodecContext *codec, AVFrame *frame, bool &drained)
{
    int ret = avcodec_receive_frame(codec, frame);
    if (ret == AVERROR(EAGAIN) && !drained) {
        drained = true;
        ret = avcodec_send_packet(codec, nullptr);
        if (ret < 0)
            return ret;
        ret = avcodec_receive_frame(codec, frame);
    }
    return ret;
}

} // namespace

Result<Image> readImage(const std::string &path, std::optional<PixelFormat> format)
{
    AVFormatContext *rawFmt = nullptr;
    // No forced demuxer: probing the content picks the image2 family's demuxer for the actual
    // format (png_pipe, jpeg_pipe, pgm_pipe, ...), so a misnamed file still reads and a non-image
    // is refused.
    int ret = avformat_open_input(&rawFmt, path.c_str(), nullptr, nullptr);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to open image %s: %s", path.c_str(), AvErrorText(ret).text);
        return unexpected(ret == AVERROR_INVALIDDATA ? Errc::InvalidArgument : Errc::Io,
                          "Failed to open image file");
    }
    FormatContextPtr fmt(rawFmt);
    if ((ret = avformat_find_stream_info(fmt.get(), nullptr)) < 0) {
        DT_LOG(Media, Warning, "Failed to read image %s: %s", path.c_str(), AvErrorText(ret).text);
        return unexpected(Errc::InvalidArgument, "Failed to read image stream");
    }
    const AVCodec *decoder = nullptr;
    const int index = av_find_best_stream(fmt.get(), AVMEDIA_TYPE_VIDEO, -1, -1, &decoder, 0);
    if (index < 0 || decoder == nullptr) {
        DT_LOG(Media, Warning, "Failed to find a picture in %s: %s", path.c_str(),
               AvErrorText(index).text);
        return unexpected(index == AVERROR_DECODER_NOT_FOUND ? Errc::NotSupported
                                                             : Errc::InvalidArgument,
                          "File holds no decodable picture");
    }
    const AVStream *stream = fmt->streams[index];

    CodecContextPtr codec(avcodec_alloc_context3(decoder));
    if (!codec)
        return unexpected(Errc::OutOfResources, "Failed to allocate decoder");
    if (avcodec_parameters_to_context(codec.get(), stream->codecpar) < 0)
        return unexpected(Errc::InvalidArgument, "Failed to configure decoder");
    codec->thread_count = 1;
    // Refuse damaged data instead of returning a partly grey picture.
    codec->err_recognition = AV_EF_EXPLODE | AV_EF_CRCCHECK;
    if ((ret = avcodec_open2(codec.get(), decoder, nullptr)) < 0) {
        DT_LOG(Media, Warning, "Failed to open decoder %s for %s: %s", decoder->name, path.c_str(),
               AvErrorText(ret).text);
        return unexpected(Errc::NotSupported, "Failed to open image decoder");
    }

    PacketPtr packet(av_packet_alloc());
    FramePtr frame(av_frame_alloc());
    if (!packet || !frame)
        return unexpected(Errc::OutOfResources, "Failed to allocate frame");

    bool drained = false;
    bool got = false;
    while (!got) {
        ret = av_read_frame(fmt.get(), packet.get());
        if (ret == AVERROR_EOF) {
            ret = receiveFrame(codec.get(), frame.get(), drained);
            if (ret < 0)
                break;
            got = true;
            break;
        }
        if (ret < 0)
            break;
        if (packet->stream_index != index) {
            av_packet_unref(packet.get());
            continue;
        }
        ret = avcodec_send_packet(codec.get(), packet.get());
        av_packet_unref(packet.get());
        if (ret < 0)
            break;
        ret = avcodec_receive_frame(codec.get(), frame.get());
        if (ret == 0)
            got = true;
        else if (ret != AVERROR(EAGAIN))
            break;
    }
    if (!got || (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0 || frame->decode_error_flags != 0) {
        DT_LOG(Media, Warning, "Failed to decode image %s: %s", path.c_str(),
               got ? "corrupt frame" : AvErrorText(ret).text);
        return unexpected(Errc::InvalidArgument, "Failed to decode image (corrupt or truncated)");
    }

    const auto srcFmtRaw = static_cast<AVPixelFormat>(frame->format);
    const PixelFormat want = format.value_or(nativeLayout(srcFmtRaw));
    Image image = Image::make(frame->width, frame->height, want);
    if (image.empty())
        return unexpected(Errc::InvalidArgument, "Image has no pixels");
    if (image.stride > static_cast<std::size_t>(INT32_MAX))
        return unexpected(Errc::InvalidArgument, "Image too wide");

    bool fullRange = false;
    AVPixelFormat srcFmt = detail::dejpeg(srcFmtRaw, fullRange);
    fullRange = fullRange || frame->color_range == AVCOL_RANGE_JPEG;
    std::uint8_t *dstData[4] = {image.data.data(), nullptr, nullptr, nullptr};
    const int dstStride[4] = {static_cast<int>(image.stride), 0, 0, 0};
    const auto result = convert(frame->data, frame->linesize, srcFmt, fullRange, dstData, dstStride,
                                detail::toAvFormat(want), image.width, image.height);
    if (!result) {
        DT_LOG(Media, Warning, "Failed to convert image %s from %s to %s", path.c_str(),
               av_get_pix_fmt_name(srcFmtRaw), pixelFormatName(want));
        return unexpected(result.error());
    }
    return image;
}

Result<void> writePng(const std::string &path, const Image &image)
{
    if (image.empty() ||
        image.stride < static_cast<std::size_t>(image.width) *
                           static_cast<std::size_t>(bytesPerPixel(image.format)) ||
        image.data.size() < image.stride * static_cast<std::size_t>(image.height) ||
        image.stride > static_cast<std::size_t>(INT32_MAX))
        return unexpected(Errc::InvalidArgument, "Image is empty or its buffer is inconsistent");

    const AVCodec *encoder = avcodec_find_encoder(AV_CODEC_ID_PNG);
    if (encoder == nullptr)
        return unexpected(Errc::NotSupported, "FFmpeg has no PNG encoder");
    // PNG stores 16-bit samples big-endian: the encoder takes gray16be.
    const AVPixelFormat pngFmt = image.format == PixelFormat::Gray8    ? AV_PIX_FMT_GRAY8
                                 : image.format == PixelFormat::Gray16 ? AV_PIX_FMT_GRAY16BE
                                                                       : AV_PIX_FMT_RGB24;
    CodecContextPtr codec(avcodec_alloc_context3(encoder));
    FramePtr frame(av_frame_alloc());
    PacketPtr packet(av_packet_alloc());
    if (!codec || !frame || !packet)
        return unexpected(Errc::OutOfResources, "Failed to allocate PNG encoder");
    codec->width = image.width;
    codec->height = image.height;
    codec->pix_fmt = pngFmt;
    codec->time_base = AVRational{1, 25};
    codec->thread_count = 1;
    int ret = avcodec_open2(codec.get(), encoder, nullptr);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to open PNG encoder for %s: %s", path.c_str(),
               AvErrorText(ret).text);
        return unexpected(Errc::NotSupported, "Failed to open PNG encoder");
    }

    frame->format = pngFmt;
    frame->width = image.width;
    frame->height = image.height;
    if (av_frame_get_buffer(frame.get(), 0) < 0)
        return unexpected(Errc::OutOfResources, "Failed to allocate PNG frame");
    const std::uint8_t *srcData[4] = {image.data.data(), nullptr, nullptr, nullptr};
    const int srcStride[4] = {static_cast<int>(image.stride), 0, 0, 0};
    DT_TRY(convert(srcData, srcStride, detail::toAvFormat(image.format), false, frame->data,
                   frame->linesize, pngFmt, image.width, image.height));

    if ((ret = avcodec_send_frame(codec.get(), frame.get())) < 0 ||
        (ret = avcodec_receive_packet(codec.get(), packet.get())) < 0) {
        DT_LOG(Media, Warning, "Failed to encode PNG %s: %s", path.c_str(), AvErrorText(ret).text);
        return unexpected(Errc::InvalidArgument, "Failed to encode PNG");
    }

    // Written under a temporary name beside it and renamed when complete: a full disk never
    // leaves a cut or empty PNG under its name.
    const std::string_view bytes(reinterpret_cast<const char *>(packet->data),
                                 static_cast<std::size_t>(packet->size));
    if (auto w = platform::writeOutputFile(path, bytes); !w) {
        char why[160];
        DT_LOG(Media, Warning, "Failed to write %s: %s", path.c_str(),
               w.error().format(why, sizeof why));
        return unexpected(Errc::Io, "Failed to write image file", w.error().sysErrno);
    }
    return ok();
}

} // namespace depthtouch::media
