// The real EventSource: libevdev on /dev/input/eventN, with SYN_DROPPED resynchronisation.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <libevdev/libevdev.h>

#include "depthtouch/drivers/common/poll_input.h"
#include "depthtouch/drivers/evdev/evdev_remote_input.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/unique_fd.h"

DT_LOG_CATEGORY(Evdev)

namespace depthtouch::drivers {

namespace {

struct LibevdevDeleter {
    void operator()(libevdev *dev) const noexcept { libevdev_free(dev); }
};
using LibevdevPtr = std::unique_ptr<libevdev, LibevdevDeleter>;

constexpr unsigned kMediaKeys[] = {KEY_PLAYPAUSE, KEY_PLAY,        KEY_PAUSE,  KEY_STOP,
                                   KEY_FASTFORWARD, KEY_REWIND,    KEY_PLAYCD, KEY_STOPCD};

class LibevdevEventSource final : public EventSource {
public:
    LibevdevEventSource(platform::UniqueFd fd, LibevdevPtr dev, std::string path) noexcept
        : fd_(std::move(fd)), dev_(std::move(dev)), path_(std::move(path))
    {
    }
    ~LibevdevEventSource() override
    {
        if (dev_)
            (void)libevdev_grab(dev_.get(), LIBEVDEV_UNGRAB);
    }

    Result<input_event> next(platform::Clock &clock, hal::Deadline until) override
    {
        for (;;) {
            input_event ev{};
            const int rc = libevdev_next_event(
                dev_.get(), syncing_ ? LIBEVDEV_READ_FLAG_SYNC : LIBEVDEV_READ_FLAG_NORMAL, &ev);
            if (rc == LIBEVDEV_READ_STATUS_SUCCESS)
                return ev;
            if (rc == LIBEVDEV_READ_STATUS_SYNC) {
                if (syncing_)
                    return ev; // a state change that the dropped events held
                // SYN_DROPPED: the kernel buffer overflowed. libevdev now replays the difference
                // between its state and the device's as SYNC events.
                DT_LOG(Evdev, Warning, "Events dropped on %s; resynchronising", path_.c_str());
                syncing_ = true;
                continue;
            }
            if (rc == -EAGAIN) {
                if (syncing_) {
                    syncing_ = false;
                    continue;
                }
                DT_TRY(wait(clock, until));
                continue;
            }
            if (rc == -EINTR)
                continue;
            if (rc == -ENODEV)
                return unexpected(Errc::NoDevice, "Input device unplugged", ENODEV);
            return unexpected(Errc::Io, "Failed to read the input device", -rc);
        }
    }

private:
    /// Waits for input until \a until. \return ok when there may be input; Timeout otherwise.
    Result<void> wait(platform::Clock &clock, hal::Deadline until)
    {
        const platform::TimePoint now = clock.now();
        if (now >= until)
            return unexpected(Errc::Timeout, "No key before the deadline");
        short revents = 0;
        const PollResult polled = pollInput(fd_.get(), until - now, revents);
        if (polled == PollResult::Interrupted)
            return ok();
        if (polled == PollResult::Failed)
            return unexpected(Errc::Io, "poll() on the input device failed", errno);
        if (polled == PollResult::Timeout) {
            // Timed out in real time; a clock that is not the real one is brought to the
            // deadline so the caller's loop ends.
            if (clock.now() < until)
                clock.sleepUntil(until);
            return unexpected(Errc::Timeout, "No key before the deadline");
        }
        if ((revents & (POLLERR | POLLHUP | POLLNVAL)) != 0 && (revents & POLLIN) == 0)
            return unexpected(Errc::NoDevice, "Input device unplugged");
        return ok();
    }

    platform::UniqueFd fd_;
    LibevdevPtr dev_;
    std::string path_;
    bool syncing_ = false;
};

Result<std::pair<platform::UniqueFd, LibevdevPtr>> openDevice(const std::string &path)
{
    platform::UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    if (!fd) {
        const int err = errno;
        if (err == EACCES || err == EPERM)
            return unexpected(Errc::PermissionDenied, "Cannot open the input device", err);
        if (err == ENOENT || err == ENODEV || err == ENXIO)
            return unexpected(Errc::NoDevice, "Input device not found", err);
        return unexpected(Errc::Io, "Failed to open the input device", err);
    }
    libevdev *raw = nullptr;
    const int rc = libevdev_new_from_fd(fd.get(), &raw);
    if (rc < 0)
        return unexpected(Errc::InvalidArgument, "Not an input device", -rc); // a bad option
    return std::pair<platform::UniqueFd, LibevdevPtr>(std::move(fd), LibevdevPtr(raw));
}

bool hasMediaKey(const libevdev *dev) noexcept
{
    if (libevdev_has_event_type(dev, EV_KEY) == 0)
        return false;
    return std::any_of(std::begin(kMediaKeys), std::end(kMediaKeys), [dev](unsigned code) {
        return libevdev_has_event_code(dev, EV_KEY, code) != 0;
    });
}

} // namespace

Result<std::unique_ptr<EventSource>> openLibevdevSource(const std::string &path, bool grab)
{
    auto opened = openDevice(path);
    if (!opened) {
        char buf[160];
        DT_LOG(Evdev, Error, "Failed to open %s: %s", path.c_str(),
               opened.error().format(buf, sizeof buf));
        return unexpected(opened.error());
    }
    auto &[fd, dev] = *opened;
    if (grab) {
        const int rc = libevdev_grab(dev.get(), LIBEVDEV_GRAB);
        if (rc < 0)
            return unexpected(Errc::Busy, "Failed to grab the input device", -rc);
    }
    DT_LOG(Evdev, Info, "Opened %s: %s", path.c_str(),
           libevdev_get_name(dev.get()) != nullptr ? libevdev_get_name(dev.get()) : "?");
    return std::unique_ptr<EventSource>(
        std::make_unique<LibevdevEventSource>(std::move(fd), std::move(dev), path));
}

Result<std::string> findRemoteDevice(const std::string &dir)
{
    std::vector<std::pair<int, std::string>> candidates;
    if (DIR *d = ::opendir(dir.c_str())) {
        while (const dirent *e = ::readdir(d)) {
            const std::string name = e->d_name;
            if (name.rfind("event", 0) != 0 || name.size() == 5)
                continue;
            const std::string digits = name.substr(5);
            if (!std::all_of(digits.begin(), digits.end(),
                             [](char c) { return c >= '0' && c <= '9'; }) ||
                digits.size() > 6)
                continue;
            candidates.emplace_back(std::stoi(digits), dir + "/" + name);
        }
        ::closedir(d);
    }
    std::sort(candidates.begin(), candidates.end());
    for (const auto &[number, path] : candidates) {
        (void)number;
        auto opened = openDevice(path);
        if (opened && hasMediaKey(opened->second.get()))
            return path;
    }
    DT_LOG(Evdev, Debug, "No input device with media keys in %s", dir.c_str());
    return unexpected(Errc::NoDevice, "No input device with media keys");
}

} // namespace depthtouch::drivers
