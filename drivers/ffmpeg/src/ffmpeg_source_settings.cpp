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
constexpr const char *kOptionKeys[] = {"fps",       "format",    "timeout_ms",
                                       "rendition", "probesize", "analyzeduration"};
constexpr int kMinProbeSize = 32;      ///< `probesize`'s smallest, bytes (libavformat's).
constexpr int kMaxProbeSize = 1 << 30; ///< `probesize`'s largest, bytes (1 GiB).
constexpr int kMaxAnalyzeDurationUs = 600'000'000; ///< `analyzeduration`'s largest: 10 min, us.
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
    auto probeSize = options.getInt("probesize", 0);
    if (!probeSize ||
        (*probeSize != 0 && (*probeSize < kMinProbeSize || *probeSize > kMaxProbeSize)))
        return unexpected(Errc::InvalidArgument,
                          "ffmpeg option probesize must be 32..1073741824 bytes (0: default)");
    auto analyze = options.getInt("analyzeduration", 0);
    if (!analyze || *analyze < 0 || *analyze > kMaxAnalyzeDurationUs)
        return unexpected(Errc::InvalidArgument,
                          "ffmpeg option analyzeduration must be 0..600000000 us (0: default)");
    s.fps = *fps;
    s.timeoutMs = *timeout;
    s.probeSize = *probeSize;
    s.analyzeDurationUs = *analyze;
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
