#include "depthtouch/drivers/egl/display_settings.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Egl)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"width",         "height",     "refresh",
                                       "swap_interval", "fullscreen", "readback"};
constexpr std::size_t kOffscreenKeys = 4; ///< The first keys; the rest are window-only.

/// Parses a positive decimal integer that fills \a text.
bool parseInt(std::string_view text, int &out) noexcept
{
    if (text.empty() || text.size() > 6)
        return false;
    int v = 0;
    for (char c : text) {
        if (c < '0' || c > '9')
            return false;
        v = v * 10 + (c - '0');
    }
    out = v;
    return true;
}

/// Parses a positive decimal number ("60", "59.94") that fills \a text.
bool parseRate(std::string_view text, double &out) noexcept
{
    if (text.empty() || text.size() > 15)
        return false;
    char buf[16];
    text.copy(buf, text.size());
    buf[text.size()] = '\0';
    if (std::isdigit(static_cast<unsigned char>(buf[0])) == 0)
        return false;
    char *end = nullptr;
    const double v = std::strtod(buf, &end);
    if (end != buf + text.size() || !std::isfinite(v))
        return false;
    out = v;
    return true;
}

/// DRM connector names are TYPE-INDEX: "HDMI-A-1", "eDP-1", "DP-2".
bool validConnectorName(std::string_view name) noexcept
{
    if (name.size() < 3 || name.size() > 32 || name.find('-') == std::string_view::npos ||
        std::isalpha(static_cast<unsigned char>(name.front())) == 0)
        return false;
    for (char c : name)
        if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-' && c != '_')
            return false;
    return true;
}

} // namespace

Result<EglDisplaySettings> EglDisplaySettings::parse(hal::OptionList options, bool window)
{
    const std::string_view unknown =
        options.firstUnknownKey(kOptionKeys, window ? std::size(kOptionKeys) : kOffscreenKeys);
    if (!unknown.empty()) {
        DT_LOG(Egl, Error, "Unknown EGL display option '%.*s' (known: width, height, refresh, "
                           "swap_interval%s)",
               static_cast<int>(unknown.size()), unknown.data(),
               window ? ", fullscreen, readback" : "");
        return unexpected(Errc::InvalidArgument, "Unknown EGL display option");
    }
    EglDisplaySettings s;
    auto w = options.getInt("width", s.width);
    auto h = options.getInt("height", s.height);
    auto hz = options.getDouble("refresh", s.refreshHz);
    auto swap = options.getInt("swap_interval", s.swapInterval);
    if (!w || !h || !hz || !swap || !validDisplaySize(*w, *h) || !validRefreshRate(*hz) ||
        *swap < 0 || *swap > 4)
        return unexpected(Errc::InvalidArgument, "EGL display option out of range");
    s.width = *w;
    s.height = *h;
    s.refreshHz = *hz;
    s.swapInterval = *swap;
    auto fullscreen = options.getBool("fullscreen", s.fullscreen);
    auto readback = options.getBool("readback", s.readback);
    if (!fullscreen || !readback)
        return unexpected(Errc::InvalidArgument,
                          "EGL display option fullscreen/readback is 0 or 1");
    s.fullscreen = *fullscreen;
    s.readback = *readback;
    return s;
}

Result<ModeSpec> parseModeSpec(std::string_view text)
{
    ModeSpec spec;
    if (text.empty())
        return spec;
    // The size part starts at the last ':' or, without one, at the start when it begins with a
    // digit; otherwise the whole text names a connector.
    std::string_view size;
    const std::size_t colon = text.rfind(':');
    if (colon != std::string_view::npos) {
        spec.connector = std::string(text.substr(0, colon));
        size = text.substr(colon + 1);
        if (!validConnectorName(spec.connector) || size.empty())
            return unexpected(Errc::NotSupported, "Mode is [CONNECTOR:]WIDTHxHEIGHT[@HZ]");
    } else if (std::isdigit(static_cast<unsigned char>(text.front())) != 0) {
        size = text;
    } else {
        if (!validConnectorName(text))
            return unexpected(Errc::NotSupported,
                              "Connector names are TYPE-INDEX, e.g. HDMI-A-1 or eDP-1");
        spec.connector = std::string(text);
        return spec;
    }
    const std::size_t x = size.find('x');
    if (x == std::string_view::npos)
        return unexpected(Errc::NotSupported, "Mode is [CONNECTOR:]WIDTHxHEIGHT[@HZ]");
    const std::size_t at = size.find('@', x);
    const std::string_view ws = size.substr(0, x);
    const std::string_view hs =
        size.substr(x + 1, at == std::string_view::npos ? std::string_view::npos : at - x - 1);
    if (!parseInt(ws, spec.width) || !parseInt(hs, spec.height) ||
        !validDisplaySize(spec.width, spec.height))
        return unexpected(Errc::NotSupported, "Mode is [CONNECTOR:]WIDTHxHEIGHT[@HZ]");
    if (at != std::string_view::npos &&
        (!parseRate(size.substr(at + 1), spec.refreshHz) || !validRefreshRate(spec.refreshHz)))
        return unexpected(Errc::NotSupported, "Mode refresh rate must be 1..1000 Hz");
    return spec;
}

Result<EglDisplaySettings> resolveWindowConfig(const hal::DisplayConfig &cfg,
                                               const EglDisplaySettings &settings)
{
    if (cfg.width < 0 || cfg.height < 0 || cfg.refreshHz < 0.0 || !std::isfinite(cfg.refreshHz))
        return unexpected(Errc::InvalidArgument, "Display size or refresh is negative");
    auto spec = parseModeSpec(cfg.mode);
    if (!spec)
        return unexpected(spec.error());
    EglDisplaySettings out = settings;
    out.width = cfg.width > 0 ? cfg.width : (spec->width > 0 ? spec->width : settings.width);
    out.height = cfg.height > 0 ? cfg.height : (spec->height > 0 ? spec->height : settings.height);
    out.refreshHz = cfg.refreshHz > 0.0
                        ? cfg.refreshHz
                        : (spec->refreshHz > 0.0 ? spec->refreshHz : settings.refreshHz);
    if (!validDisplaySize(out.width, out.height) || !validRefreshRate(out.refreshHz))
        return unexpected(Errc::InvalidArgument, "Display size or refresh out of range");
    return out;
}

} // namespace depthtouch::drivers
