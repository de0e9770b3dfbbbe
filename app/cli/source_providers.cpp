/// \file
/// \brief makeSourceProviders() and the helpers both source kinds share (see source_providers.h).

#include "source_providers.h"

#include <charconv>
#include <memory>
#include <set>

#include "source_factories.h"

namespace depthtouch::cli {

const char *persistentText(const std::string &text)
{
    static std::mutex mutex;
    static std::set<std::string> texts; // node-based: c_str() stays valid as the set grows
    const std::lock_guard lock(mutex);
    return texts.insert(text).first->c_str();
}

bool parseSizeText(std::string_view text, int &width, int &height)
{
    const std::size_t x = text.find('x');
    if (x == std::string_view::npos)
        return false;
    int w = 0;
    int h = 0;
    const char *end = text.data() + text.size();
    const auto rw = std::from_chars(text.data(), text.data() + x, w);
    const auto rh = std::from_chars(text.data() + x + 1, end, h);
    if (rw.ec != std::errc{} || rw.ptr != text.data() + x || rh.ec != std::errc{} ||
        rh.ptr != end || w <= 0 || h <= 0)
        return false;
    width = w;
    height = h;
    return true;
}

Result<bool> wantsDepthStream(std::string_view streamOption, const media::SourceOptions &options)
{
    if (streamOption.empty())
        return options.streamTitle == "depth";
    if (streamOption == "depth")
        return true;
    if (streamOption == "color")
        return false;
    return unexpected(Errc::InvalidArgument, "stream= must be color or depth");
}

media::SourceProviders makeSourceProviders()
{
    media::SourceProviders providers;
    auto cameras = std::make_shared<CameraSourceFactory>();
    providers.v4l2 = [cameras](const std::string &target, const media::SourceOptions &options) {
        return cameras->open(target, options);
    };
    if (SyntheticSourceFactory::available()) {
        auto scenes = std::make_shared<SyntheticSourceFactory>();
        providers.synthetic = [scenes](const std::string &target,
                                       const media::SourceOptions &options) {
            return scenes->open(target, options);
        };
    }
    return providers;
}

} // namespace depthtouch::cli
