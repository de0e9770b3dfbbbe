/// \file
/// \brief Whether one rendition's streams decode as another's (see rendition_match.h).

#include "rendition_match.h"

#include <cstdio>
#include <cstring>

extern "C" {
#include <libavcodec/codec_par.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
}

namespace depthtouch::drivers::ffmpeg {

namespace {

/// \return the bits of a sample of \a par's pictures: bits_per_raw_sample when given, else its
/// pixel format's first component's; 0 when unknown.
int bitDepthOf(const AVCodecParameters &par) noexcept
{
    if (par.bits_per_raw_sample > 0)
        return par.bits_per_raw_sample;
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(static_cast<AVPixelFormat>(par.format));
    return d != nullptr ? d->comp[0].depth : 0;
}

/// \return whether \a par carries its parameter sets out of band (avcC/hvcC extradata, whose
/// configurationVersion byte is 1; Annex B extradata starts with a start code, 0).
bool outOfBandParameterSets(const AVCodecParameters &par) noexcept
{
    return par.extradata != nullptr && par.extradata_size > 0 && par.extradata[0] == 1;
}

/// \return "codec format N-bit" of a picture stream.
std::string videoOf(const AVCodecParameters &par)
{
    const char *format = av_get_pix_fmt_name(static_cast<AVPixelFormat>(par.format));
    return std::string(avcodec_get_name(par.codec_id)) + " " +
           (format != nullptr ? format : "unknown") + " " + std::to_string(bitDepthOf(par)) +
           "-bit";
}

/// \return "" when a picture stream \a b decodes with a decoder opened for \a a, else why not.
std::string videoMismatch(const AVCodecParameters &a, const AVCodecParameters &b)
{
    const bool formatsKnown = a.format >= 0 && b.format >= 0;
    const int depthA = bitDepthOf(a), depthB = bitDepthOf(b);
    if (a.codec_id != b.codec_id || (formatsKnown && a.format != b.format) ||
        (depthA > 0 && depthB > 0 && depthA != depthB))
        return videoOf(b) + " where the playing rendition's is " + videoOf(a);
    const bool outOfBand = outOfBandParameterSets(a) || outOfBandParameterSets(b);
    if (outOfBand &&
        (a.extradata_size != b.extradata_size ||
         std::memcmp(a.extradata, b.extradata, static_cast<std::size_t>(a.extradata_size)) != 0))
        return "coded with other out-of-band parameter sets (avcC/hvcC) than the playing "
               "rendition's";
    return "";
}

/// \return "" when a sound stream \a b decodes with a decoder opened for \a a, else why not.
std::string audioMismatch(const AVCodecParameters &a, const AVCodecParameters &b)
{
    if (a.codec_id == b.codec_id && a.sample_rate == b.sample_rate &&
        a.ch_layout.nb_channels == b.ch_layout.nb_channels)
        return "";
    const auto of = [](const AVCodecParameters &p) {
        return std::string(avcodec_get_name(p.codec_id)) + " " + std::to_string(p.sample_rate) +
               " Hz " + std::to_string(p.ch_layout.nb_channels) + " ch";
    };
    return of(b) + " where the playing rendition's is " + of(a);
}

} // namespace

int streamOfKind(const AVFormatContext &ctx, const AVProgram &p, AVMediaType type, int ordinal)
{
    for (unsigned k = 0; k < p.nb_stream_indexes; ++k) {
        const unsigned i = p.stream_index[k];
        if (i < ctx.nb_streams && ctx.streams[i]->codecpar->codec_type == type && ordinal-- == 0)
            return static_cast<int>(i);
    }
    return -1;
}

std::string renditionMismatch(const AVFormatContext &ctx, int playing, int other)
{
    if (playing < 0 || other < 0 || static_cast<unsigned>(playing) >= ctx.nb_programs ||
        static_cast<unsigned>(other) >= ctx.nb_programs)
        return "no such rendition";
    const AVProgram &a = *ctx.programs[playing];
    const AVProgram &b = *ctx.programs[other];
    for (const AVMediaType type : {AVMEDIA_TYPE_VIDEO, AVMEDIA_TYPE_AUDIO}) {
        const char *kind = type == AVMEDIA_TYPE_VIDEO ? "video" : "sound";
        for (int n = 0;; ++n) {
            const int ia = streamOfKind(ctx, a, type, n);
            if (ia < 0)
                break;
            const int ib = streamOfKind(ctx, b, type, n);
            const std::string stream = std::string(kind) + " stream " + std::to_string(n + 1);
            if (ib < 0)
                return "it has no " + stream;
            const AVCodecParameters &pa = *ctx.streams[ia]->codecpar;
            const AVCodecParameters &pb = *ctx.streams[ib]->codecpar;
            const std::string why =
                type == AVMEDIA_TYPE_VIDEO ? videoMismatch(pa, pb) : audioMismatch(pa, pb);
            if (!why.empty())
                return "its " + stream + " is " + why;
        }
    }
    return "";
}

} // namespace depthtouch::drivers::ffmpeg
