#pragma once
// A fake evdev EventSource: input_event records (or an unplug) scheduled at times on the clock,
// delivered like a device would, for tests without /dev/input.

#include <algorithm>
#include <deque>
#include <optional>

#include <linux/input.h>

#include "depthtouch/drivers/evdev/evdev_remote_input.h"

namespace depthtouch::drivers::test {

class FakeEventSource final : public EventSource {
public:
    struct Item {
        platform::TimePoint at;
        input_event event{};
        std::optional<Errc> error; ///< Set: next() returns this error instead (e.g. NoDevice).
    };

    /// Queues one raw record at \a at (records at equal times keep their order).
    void pushRaw(platform::TimePoint at, unsigned short type, unsigned short code, int value)
    {
        Item item{at, {}, std::nullopt};
        item.event.type = type;
        item.event.code = code;
        item.event.value = value;
        insert(item);
    }
    /// Queues EV_KEY \a code with \a value (0 release, 1 press, 2 repeat) and its SYN_REPORT.
    void pushKey(platform::TimePoint at, unsigned short code, int value)
    {
        pushRaw(at, EV_MSC, MSC_SCAN, 0x1234);
        pushRaw(at, EV_KEY, code, value);
        pushRaw(at, EV_SYN, SYN_REPORT, 0);
    }
    /// Makes next() fail with \a code from \a at on.
    void pushError(platform::TimePoint at, Errc code) { insert({at, {}, code}); }

    [[nodiscard]] std::size_t pending() const noexcept { return items_.size(); }

    Result<input_event> next(platform::Clock &clock, hal::Deadline until) override
    {
        const platform::TimePoint now = clock.now();
        if (items_.empty() || items_.front().at > std::max(until, now)) {
            if (until > now)
                clock.sleepUntil(until);
            return unexpected(Errc::Timeout, "No event before the deadline");
        }
        const Item item = items_.front();
        if (item.at > now)
            clock.sleepUntil(item.at);
        if (item.error)
            return unexpected(*item.error, "Fake input device error");
        items_.pop_front();
        return item.event;
    }

private:
    void insert(const Item &item)
    {
        const auto pos = std::upper_bound(
            items_.begin(), items_.end(), item.at,
            [](platform::TimePoint t, const Item &i) { return t < i.at; });
        items_.insert(pos, item);
    }

    std::deque<Item> items_;
};

} // namespace depthtouch::drivers::test
