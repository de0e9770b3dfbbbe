/// \file
/// \brief makeSourceProviders() (see source_providers.h): the `v4l2:` and `synthetic:` factories of
/// dt_media and dt_synthetic_source, handed the driver backends they run on.

#include "source_providers.h"

#include <memory>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/camera_source.h"

#if __has_include("depthtouch/synthetic/synthetic_source.h")
#include "depthtouch/synthetic/synthetic_source.h"
#define DT_CLI_HAVE_SYNTHETIC 1
#else
#define DT_CLI_HAVE_SYNTHETIC 0
#endif

namespace depthtouch::cli {

media::SourceProviders makeSourceProviders()
{
    media::SourceProviders providers;
    auto cameras =
        std::make_shared<media::CameraSourceFactory>([](const hal::BackendConfig &config) {
            return drivers::createDepthCamera("v4l2", config);
        });
    providers.v4l2 = [cameras](const std::string &target, const media::SourceOptions &options) {
        return cameras->open(target, options);
    };
#if DT_CLI_HAVE_SYNTHETIC
    auto scenes = std::make_shared<synthetic::SyntheticSourceFactory>(
        [] { return drivers::createDisplay("headless", hal::BackendConfig{}); });
    providers.synthetic = [scenes](const std::string &target, const media::SourceOptions &options) {
        return scenes->open(target, options);
    };
#endif
    return providers;
}

} // namespace depthtouch::cli
