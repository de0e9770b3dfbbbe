/// \file
/// \brief The FFmpeg media source's description of an input's streams (ffmpeg_source_impl.h):
/// each video stream's role (colour, depth, material), format, size and rate, its depth tags
/// (hal/depth_tags.h) and still-image decoder, the duration, and the sound streams.

#include "ffmpeg_source_impl.h"

namespace depthtouch::drivers {

void FfmpegMediaSource::Impl::addStream(unsigned i, int videoStreams, int videoOrdinal,
                                        const AVDictionary *serviceTags)
{
    AVFormatContext *ctx = fmt.get();
    const AVStream &st = *ctx->streams[i];
    const AVCodecParameters &par = *st.codecpar;
    if (st.discard == AVDISCARD_ALL) // another rendition (hls_variants.h)
        return;
    if (par.codec_type == AVMEDIA_TYPE_AUDIO)
        addAudioStream(st);
    if (par.codec_type != AVMEDIA_TYPE_VIDEO)
        return;
    if ((st.disposition & AV_DISPOSITION_ATTACHED_PIC) != 0)
        return;
    hal::StreamInfo si;
    si.index = static_cast<int>(info.streams.size());
    si.containerIndex = static_cast<int>(i);
    const AVDictionaryEntry *title = av_dict_get(st.metadata, "title", nullptr, 0);
    const AVDictionaryEntry *handler = av_dict_get(st.metadata, "handler_name", nullptr, 0);
    if (title != nullptr) {
        si.title = title->value;
        si.titleFrom = "title";
    } else if (handler != nullptr && isRoleName(handler->value)) {
        si.title = handler->value;
        si.titleFrom = "MP4 handler name";
    } else if (serviceTags != nullptr && videoOrdinal < 2) {
        si.title = videoOrdinal == 0 ? "color" : "depth";
        si.titleFrom = serviceTagsFrom;
    }
    const AVPixelFormat pixfmt =
        si.title == "color" ? static_cast<AVPixelFormat>(par.format) : samplesFormatOf(par);
    if (si.title == "depth")
        si.kind = hal::StreamKind::Depth;
    else if (si.title == "color")
        si.kind = hal::StreamKind::Color;
    else
        si.kind =
            videoStreams == 1 && isGray(pixfmt) ? hal::StreamKind::Depth : hal::StreamKind::Color;
    si.codec = codecOf(par.codec_id);
    si.format = halFormatOf(pixfmt, si.kind);
    si.width = par.width;
    si.height = par.height;
    // A live input's average over its few probed frames is rough (29.92 for 30 was seen); the
    // rate of its timestamp steps is exact for a constant rate.
    const bool real = st.r_frame_rate.num > 0 && st.r_frame_rate.den > 0;
    const bool average = st.avg_frame_rate.num > 0 && st.avg_frame_rate.den > 0;
    AVRational rate = average && !(live && real) ? st.avg_frame_rate : st.r_frame_rate;
    if (rate.num > 0 && rate.den > 0)
        si.frameRate = {rate.num, rate.den};
    si.timeBase = {st.time_base.num, st.time_base.den};
    if (par.extradata != nullptr && par.extradata_size > 0)
        si.extradata.assign(par.extradata,
                            par.extradata + static_cast<std::size_t>(par.extradata_size));
    for (const char *key : hal::kDepthTagNames)
        hal::applyDepthTag(key, tagOf(st, *ctx, serviceTags, key), si.depth);

    Stream s;
    s.avIndex = static_cast<int>(i);
    if (rate.num > 0 && rate.den > 0)
        s.frameDuration = hal::Pts(av_rescale_q(1, av_inv_q(rate), kNanoseconds));
    if (si.codec == hal::CodecId::Unknown) {
        // A still-image codec (image sequence): decode here, deliver RawVideo packets.
        if (si.format == hal::PixelFormat::Unknown || si.width <= 0 || si.height <= 0)
            return;
        s.imageDecoder = openStillImageDecoder(par);
        if (!s.imageDecoder)
            return;
        si.codec = hal::CodecId::RawVideo;
        si.extradata.clear();
    }
    avToHal[i] = si.index;
    info.streams.push_back(std::move(si));
    streams.push_back(std::move(s));
}

void FfmpegMediaSource::Impl::readDuration() noexcept
{
    const AVFormatContext *ctx = fmt.get();
    if (ctx->duration != AV_NOPTS_VALUE && ctx->duration > 0) {
        info.duration = hal::Pts(av_rescale_q(ctx->duration, kMicroseconds, kNanoseconds));
    } else {
        for (const Stream &s : streams) {
            const AVStream &st = *ctx->streams[s.avIndex];
            if (st.duration != AV_NOPTS_VALUE)
                info.duration = std::max(
                    info.duration, hal::Pts(av_rescale_q(st.duration, st.time_base, kNanoseconds)));
        }
    }
}

void FfmpegMediaSource::Impl::addAudioStream(const AVStream &st)
{
    const AVCodecParameters &par = *st.codecpar;
    hal::AudioStreamInfo a;
    a.containerIndex = st.index;
    a.codec = avcodec_get_name(par.codec_id);
    a.sampleRate = par.sample_rate;
    a.channels = par.ch_layout.nb_channels;
    if (st.start_time != AV_NOPTS_VALUE)
        a.start = hal::Pts(av_rescale_q(st.start_time, st.time_base, kNanoseconds)) - start;
    // MKV gives no stream duration but libavformat's muxer writes a DURATION tag.
    const AVDictionaryEntry *tag = av_dict_get(st.metadata, "DURATION", nullptr, 0);
    std::int64_t tagged = 0;
    if (st.duration != AV_NOPTS_VALUE && st.duration > 0)
        a.duration = hal::Pts(av_rescale_q(st.duration, st.time_base, kNanoseconds));
    else if (tag != nullptr && av_parse_time(&tagged, tag->value, 1) == 0 && tagged > 0)
        a.duration = hal::Pts(av_rescale_q(tagged, kMicroseconds, kNanoseconds));
    const AVDictionaryEntry *lang = av_dict_get(st.metadata, "language", nullptr, 0);
    if (lang != nullptr && std::string_view(lang->value) != "und") // ISO 639-2 "undetermined"
        a.language = lang->value;
    if (par.extradata != nullptr && par.extradata_size > 0)
        a.extradata.assign(par.extradata, par.extradata + par.extradata_size);
    info.audio.push_back(std::move(a));
}

} // namespace depthtouch::drivers
