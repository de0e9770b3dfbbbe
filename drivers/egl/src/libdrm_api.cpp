// DrmApi on libdrm (the real DRM side of the kms display).
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <xf86drm.h>
#include <xf86drmMode.h>

#include "depthtouch/drivers/egl/kms_output.h"
#include "depthtouch/platform/unique_fd.h"
#include "libdrm_mode.h"

namespace depthtouch::drivers {

namespace {

class LibdrmApi final : public DrmApi {
public:
    std::vector<std::string> listCards() override
    {
        std::vector<std::string> out;
        std::error_code ec;
        for (const auto &entry : std::filesystem::directory_iterator("/dev/dri", ec)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind("card", 0) == 0 && name.size() > 4 &&
                name.find_first_not_of("0123456789", 4) == std::string::npos)
                out.push_back(entry.path().string());
        }
        std::sort(out.begin(), out.end());
        return out;
    }

    Result<DrmCardInfo> probeCard(const std::string &path) override
    {
        platform::UniqueFd fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
        if (!fd) {
            const int err = errno;
            if (err == EACCES || err == EPERM)
                return unexpected(Errc::PermissionDenied, "No access to the DRM device", err);
            return unexpected(Errc::NoDevice, "Failed to open the DRM device", err);
        }
        drmModeRes *res = drmModeGetResources(fd.get());
        if (res == nullptr)
            return unexpected(Errc::NotSupported, "DRM device without KMS", errno);
        DrmCardInfo card;
        card.path = path;
        for (int i = 0; i < res->count_connectors; ++i) {
            drmModeConnector *c = drmModeGetConnector(fd.get(), res->connectors[i]);
            if (c == nullptr)
                continue;
            DrmConnectorInfo info;
            info.id = c->connector_id;
            const char *type = drmModeGetConnectorTypeName(c->connector_type);
            info.name = std::string(type != nullptr ? type : "Unknown") + "-" +
                        std::to_string(c->connector_type_id);
            info.connected = c->connection == DRM_MODE_CONNECTED;
            for (int m = 0; m < c->count_modes; ++m)
                info.modes.push_back(kms::fromDrmMode(c->modes[m]));
            drmModeFreeConnector(c);
            card.connectors.push_back(std::move(info));
        }
        drmModeFreeResources(res);
        return card;
    }
};

} // namespace

namespace kms {

DrmModeInfo fromDrmMode(const drmModeModeInfo &mi)
{
    DrmModeInfo mode;
    mode.name.assign(mi.name, strnlen(mi.name, sizeof mi.name));
    mode.width = mi.hdisplay;
    mode.height = mi.vdisplay;
    const double total = static_cast<double>(mi.htotal) * static_cast<double>(mi.vtotal);
    mode.refreshHz = total > 0.0 ? mi.clock * 1000.0 / total : mi.vrefresh;
    mode.preferred = (mi.type & DRM_MODE_TYPE_PREFERRED) != 0;
    DrmModeTimings &t = mode.timings;
    t.clock = mi.clock;
    t.hdisplay = mi.hdisplay;
    t.hsyncStart = mi.hsync_start;
    t.hsyncEnd = mi.hsync_end;
    t.htotal = mi.htotal;
    t.hskew = mi.hskew;
    t.vdisplay = mi.vdisplay;
    t.vsyncStart = mi.vsync_start;
    t.vsyncEnd = mi.vsync_end;
    t.vtotal = mi.vtotal;
    t.vscan = mi.vscan;
    t.vrefresh = mi.vrefresh;
    t.flags = mi.flags;
    t.type = mi.type;
    return mode;
}

drmModeModeInfo toDrmMode(const DrmModeInfo &m) noexcept
{
    drmModeModeInfo mi{};
    const DrmModeTimings &t = m.timings;
    mi.clock = t.clock;
    mi.hdisplay = t.hdisplay;
    mi.hsync_start = t.hsyncStart;
    mi.hsync_end = t.hsyncEnd;
    mi.htotal = t.htotal;
    mi.hskew = t.hskew;
    mi.vdisplay = t.vdisplay;
    mi.vsync_start = t.vsyncStart;
    mi.vsync_end = t.vsyncEnd;
    mi.vtotal = t.vtotal;
    mi.vscan = t.vscan;
    mi.vrefresh = t.vrefresh;
    mi.flags = t.flags;
    mi.type = t.type;
    const std::size_t n = std::min(m.name.size(), sizeof mi.name - 1);
    std::memcpy(mi.name, m.name.data(), n);
    return mi;
}

} // namespace kms

std::unique_ptr<DrmApi> makeLibdrmApi()
{
    return std::make_unique<LibdrmApi>();
}

} // namespace depthtouch::drivers
