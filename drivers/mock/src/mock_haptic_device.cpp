#include "depthtouch/drivers/mock/mock_haptic_device.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"
#include "simulated_caps.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr double kUnbounded = HUGE_VAL;

constexpr NumericOption<MockHapticSettings> kOptions[] = {
    {.key = "max_force",
     .real = &MockHapticSettings::maxForce,
     .max = kUnbounded,
     .minExclusive = true},
    {.key = "workspace",
     .real = &MockHapticSettings::workspaceHalfExtent,
     .max = kUnbounded,
     .minExclusive = true},
    {.key = "servo_rate",
     .real = &MockHapticSettings::servoRateHz,
     .max = kUnbounded,
     .minExclusive = true},
    {.key = "buttons", .integer = &MockHapticSettings::buttonCount, .min = 0, .max = 32},
};

double clampTo(double v, double lo, double hi) noexcept
{
    return std::min(std::max(v, lo), hi);
}

} // namespace

Result<MockHapticSettings> MockHapticSettings::parse(hal::OptionList options)
{
    return parseNumericOptions(options, kOptions, kLogCategoryMock,
                               "Unknown mock haptic device option",
                               "Mock haptic device option out of range");
}

Result<std::unique_ptr<hal::HapticDevice>> MockHapticDevice::create(const hal::BackendConfig &cfg)
{
    return createFromSettings<hal::HapticDevice, MockHapticDevice, MockHapticSettings>(cfg);
}

MockHapticDevice::MockHapticDevice(platform::Clock &clock, const MockHapticSettings &settings)
    : clock_(clock)
{
    caps_ = simulatedCapabilities("Mock 3-DOF haptic device", settings);
}

Result<MockHapticDevice::State> MockHapticDevice::openDevice()
{
    if (!devicePresent())
        return unexpected(Errc::NoDevice, "Mock haptic device unplugged");
    setOutput({});
    return State::Open;
}

Result<void> MockHapticDevice::readDevice(hal::HapticState &out) noexcept
{
    DT_TRY(checkStall());
    out = sampleAt(clock_.now());
    readCount_.fetch_add(1, std::memory_order_relaxed);
    return ok();
}

Result<void> MockHapticDevice::commandForceDevice(const hal::ForceCommand &command) noexcept
{
    DT_TRY(checkStall());
    forceCount_.fetch_add(1, std::memory_order_relaxed);
    if (command.clamped)
        clampCount_.fetch_add(1, std::memory_order_relaxed);
    setOutput(command.force);
    if (command.magnitude > maxMagnitude_.load(std::memory_order_relaxed))
        maxMagnitude_.store(command.magnitude, std::memory_order_relaxed);
    return ok();
}

void MockHapticDevice::setWaypoints(std::vector<HapticWaypoint> points)
{
    std::stable_sort(
        points.begin(), points.end(),
        [](const HapticWaypoint &a, const HapticWaypoint &b) { return a.time < b.time; });
    waypoints_ = std::move(points);
}

hal::HapticState MockHapticDevice::sampleAt(platform::TimePoint t) const noexcept
{
    hal::HapticState s;
    s.time = t;
    s.velocityValid = true;
    if (!waypoints_.empty()) {
        // First waypoint strictly after t; the one before it (if any) starts the current segment.
        const auto next = std::upper_bound(
            waypoints_.begin(), waypoints_.end(), t,
            [](platform::TimePoint v, const HapticWaypoint &w) { return v < w.time; });
        if (next == waypoints_.begin()) {
            s.position = next->position;
            s.buttons = next->buttons;
        } else {
            const HapticWaypoint &a = *(next - 1);
            s.buttons = a.buttons;
            if (next == waypoints_.end()) {
                s.position = a.position;
            } else {
                const double span = platform::toSeconds(next->time - a.time);
                const double f = platform::toSeconds(t - a.time) / span;
                const hal::Vec3 delta = next->position - a.position;
                s.position = a.position + delta * f;
                s.velocity = delta * (1.0 / span);
            }
        }
    }
    const hal::Vec3 &lo = caps_.workspaceMin;
    const hal::Vec3 &hi = caps_.workspaceMax;
    const hal::Vec3 p = s.position;
    s.position = {clampTo(p.x, lo.x, hi.x), clampTo(p.y, lo.y, hi.y), clampTo(p.z, lo.z, hi.z)};
    // A clamped axis does not move.
    if (s.position.x != p.x)
        s.velocity.x = 0.0;
    if (s.position.y != p.y)
        s.velocity.y = 0.0;
    if (s.position.z != p.z)
        s.velocity.z = 0.0;
    if (caps_.buttonCount < 32)
        s.buttons &= (1u << caps_.buttonCount) - 1u;
    return s;
}

} // namespace depthtouch::drivers
