#pragma once
/// \file
/// \brief The DRM/KMS side of the `kms` display: device discovery and connector/mode selection,
/// behind the DrmApi seam (plain structs describing cards, connectors and modes) so the logic is
/// tested against a fake. LibdrmApi is the real one (libdrm).
///
/// Selection (selectKmsOutput()): cards in DrmApi::listCards() order; on each, the connected
/// connectors that have modes, in order, or only the one named by the mode string
/// ("HDMI-A-1[:WIDTHxHEIGHT[@HZ]]"). Without a requested size the connector's preferred mode is
/// taken (its first mode when none is flagged). With a size: the modes of that size; with a rate
/// too, the one nearest to it within 0.5 Hz, else the highest rate of that size.
/// selectKmsScreenMode() adds the rule of the kms display for a size that is the content's rather
/// than the screen's; chooseCrtc() picks the CRTC that drives the chosen connector.
/// Thread-safety: reentrant (a DrmApi object is used by one thread at a time).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/display.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief The raw timings of a DRM mode (the fields of drmModeModeInfo besides its name), enough
/// to set the mode again with drmModeSetCrtc(). Pixel clock in kHz, the rest in pixels or lines.
struct DrmModeTimings {
    std::uint32_t clock = 0; ///< Pixel clock, kHz.
    std::uint16_t hdisplay = 0, hsyncStart = 0, hsyncEnd = 0, htotal = 0, hskew = 0;
    std::uint16_t vdisplay = 0, vsyncStart = 0, vsyncEnd = 0, vtotal = 0, vscan = 0;
    std::uint32_t vrefresh = 0; ///< Hertz, rounded.
    std::uint32_t flags = 0;    ///< DRM_MODE_FLAG_*.
    std::uint32_t type = 0;     ///< DRM_MODE_TYPE_*.

    friend bool operator==(const DrmModeTimings &, const DrmModeTimings &) = default;
};

/// One display mode of a connector.
struct DrmModeInfo {
    std::string name;        ///< e.g. "1920x1080".
    int width = 0;           ///< Pixels.
    int height = 0;          ///< Pixels.
    double refreshHz = 0.0;  ///< Vertical refresh, hertz.
    bool preferred = false;  ///< DRM_MODE_TYPE_PREFERRED (the sink's native mode).
    DrmModeTimings timings{}; ///< As the kernel reports them (LibdrmApi); zero from fakes.

    friend bool operator==(const DrmModeInfo &, const DrmModeInfo &) = default;
};

/// One connector (HDMI, DP, ...) of a card.
struct DrmConnectorInfo {
    std::uint32_t id = 0;            ///< KMS object id.
    std::string name;                ///< TYPE-INDEX, e.g. "HDMI-A-1".
    bool connected = false;          ///< A sink is plugged in.
    std::vector<DrmModeInfo> modes;  ///< As the sink reports them (EDID order).
};

/// One KMS-capable DRM card.
struct DrmCardInfo {
    std::string path; ///< e.g. "/dev/dri/card0".
    std::vector<DrmConnectorInfo> connectors;
};

/// \brief What the kms display needs from DRM to choose an output (the seam for tests).
class DrmApi {
public:
    virtual ~DrmApi() = default;
    /// \return the DRM card nodes present, in order (e.g. "/dev/dri/card0"); empty when none.
    virtual std::vector<std::string> listCards() = 0;
    /// \brief Reads the connectors and modes of card \a path.
    /// \return the card. Errors: NoDevice (cannot open), NotSupported (not a KMS device),
    /// PermissionDenied (no access).
    virtual Result<DrmCardInfo> probeCard(const std::string &path) = 0;

protected:
    DrmApi() = default;
};

/// The output chosen by selectKmsOutput().
struct KmsSelection {
    DrmCardInfo card;
    std::size_t connector = 0; ///< Index in card.connectors.
    std::size_t mode = 0;      ///< Index in card.connectors[connector].modes.

    [[nodiscard]] const DrmConnectorInfo &connectorInfo() const
    {
        return card.connectors[connector];
    }
    [[nodiscard]] const DrmModeInfo &modeInfo() const { return connectorInfo().modes[mode]; }
};

/// \brief Chooses card, connector and mode for \a cfg (size and refresh fields, then cfg.mode).
/// \return the selection. Errors: NoDevice (no DRM card, no connected connector, or the named
/// connector absent or disconnected), NotSupported (malformed mode string, or no mode of the
/// requested size/rate on the chosen connector), InvalidArgument (negative fields).
Result<KmsSelection> selectKmsOutput(DrmApi &api, const hal::DisplayConfig &cfg);

/// \brief Chooses the mode for opening the kms display on a screen (EglGbmDisplay::open()).
///
/// A screen has the modes its sink offers, while DisplayConfig's size is usually the size of the
/// content (the player asks for twice the depth width by its height). So: an explicit \a modeText
/// (the backend option `mode`, else cfg.mode) that gives a size is followed strictly; otherwise
/// cfg's size and refresh choose a mode when the connector has one of that size, and when it has
/// none the connector's preferred mode is used (logged). A connector named in the mode text is
/// always honoured.
/// \return the selection. Errors: as selectKmsOutput().
Result<KmsSelection> selectKmsScreenMode(DrmApi &api, const hal::DisplayConfig &cfg,
                                         const std::string &modeText);

/// One encoder of a card, as drmModeGetEncoder() reports it.
struct DrmEncoderInfo {
    std::uint32_t id = 0;
    std::uint32_t crtcId = 0;        ///< CRTC it drives now; 0 when none.
    std::uint32_t possibleCrtcs = 0; ///< Bit i: it can drive the card's i-th CRTC.
};

/// \brief Chooses the CRTC to drive a connector: the CRTC of its current encoder
/// (\a currentEncoder, 0 when none) when that encoder drives one, else the first CRTC, in card
/// order (\a crtcs, drmModeRes::crtcs), that one of the connector's \a encoders can drive.
/// \return the CRTC id; 0 when no CRTC can drive the connector.
std::uint32_t chooseCrtc(std::uint32_t currentEncoder, const std::vector<DrmEncoderInfo> &encoders,
                         const std::vector<std::uint32_t> &crtcs);

/// \brief DrmApi on libdrm: cards are /dev/dri/card[0-9]*; connectors and modes from
/// drmModeGetResources()/drmModeGetConnector().
std::unique_ptr<DrmApi> makeLibdrmApi();

} // namespace depthtouch::drivers
