#include "depthtouch/drivers/mock/mock_remote_input.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <string>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"keys"};

bool isScriptSeparator(char c) noexcept
{
    return c == ' ' || c == '+' || c == '\t';
}

} // namespace

Result<std::vector<hal::KeyEvent>> parseKeyScript(std::string_view script)
{
    std::vector<hal::KeyEvent> events;
    std::size_t pos = 0;
    while (pos < script.size()) {
        if (isScriptSeparator(script[pos])) {
            ++pos;
            continue;
        }
        std::size_t end = pos;
        while (end < script.size() && !isScriptSeparator(script[end]))
            ++end;
        const std::string_view item = script.substr(pos, end - pos);
        pos = end;
        const std::size_t at = item.find('@');
        if (at == std::string_view::npos) {
            DT_LOG(Mock, Error, "Key script item '%.*s' has no @time",
                   static_cast<int>(item.size()), item.data());
            return unexpected(Errc::InvalidArgument, "Key script item without @time");
        }
        const std::string name(item.substr(0, at));
        const hal::Key key = hal::keyFromName(name.c_str());
        if (key == hal::Key::Unknown) {
            DT_LOG(Mock, Error, "Unknown key '%s' in key script", name.c_str());
            return unexpected(Errc::InvalidArgument, "Unknown key name in key script");
        }
        const std::string_view timeText = item.substr(at + 1);
        double seconds = 0.0;
        const auto [ptr, ec] =
            std::from_chars(timeText.data(), timeText.data() + timeText.size(), seconds);
        if (ec != std::errc() || ptr != timeText.data() + timeText.size() || timeText.empty() ||
            !std::isfinite(seconds) || seconds < 0.0)
            return unexpected(Errc::InvalidArgument, "Malformed time in key script");
        const platform::TimePoint t{platform::fromSeconds(seconds)};
        events.push_back({key, hal::KeyAction::Press, t});
        events.push_back({key, hal::KeyAction::Release, t + kMockKeyHold});
    }
    std::stable_sort(
        events.begin(), events.end(),
        [](const hal::KeyEvent &a, const hal::KeyEvent &b) { return a.time < b.time; });
    return events;
}

Result<std::unique_ptr<hal::RemoteInput>> MockRemoteInput::create(const hal::BackendConfig &cfg)
{
    DT_TRY(rejectUnknownOptions(cfg.options, kOptionKeys, std::size(kOptionKeys),
                                "Unknown mock remote input option"));
    platform::Clock &clock = cfg.clockRef();
    auto remote = std::make_unique<MockRemoteInput>(clock);
    if (const auto keys = cfg.options.find("keys")) {
        auto events = parseKeyScript(*keys);
        if (!events)
            return unexpected(events.error());
        const platform::Duration start = clock.now().time_since_epoch();
        for (hal::KeyEvent e : *events) {
            e.time += start;
            remote->push(e);
        }
    }
    return std::unique_ptr<hal::RemoteInput>(std::move(remote));
}

MockRemoteInput::MockRemoteInput(platform::Clock &clock) : clock_(clock) {}

void MockRemoteInput::push(const hal::KeyEvent &event)
{
    const auto pos =
        std::upper_bound(events_.begin(), events_.end(), event.time,
                         [](platform::TimePoint t, const hal::KeyEvent &e) { return t < e.time; });
    events_.insert(pos, event);
}

void MockRemoteInput::pushKey(hal::Key key, platform::TimePoint at, platform::Duration hold)
{
    push({key, hal::KeyAction::Press, at});
    push({key, hal::KeyAction::Release, at + hold});
}

Result<hal::KeyEvent> MockRemoteInput::poll(hal::Deadline until)
{
    if (!present_)
        return unexpected(Errc::NoDevice, "Mock remote unplugged");
    // An event already due is returned even when the deadline has passed (a poll).
    const platform::TimePoint now = clock_.now();
    if (!events_.empty() && events_.front().time <= std::max(until, now)) {
        const hal::KeyEvent e = events_.front();
        if (e.time > now)
            clock_.sleepUntil(e.time);
        events_.pop_front();
        return e;
    }
    if (until > now)
        clock_.sleepUntil(until);
    return unexpected(Errc::Timeout, "No key before the deadline");
}

Result<std::unique_ptr<hal::RemoteInput>> NullRemoteInput::create(const hal::BackendConfig &cfg)
{
    return std::unique_ptr<hal::RemoteInput>(std::make_unique<NullRemoteInput>(cfg.clockRef()));
}

Result<hal::KeyEvent> NullRemoteInput::poll(hal::Deadline until)
{
    if (until > clock_.now())
        clock_.sleepUntil(until);
    return unexpected(Errc::Timeout, "No remote input (backend none)");
}

} // namespace depthtouch::drivers
