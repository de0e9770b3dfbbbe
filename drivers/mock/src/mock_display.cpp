#include "depthtouch/drivers/mock/mock_display.h"

#include <cstdio>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr NumericOption<MockDisplaySettings> kOptions[] = {
    {.key = "width", .integer = &MockDisplaySettings::width, .min = 1, .max = kMaxDisplayPixels},
    {.key = "height", .integer = &MockDisplaySettings::height, .min = 1, .max = kMaxDisplayPixels},
    {.key = "refresh",
     .real = &MockDisplaySettings::refreshHz,
     .min = kMinRefreshHz,
     .max = kMaxRefreshHz},
};

} // namespace

Result<MockDisplaySettings> MockDisplaySettings::parse(hal::OptionList options)
{
    return parseNumericOptions(options, kOptions, kLogCategoryMock, "Unknown mock display option",
                               "Mock display option out of range");
}

Result<std::unique_ptr<hal::Display>> MockDisplay::create(const hal::BackendConfig &cfg)
{
    return createFromSettings<hal::Display, MockDisplay, MockDisplaySettings>(cfg);
}

MockDisplay::MockDisplay(platform::Clock &clock, const MockDisplaySettings &settings)
    : clock_(clock), settings_(settings)
{
    caps_.hasGlesContext = false;
    caps_.offscreen = true;
}

Result<void> MockDisplay::openDevice(const hal::DisplayConfig &cfg)
{
    if (!connected_)
        return unexpected(Errc::NoDevice, "No display connected");
    int width = cfg.width > 0 ? cfg.width : settings_.width;
    int height = cfg.height > 0 ? cfg.height : settings_.height;
    double hz = cfg.refreshHz > 0.0 ? cfg.refreshHz : settings_.refreshHz;
    if (!cfg.mode.empty()) {
        int w = 0;
        int h = 0;
        int used = 0;
        const char *mode = cfg.mode.c_str();
        if (std::sscanf(mode, "%dx%d%n", &w, &h, &used) != 2)
            return unexpected(Errc::NotSupported, "Mock display modes are WIDTHxHEIGHT[@HZ]");
        const char *rest = mode + used;
        if (*rest == '@') {
            double r = 0.0;
            int usedHz = 0;
            if (std::sscanf(rest + 1, "%lf%n", &r, &usedHz) != 1 || rest[1 + usedHz] != '\0')
                return unexpected(Errc::NotSupported, "Mock display modes are WIDTHxHEIGHT[@HZ]");
            hz = r;
        } else if (*rest != '\0') {
            return unexpected(Errc::NotSupported, "Mock display modes are WIDTHxHEIGHT[@HZ]");
        }
        width = w;
        height = h;
    }
    if (!validDisplaySize(width, height) || !validRefreshRate(hz) || cfg.width < 0 ||
        cfg.height < 0 || cfg.refreshHz < 0.0)
        return unexpected(Errc::InvalidArgument, "Display size or refresh out of range");
    size_ = {width, height};
    refreshHz_ = hz;
    pacer_.start(clock_.now(), hz);
    current_ = false;
    return ok();
}

Result<void> MockDisplay::makeCurrentDevice()
{
    current_ = true;
    return ok();
}

Result<hal::PresentInfo> MockDisplay::presentDevice()
{
    if (const double stall = stallSeconds_.exchange(0.0); stall > 0.0)
        clock_.sleepFor(platform::fromSeconds(stall));
    return pacer_.next(clock_);
}

void MockDisplay::loseDisplay() noexcept
{
    connected_ = false;
    markLost();
    current_ = false;
}

} // namespace depthtouch::drivers
