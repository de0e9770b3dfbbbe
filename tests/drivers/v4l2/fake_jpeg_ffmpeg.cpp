// MJPEG frames of the fake kernel: the YUYV pattern converted with libswscale and encoded with
// libavcodec's mjpeg encoder (a real JPEG, as a UVC camera sends).
#include "fake_v4l2_kernel.h"

#include <memory>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/frame.h>
#include <libswscale/swscale.h>
}

#include "depthtouch/av/av_handles.h"

namespace depthtouch::drivers::fake {

bool fakeJpegAvailable() noexcept
{
    return avcodec_find_encoder(AV_CODEC_ID_MJPEG) != nullptr;
}

std::vector<std::uint8_t> encodeFakeJpeg(const std::uint8_t *yuyv, int width, int height)
{
    const AVCodec *codec = avcodec_find_encoder(AV_CODEC_ID_MJPEG);
    if (codec == nullptr)
        return {};
    av::CodecContextPtr ctx(avcodec_alloc_context3(codec));
    av::FramePtr frame(av_frame_alloc());
    av::PacketPtr pkt(av_packet_alloc());
    if (!ctx || !frame || !pkt)
        return {};
    ctx->width = width;
    ctx->height = height;
    ctx->pix_fmt = AV_PIX_FMT_YUVJ422P;
    ctx->time_base = {1, 30};
    ctx->flags |= AV_CODEC_FLAG_QSCALE;
    ctx->global_quality = 2 * FF_QP2LAMBDA; // high quality: the tests compare pixels
    if (avcodec_open2(ctx.get(), codec, nullptr) < 0)
        return {};
    frame->width = width;
    frame->height = height;
    frame->format = AV_PIX_FMT_YUVJ422P;
    frame->quality = ctx->global_quality;
    if (av_frame_get_buffer(frame.get(), 0) < 0)
        return {};
    SwsContext *sws = sws_getContext(width, height, AV_PIX_FMT_YUYV422, width, height,
                                     AV_PIX_FMT_YUVJ422P, SWS_POINT, nullptr, nullptr, nullptr);
    if (sws == nullptr)
        return {};
    const std::uint8_t *src[4] = {yuyv, nullptr, nullptr, nullptr};
    const int srcStride[4] = {2 * width, 0, 0, 0};
    sws_scale(sws, src, srcStride, 0, height, frame->data, frame->linesize);
    sws_freeContext(sws);
    std::vector<std::uint8_t> out;
    if (avcodec_send_frame(ctx.get(), frame.get()) < 0 ||
        avcodec_receive_packet(ctx.get(), pkt.get()) < 0)
        return {};
    out.assign(pkt->data, pkt->data + pkt->size);
    return out;
}

} // namespace depthtouch::drivers::fake
