/// \file
/// \brief One rendition of an HLS multivariant playlist (see hls_variants.h).

#include "hls_variants.h"

#include <cstdlib>
#include <cstring>
#include <string>

extern "C" {
#include <libavformat/avformat.h>
}

namespace depthtouch::drivers::ffmpeg {

namespace {

constexpr int kMaxHeight = 8192;

/// A variant's height (its tallest video stream) and bit rate (`variant_bitrate`, 0 if absent).
struct Variant {
    int height = 0;
    long long bitRate = 0;
};

Variant variantOf(const AVFormatContext &ctx, const AVProgram &program) noexcept
{
    Variant v;
    for (unsigned k = 0; k < program.nb_stream_indexes; ++k) {
        const unsigned i = program.stream_index[k];
        if (i >= ctx.nb_streams)
            continue;
        const AVCodecParameters &par = *ctx.streams[i]->codecpar;
        if (par.codec_type == AVMEDIA_TYPE_VIDEO && par.height > v.height)
            v.height = par.height;
    }
    if (const AVDictionaryEntry *e = av_dict_get(program.metadata, "variant_bitrate", nullptr, 0))
        v.bitRate = std::strtoll(e->value, nullptr, 10);
    return v;
}

/// \return whether \a a is taller than \a b (or as tall at a higher bit rate).
bool taller(const Variant &a, const Variant &b) noexcept
{
    return a.height != b.height ? a.height > b.height : a.bitRate > b.bitRate;
}

/// \return whether variant \a a serves \a choice better than \a b: any with a video stream
/// serves better than one without.
bool better(const Variant &a, const Variant &b, const RenditionChoice &choice) noexcept
{
    if ((a.height > 0) != (b.height > 0)) // one without video (its playlist did not answer)
        return a.height > 0;
    if (choice.maxHeight < 0)
        return taller(b, a);
    if (choice.maxHeight == 0)
        return taller(a, b);
    const bool aFits = a.height <= choice.maxHeight;
    const bool bFits = b.height <= choice.maxHeight;
    if (aFits != bFits)
        return aFits;
    return aFits ? taller(a, b) : taller(b, a);
}

} // namespace

Result<RenditionChoice> parseRenditionChoice(std::string_view text)
{
    if (text == "auto")
        return RenditionChoice{0, true};
    if (text == "highest")
        return RenditionChoice{0};
    if (text == "lowest")
        return RenditionChoice{-1};
    const std::string s(text);
    char *end = nullptr;
    const long h = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || h < 1 || h > kMaxHeight)
        return unexpected(
            Errc::InvalidArgument,
            "ffmpeg option rendition must be auto, highest, lowest or a height 1..8192");
    return RenditionChoice{static_cast<int>(h)};
}

int keepOneVariant(AVFormatContext &ctx, const RenditionChoice &choice,
                   std::vector<hal::RenditionInfo> &renditions)
{
    renditions.clear();
    if (ctx.iformat == nullptr || std::strcmp(ctx.iformat->name, "hls") != 0 || ctx.nb_programs < 2)
        return -1;
    unsigned best = 0;
    for (unsigned p = 1; p < ctx.nb_programs; ++p)
        if (better(variantOf(ctx, *ctx.programs[p]), variantOf(ctx, *ctx.programs[best]), choice))
            best = p;
    for (unsigned i = 0; i < ctx.nb_streams; ++i)
        ctx.streams[i]->discard = AVDISCARD_ALL;
    for (unsigned p = 0; p < ctx.nb_programs; ++p) {
        const Variant v = variantOf(ctx, *ctx.programs[p]);
        int width = 0;
        for (unsigned k = 0; k < ctx.programs[p]->nb_stream_indexes; ++k) {
            const unsigned i = ctx.programs[p]->stream_index[k];
            if (i < ctx.nb_streams && ctx.streams[i]->codecpar->height == v.height &&
                ctx.streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO)
                width = ctx.streams[i]->codecpar->width;
        }
        renditions.push_back(hal::RenditionInfo{width, v.height, v.bitRate, p == best});
    }
    const AVProgram &kept = *ctx.programs[best];
    for (unsigned k = 0; k < kept.nb_stream_indexes; ++k)
        if (kept.stream_index[k] < ctx.nb_streams)
            ctx.streams[kept.stream_index[k]]->discard = AVDISCARD_DEFAULT;
    return static_cast<int>(best);
}

} // namespace depthtouch::drivers::ffmpeg
