#include "depthtouch/drivers/evdev/evdev_remote_input.h"

#include <chrono>
#include <iterator>

#include "depthtouch/drivers/evdev/hotplug_event_source.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Evdev)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"device", "grab", "repeat"};

/// How often an awaited remote is looked for: a key pressed in the first second after it is
/// plugged in may be missed; a scan of /dev/input costs an open() per event node.
constexpr platform::Duration kHotplugRetry = std::chrono::seconds(1);

struct Alias {
    int code;
    hal::Key key;
};

// Codes outside hal::Key that remotes commonly send for the same function.
constexpr Alias kAliases[] = {
    {KEY_MODE, hal::Key::Mode3d},
    {KEY_PLAYCD, hal::Key::Play},
    {KEY_PAUSECD, hal::Key::Pause},
    {KEY_STOPCD, hal::Key::Stop},
    {KEY_SELECT, hal::Key::Ok},
    {KEY_SPACE, hal::Key::PlayPause},
    {KEY_ESC, hal::Key::Exit},
    {KEY_PAGEUP, hal::Key::ChannelUp},
    {KEY_PAGEDOWN, hal::Key::ChannelDown},
};

Result<RepeatPolicy> repeatPolicy(const hal::OptionList &options)
{
    const auto text = options.find("repeat");
    if (!text || *text == "nav")
        return RepeatPolicy::Navigation;
    if (*text == "all")
        return RepeatPolicy::All;
    if (*text == "none")
        return RepeatPolicy::None;
    return unexpected(Errc::InvalidArgument, "Option repeat must be nav, all or none");
}

} // namespace

bool isContinuousKey(hal::Key key) noexcept
{
    switch (key) {
    case hal::Key::Up:
    case hal::Key::Down:
    case hal::Key::Left:
    case hal::Key::Right:
    case hal::Key::FastForward:
    case hal::Key::Rewind:
    case hal::Key::VolumeUp:
    case hal::Key::VolumeDown:
    case hal::Key::ChannelUp:
    case hal::Key::ChannelDown:
        return true;
    default:
        return false;
    }
}

hal::Key keyFromEvdevCode(int code) noexcept
{
    const hal::Key key = hal::keyFromCode(code);
    if (key != hal::Key::Unknown)
        return key;
    for (const Alias &a : kAliases)
        if (a.code == code)
            return a.key;
    return hal::Key::Unknown;
}

Result<std::unique_ptr<hal::RemoteInput>> EvdevRemoteInput::create(const hal::BackendConfig &cfg)
{
    const std::string_view unknown =
        cfg.options.firstUnknownKey(kOptionKeys, std::size(kOptionKeys));
    if (!unknown.empty()) {
        DT_LOG(Evdev, Error, "Unknown evdev option '%.*s' (device, grab, repeat)",
               static_cast<int>(unknown.size()), unknown.data());
        return unexpected(Errc::InvalidArgument, "Unknown evdev remote input option");
    }
    const Result<bool> grab = cfg.options.getBool("grab", false);
    if (!grab)
        return unexpected(grab.error());
    DT_TRY(repeatPolicy(cfg.options));

    std::string path;
    if (const auto device = cfg.options.find("device"))
        path = std::string(*device);
    else if (!cfg.device.empty())
        path = std::string(cfg.device);
    if (cfg.awaitDevice) {
        // The device may come and go: the same path, or the first with media keys, each time.
        HotplugEventSource::Opener open = [path, grab = *grab]() {
            if (!path.empty())
                return openLibevdevSource(path, grab);
            Result<std::string> found = findRemoteDevice();
            if (!found)
                return Result<std::unique_ptr<EventSource>>(unexpected(found.error()));
            return openLibevdevSource(*found, grab);
        };
        auto source = std::make_unique<HotplugEventSource>(std::move(open), kHotplugRetry);
        source->look(cfg.clockRef().now());
        Result<std::unique_ptr<EvdevRemoteInput>> remote = createWithSource(cfg, std::move(source));
        if (!remote)
            return unexpected(remote.error());
        return std::unique_ptr<hal::RemoteInput>(std::move(*remote));
    }
    if (path.empty()) {
        Result<std::string> found = findRemoteDevice();
        if (!found)
            return unexpected(found.error());
        path = std::move(*found);
    }
    Result<std::unique_ptr<EventSource>> source = openLibevdevSource(path, *grab);
    if (!source)
        return unexpected(source.error());
    DT_LOG(Evdev, Info, "Reading remote keys from %s", path.c_str());
    Result<std::unique_ptr<EvdevRemoteInput>> remote = createWithSource(cfg, std::move(*source));
    if (!remote)
        return unexpected(remote.error());
    return std::unique_ptr<hal::RemoteInput>(std::move(*remote));
}

Result<std::unique_ptr<EvdevRemoteInput>>
EvdevRemoteInput::createWithSource(const hal::BackendConfig &cfg,
                                   std::unique_ptr<EventSource> source)
{
    if (!source)
        return unexpected(Errc::InvalidArgument, "No event source");
    const Result<RepeatPolicy> repeat = repeatPolicy(cfg.options);
    if (!repeat)
        return unexpected(repeat.error());
    return std::make_unique<EvdevRemoteInput>(std::move(source), cfg.clockRef(), *repeat);
}

EvdevRemoteInput::EvdevRemoteInput(std::unique_ptr<EventSource> source, platform::Clock &clock,
                                   RepeatPolicy repeat) noexcept
    : source_(std::move(source)), clock_(clock), repeat_(repeat)
{
}

Result<hal::KeyEvent> EvdevRemoteInput::poll(hal::Deadline until)
{
    if (gone_)
        return unexpected(Errc::NoDevice, "Input device unplugged");
    for (;;) {
        Result<input_event> ev = source_->next(clock_, until);
        if (!ev) {
            if (ev.error().code == Errc::NoDevice) {
                DT_LOG(Evdev, Warning, "Remote control input device went away");
                gone_ = true;
            }
            return unexpected(ev.error());
        }
        if (ev->type != EV_KEY)
            continue;
        const hal::Key key = keyFromEvdevCode(ev->code);
        if (key == hal::Key::Unknown)
            continue;
        hal::KeyAction action;
        switch (ev->value) {
        case 0:
            action = hal::KeyAction::Release;
            break;
        case 1:
            action = hal::KeyAction::Press;
            break;
        case 2:
            action = hal::KeyAction::Repeat;
            if (repeat_ == RepeatPolicy::None ||
                (repeat_ == RepeatPolicy::Navigation && !isContinuousKey(key)))
                continue;
            break;
        default:
            continue;
        }
        return hal::KeyEvent{key, action, clock_.now()};
    }
}

} // namespace depthtouch::drivers
