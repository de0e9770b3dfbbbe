#include "depthtouch/drivers/evdev/hotplug_event_source.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Evdev)

namespace depthtouch::drivers {

HotplugEventSource::HotplugEventSource(Opener open, platform::Duration retry)
    : open_(std::move(open)),
      retry_(std::max(retry, platform::Duration(std::chrono::milliseconds(1))))
{
}

bool HotplugEventSource::tryOpen(platform::TimePoint now)
{
    if (nextTry_ && now < *nextTry_)
        return false;
    nextTry_ = now + retry_;
    Result<std::unique_ptr<EventSource>> opened = open_();
    if (opened && *opened) {
        device_ = std::move(*opened);
        ++arrivals_;
        failureLogged_ = false;
        DT_LOG(Evdev, Info, "Remote control input device %s: reading its keys",
               arrivals_ == 1 ? "found" : "back");
        return true;
    }
    if (!failureLogged_) {
        char buf[160];
        DT_LOG(Evdev, Warning,
               "No remote control input device yet (%s): looking for one every %lld ms",
               opened ? "none" : opened.error().format(buf, sizeof buf),
               static_cast<long long>(
                   std::chrono::duration_cast<std::chrono::milliseconds>(retry_).count()));
        failureLogged_ = true;
    }
    return false;
}

Result<input_event> HotplugEventSource::next(platform::Clock &clock, hal::Deadline until)
{
    for (;;) {
        const platform::TimePoint now = clock.now();
        if (device_ == nullptr && !tryOpen(now)) {
            if (now >= until)
                return unexpected(Errc::Timeout, "No remote control input device");
            clock.sleepUntil(std::min(until, *nextTry_));
            continue;
        }
        Result<input_event> event = device_->next(clock, until);
        if (event || event.error().code != Errc::NoDevice)
            return event;
        DT_LOG(Evdev, Warning, "Remote control input device went away: waiting for it");
        device_.reset();
        nextTry_ = clock.now() + retry_;
    }
}

} // namespace depthtouch::drivers
