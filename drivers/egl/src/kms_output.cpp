#include "depthtouch/drivers/egl/kms_output.h"

#include <cmath>

#include "depthtouch/drivers/egl/display_settings.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Kms)

namespace depthtouch::drivers {

namespace {

/// \return the index of the mode to use on \a c for the request, or -1.
long chooseMode(const DrmConnectorInfo &c, int width, int height, double hz)
{
    if (c.modes.empty())
        return -1;
    if (width == 0 && height == 0 && hz == 0.0) {
        for (std::size_t i = 0; i < c.modes.size(); ++i)
            if (c.modes[i].preferred)
                return static_cast<long>(i);
        return 0;
    }
    long best = -1;
    for (std::size_t i = 0; i < c.modes.size(); ++i) {
        const DrmModeInfo &m = c.modes[i];
        if ((width != 0 && m.width != width) || (height != 0 && m.height != height))
            continue;
        if (hz > 0.0) {
            if (std::abs(m.refreshHz - hz) > 0.5)
                continue;
            if (best < 0 || std::abs(m.refreshHz - hz) <
                                std::abs(c.modes[static_cast<std::size_t>(best)].refreshHz - hz))
                best = static_cast<long>(i);
        } else if (best < 0 || m.refreshHz > c.modes[static_cast<std::size_t>(best)].refreshHz ||
                   (m.refreshHz == c.modes[static_cast<std::size_t>(best)].refreshHz &&
                    m.preferred)) {
            best = static_cast<long>(i);
        }
    }
    return best;
}

} // namespace

Result<KmsSelection> selectKmsOutput(DrmApi &api, const hal::DisplayConfig &cfg)
{
    if (cfg.width < 0 || cfg.height < 0 || cfg.refreshHz < 0.0)
        return unexpected(Errc::InvalidArgument, "Display size or refresh is negative");
    auto spec = parseModeSpec(cfg.mode);
    if (!spec)
        return unexpected(spec.error());
    const int width = cfg.width > 0 ? cfg.width : spec->width;
    const int height = cfg.height > 0 ? cfg.height : spec->height;
    const double hz = cfg.refreshHz > 0.0 ? cfg.refreshHz : spec->refreshHz;

    const std::vector<std::string> cards = api.listCards();
    if (cards.empty()) {
        DT_LOG(Kms, Info, "No DRM device (/dev/dri/card*)");
        return unexpected(Errc::NoDevice, "No DRM device (/dev/dri/card*)");
    }
    bool sawConnector = false;
    bool sawNamed = false;
    for (const std::string &path : cards) {
        auto card = api.probeCard(path);
        if (!card) {
            DT_LOG(Kms, Info, "Skipping %s: %s", path.c_str(), card.error().what);
            continue;
        }
        for (std::size_t i = 0; i < card->connectors.size(); ++i) {
            const DrmConnectorInfo &c = card->connectors[i];
            if (!spec->connector.empty() && c.name != spec->connector)
                continue;
            sawNamed = true;
            if (!c.connected || c.modes.empty())
                continue;
            sawConnector = true;
            const long mode = chooseMode(c, width, height, hz);
            if (mode < 0) {
                DT_LOG(Kms, Info, "%s on %s has no %dx%d@%g mode", c.name.c_str(), path.c_str(),
                       width, height, hz);
                continue;
            }
            KmsSelection sel;
            sel.connector = i;
            sel.mode = static_cast<std::size_t>(mode);
            sel.card = std::move(*card);
            DT_LOG(Kms, Info, "Using %s on %s, mode %s at %.2f Hz",
                   sel.connectorInfo().name.c_str(), path.c_str(), sel.modeInfo().name.c_str(),
                   sel.modeInfo().refreshHz);
            return sel;
        }
    }
    if (!spec->connector.empty() && !sawNamed)
        return unexpected(Errc::NoDevice, "No DRM connector of that name");
    if (!sawConnector)
        return unexpected(Errc::NoDevice, "No display connected to any DRM connector");
    return unexpected(Errc::NotSupported, "No connected display offers the requested mode");
}

Result<KmsSelection> selectKmsScreenMode(DrmApi &api, const hal::DisplayConfig &cfg,
                                         const std::string &modeText)
{
    if (cfg.width < 0 || cfg.height < 0 || cfg.refreshHz < 0.0)
        return unexpected(Errc::InvalidArgument, "Display size or refresh is negative");
    const std::string &text = modeText.empty() ? cfg.mode : modeText;
    auto spec = parseModeSpec(text);
    if (!spec)
        return unexpected(spec.error());
    hal::DisplayConfig onlyText;
    onlyText.mode = text;
    auto sel = selectKmsOutput(api, onlyText);
    const bool sizeAsked = cfg.width > 0 || cfg.height > 0 || cfg.refreshHz > 0.0;
    if (!sel || spec->width > 0 || spec->height > 0 || spec->refreshHz > 0.0 || !sizeAsked)
        return sel;
    // The content size picks a mode of the chosen connector only when the sink has one.
    const long mode = chooseMode(sel->connectorInfo(), cfg.width, cfg.height, cfg.refreshHz);
    if (mode >= 0) {
        sel->mode = static_cast<std::size_t>(mode);
    } else {
        DT_LOG(Kms, Info, "%s has no %dx%d@%g mode: using %s at %.2f Hz",
               sel->connectorInfo().name.c_str(), cfg.width, cfg.height, cfg.refreshHz,
               sel->modeInfo().name.c_str(), sel->modeInfo().refreshHz);
    }
    return sel;
}

std::uint32_t chooseCrtc(std::uint32_t currentEncoder, const std::vector<DrmEncoderInfo> &encoders,
                         const std::vector<std::uint32_t> &crtcs)
{
    if (currentEncoder != 0) {
        for (const DrmEncoderInfo &e : encoders)
            if (e.id == currentEncoder && e.crtcId != 0)
                return e.crtcId;
    }
    for (std::size_t i = 0; i < crtcs.size() && i < 32; ++i)
        for (const DrmEncoderInfo &e : encoders)
            if ((e.possibleCrtcs & (1u << i)) != 0)
                return crtcs[i];
    return 0;
}

} // namespace depthtouch::drivers
