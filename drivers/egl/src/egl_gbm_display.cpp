#include "depthtouch/drivers/egl/egl_gbm_display.h"

#include <string>
#include <vector>

#include "depthtouch/drivers/egl/kms_output.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Kms)

namespace depthtouch::drivers {

namespace {

/// Discovery limited to one card path (BackendConfig::device).
class OneCardApi final : public DrmApi {
public:
    OneCardApi(std::unique_ptr<DrmApi> api, std::string path)
        : api_(std::move(api)), path_(std::move(path))
    {
    }
    std::vector<std::string> listCards() override { return {path_}; }
    Result<DrmCardInfo> probeCard(const std::string &path) override
    {
        return api_->probeCard(path);
    }

private:
    std::unique_ptr<DrmApi> api_;
    std::string path_;
};

} // namespace

Result<std::unique_ptr<hal::Display>> EglGbmDisplay::create(const hal::BackendConfig &cfg)
{
    if (!cfg.options.text().empty())
        return unexpected(Errc::InvalidArgument, "The kms display takes no options");
    std::unique_ptr<DrmApi> api = makeLibdrmApi();
    if (!cfg.device.empty())
        api = std::make_unique<OneCardApi>(std::move(api), std::string(cfg.device));
    auto selection = selectKmsOutput(*api, {});
    if (!selection)
        return unexpected(selection.error());
    DT_LOG(Kms, Warning, "GBM/KMS scan-out is not implemented yet; use --display headless or x11");
    return unexpected(Errc::NotSupported, "GBM/KMS scan-out not implemented");
}

} // namespace depthtouch::drivers
