/// \file
/// \brief The tags of an input's streams: see stream_tags.h.

#include "stream_tags.h"

#include <cstring>

namespace depthtouch::drivers {

/// \return the value of tag \a key (any case) of the stream, else of the container, else of
/// DepthTouch's MPEG-TS tags \a service (its timed metadata, or the service name of older files);
/// nullptr when none has it.
const char *tagOf(const AVStream &st, const AVFormatContext &fmt, const AVDictionary *service,
                  const char *key) noexcept
{
    if (const AVDictionaryEntry *e = av_dict_get(st.metadata, key, nullptr, 0))
        return e->value;
    if (const AVDictionaryEntry *e = av_dict_get(fmt.metadata, key, nullptr, 0))
        return e->value;
    if (const AVDictionaryEntry *e = av_dict_get(service, key, nullptr, 0))
        return e->value;
    return nullptr;
}

/// \return the tags DepthTouch's MPEG-TS muxer wrote into the service name before its timed
/// metadata stream ("key=value;…", service provider "DepthTouch"), parsed with
/// av_dict_parse_string; nullptr for any other input. The caller frees it (av_dict_free).
AVDictionary *serviceTagsOf(const AVFormatContext &fmt) noexcept
{
    for (unsigned p = 0; p < fmt.nb_programs; ++p) {
        const AVDictionaryEntry *provider =
            av_dict_get(fmt.programs[p]->metadata, "service_provider", nullptr, 0);
        const AVDictionaryEntry *name =
            av_dict_get(fmt.programs[p]->metadata, "service_name", nullptr, 0);
        if (provider == nullptr || name == nullptr ||
            std::strcmp(provider->value, "DepthTouch") != 0)
            continue;
        AVDictionary *tags = nullptr;
        if (av_dict_parse_string(&tags, name->value, "=", ";", 0) < 0)
            av_dict_free(&tags);
        return tags;
    }
    return nullptr;
}

/// \return whether \a text names a stream role DepthTouch writes ("color", "depth" or "material":
/// an MP4 handler name that counts as the stream title).
bool isRoleName(const char *text) noexcept
{
    return text != nullptr && (std::strcmp(text, "color") == 0 || std::strcmp(text, "depth") == 0 ||
                               std::strcmp(text, "material") == 0);
}

} // namespace depthtouch::drivers
