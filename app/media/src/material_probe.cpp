/// \file
/// \brief probeMaterialStream(): the material stream of a file and the ranges of its first frame
/// (see material_track.h).

#include <algorithm>
#include <cstring>
#include <string>

extern "C" {
#include <libavutil/frame.h>
}

#include "media_libav.h"
#include "material_stream.h"
#include "depthtouch/media/material_track.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::media {

using namespace detail;

namespace detail {

int findMaterialStream(const AVFormatContext &fmt, std::string &from)
{
    int videoOrdinal = 0;
    int third = -1;
    for (unsigned i = 0; i < fmt.nb_streams; ++i) {
        const AVStream &st = *fmt.streams[i];
        if (st.codecpar->codec_type != AVMEDIA_TYPE_VIDEO)
            continue;
        const AVDictionaryEntry *title = av_dict_get(st.metadata, "title", nullptr, 0);
        const AVDictionaryEntry *handler = av_dict_get(st.metadata, "handler_name", nullptr, 0);
        if (title != nullptr && std::strcmp(title->value, scene::kMaterialTitle) == 0) {
            from = "title";
            return static_cast<int>(i);
        }
        if (handler != nullptr && std::strcmp(handler->value, scene::kMaterialTitle) == 0) {
            from = "MP4 handler name";
            return static_cast<int>(i);
        }
        if (videoOrdinal++ == 2)
            third = static_cast<int>(i);
    }
    // MPEG-TS carries no titles: DepthTouch writes color, depth, material in that order.
    const bool ts = std::strcmp(fmt.iformat->name, "mpegts") == 0;
    if (ts && third >= 0 && fmt.streams[third]->codecpar->format == AV_PIX_FMT_GBRP) {
        from = "MPEG-TS order";
        return third;
    }
    return -1;
}

int videoStreamCount(const AVFormatContext &fmt) noexcept
{
    int n = 0;
    for (unsigned i = 0; i < fmt.nb_streams; ++i)
        n += fmt.streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO ? 1 : 0;
    return n;
}

} // namespace detail

namespace {

/// \return whether x264's settings in \a frame's unregistered SEI say lossless (constant QP 0);
/// nullopt when the frame carries none.
std::optional<bool> x264Lossless(const AVFrame &frame)
{
    for (int i = 0; i < frame.nb_side_data; ++i) {
        const AVFrameSideData &sd = *frame.side_data[i];
        if (sd.type != AV_FRAME_DATA_SEI_UNREGISTERED || sd.size <= 16)
            continue;
        // 16 bytes of UUID, then x264's text ("x264 - core … options: … rc=cqp … qp=0 …").
        const std::string text(reinterpret_cast<const char *>(sd.data) + 16, sd.size - 16);
        if (text.find("x264") == std::string::npos)
            continue;
        const std::size_t qp = text.find(" qp=0");
        const std::size_t after = qp + 5;
        return text.find("rc=cqp") != std::string::npos && qp != std::string::npos &&
               (after >= text.size() || text[after] == ' ' || text[after] == '\0');
    }
    return std::nullopt;
}

/// Decodes the first frame of stream \a index into \a frame. \return false when none decodes.
bool decodeFirstFrame(AVFormatContext &fmt, int index, AVCodecContext &codec, AVFrame &frame)
{
    PacketPtr pkt(av_packet_alloc());
    if (!pkt)
        return false;
    bool draining = false;
    for (int packets = 0; packets < 10000;) {
        if (!draining) {
            const int r = av_read_frame(&fmt, pkt.get());
            if (r < 0) {
                draining = true;
                (void)avcodec_send_packet(&codec, nullptr);
            } else if (pkt->stream_index != index) {
                av_packet_unref(pkt.get());
                continue;
            } else {
                ++packets;
                (void)avcodec_send_packet(&codec, pkt.get());
                av_packet_unref(pkt.get());
            }
        }
        const int r = avcodec_receive_frame(&codec, &frame);
        if (r == 0)
            return true;
        if (r != AVERROR(EAGAIN))
            return false;
        if (draining)
            return false;
    }
    return false;
}

/// The smallest and largest code of each plane of a gbrp \a frame, as values.
void measureRanges(const AVFrame &frame, MaterialStreamInfo &out)
{
    // gbrp: plane 0 is G, 1 is B, 2 is R.
    static constexpr int kPlaneOf[3] = {2, 0, 1};
    static constexpr double kScale[3] = {scene::kStiffnessScalePerCode, scene::kFrictionPerCode,
                                         scene::kFrictionPerCode};
    for (int c = 0; c < 3; ++c) {
        int lo = 255;
        int hi = 0;
        for (int y = 0; y < frame.height; ++y) {
            const std::uint8_t *row = frame.data[kPlaneOf[c]] + y * frame.linesize[kPlaneOf[c]];
            const auto [mn, mx] = std::minmax_element(row, row + frame.width);
            lo = std::min(lo, static_cast<int>(*mn));
            hi = std::max(hi, static_cast<int>(*mx));
        }
        out.minValue[c] = lo * kScale[c];
        out.maxValue[c] = hi * kScale[c];
    }
}

} // namespace

Result<std::optional<MaterialStreamInfo>> probeMaterialStream(const std::string &path)
{
    quietFfmpegLog();
    AVFormatContext *raw = nullptr;
    if (avformat_open_input(&raw, path.c_str(), nullptr, nullptr) < 0)
        return unexpected(Errc::Io, "Failed to open the file");
    InputContextPtr fmt(raw);
    if (avformat_find_stream_info(fmt.get(), nullptr) < 0)
        return unexpected(Errc::InvalidArgument, "Failed to read the streams");
    MaterialStreamInfo info;
    info.index = findMaterialStream(*fmt, info.titleFrom);
    if (info.index < 0)
        return std::optional<MaterialStreamInfo>{};
    const AVStream &st = *fmt->streams[info.index];
    const AVCodecParameters &par = *st.codecpar;
    info.width = par.width;
    info.height = par.height;
    info.codec = avcodec_get_name(par.codec_id);
    const char *pf = av_get_pix_fmt_name(static_cast<AVPixelFormat>(par.format));
    info.pixelFormat = pf != nullptr ? pf : "unknown";
    info.tagsPresent = av_dict_get(st.metadata, scene::kMaterialPlanesTag, nullptr, 0) != nullptr &&
                       av_dict_get(st.metadata, scene::kMaterialScalesTag, nullptr, 0) != nullptr;

    const AVCodec *dec = avcodec_find_decoder(par.codec_id);
    CodecContextPtr codec(dec != nullptr ? avcodec_alloc_context3(dec) : nullptr);
    FramePtr frame(av_frame_alloc());
    if (!codec || !frame || avcodec_parameters_to_context(codec.get(), &par) < 0 ||
        avcodec_open2(codec.get(), dec, nullptr) < 0)
        return std::optional<MaterialStreamInfo>{info};
    discardOtherStreams(*fmt, info.index);
    if (decodeFirstFrame(*fmt, info.index, *codec, *frame)) {
        info.lossless = x264Lossless(*frame);
        if (frame->format == AV_PIX_FMT_GBRP) {
            measureRanges(*frame, info);
            info.decoded = true;
        }
    }
    return std::optional<MaterialStreamInfo>{info};
}

} // namespace depthtouch::media
