/// \file
/// \brief The ffmpeg media source's options (FfmpegSourceSettings, ffmpeg_media_source.h).

#include <iterator>
#include <string>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/drivers/ffmpeg/ffmpeg_media_source.h"
#include "depthtouch/platform/log.h"
#include "hls_variants.h"

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers {

namespace {
constexpr const char *kOptionKeys[] = {"fps", "format", "timeout_ms", "rendition"};
} // namespace

Result<FfmpegSourceSettings> FfmpegSourceSettings::parse(hal::OptionList options)
{
    FfmpegSourceSettings s;
    DT_TRY(rejectUnknownOptions(options, kOptionKeys, std::size(kOptionKeys), kLogCategoryFfmpeg,
                                "Unknown ffmpeg media source option"));
    auto fps = options.getDouble("fps", 0.0);
    auto timeout = options.getInt("timeout_ms", s.timeoutMs);
    if (!fps || *fps < 0.0 || *fps > 10'000.0)
        return unexpected(Errc::InvalidArgument, "ffmpeg option fps must be in 0..10000");
    if (!timeout || *timeout < 1)
        return unexpected(Errc::InvalidArgument, "ffmpeg option timeout_ms must be positive");
    s.fps = *fps;
    s.timeoutMs = *timeout;
    if (auto f = options.find("format"))
        s.format = std::string(*f);
    if (auto r = options.find("rendition")) {
        auto choice = ffmpeg::parseRenditionChoice(*r);
        if (!choice)
            return unexpected(choice.error());
        s.renditionHeight = choice->maxHeight;
        s.renditionAuto = choice->automatic;
    }
    return s;
}

} // namespace depthtouch::drivers
