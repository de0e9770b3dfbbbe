/// \file
/// \brief Image sequences decoded by the media source (see still_image.h).

#include "still_image.h"

namespace depthtouch::drivers::ffmpeg {

av::CodecContextPtr openStillImageDecoder(const AVCodecParameters &par) noexcept
{
    const AVCodec *codec = avcodec_find_decoder(par.codec_id);
    if (codec == nullptr)
        return {};
    av::CodecContextPtr dec(avcodec_alloc_context3(codec));
    if (!dec || avcodec_parameters_to_context(dec.get(), &par) < 0 ||
        avcodec_open2(dec.get(), codec, nullptr) < 0)
        return {};
    return dec;
}

Result<void> decodeStillImage(AVCodecContext &dec, const AVPacket &packet, AVFrame &frame,
                              const hal::StreamInfo &si, std::vector<std::uint8_t> &raw,
                              av::SwsPtr &sws)
{
    avcodec_flush_buffers(&dec);
    int d = avcodec_send_packet(&dec, &packet);
    if (d >= 0)
        d = avcodec_receive_frame(&dec, &frame);
    if (d == AVERROR(EAGAIN)) {
        avcodec_send_packet(&dec, nullptr);
        d = avcodec_receive_frame(&dec, &frame);
    }
    if (d < 0)
        return unexpected(Errc::Io, "Failed to decode an image of the sequence", AVUNERROR(d));
    raw.resize(hal::imageBytes(si.format, si.width, si.height));
    hal::ImageView view;
    view.width = si.width;
    view.height = si.height;
    view.format = si.format;
    std::uint8_t *base = raw.data();
    for (int plane = 0; plane < hal::planeCount(si.format); ++plane) {
        const hal::PlaneLayout l = hal::planeLayout(si.format, si.width, si.height, plane);
        view.planes[static_cast<std::size_t>(plane)] = {base, l.rowBytes};
        base += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
    }
    auto c = copyFrame(frame, view, sws);
    av_frame_unref(&frame);
    if (!c)
        return unexpected(Errc::Io, "An image of the sequence differs in size or format");
    return ok();
}

} // namespace depthtouch::drivers::ffmpeg
