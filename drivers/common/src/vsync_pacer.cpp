#include "depthtouch/drivers/common/vsync_pacer.h"

#include <cmath>

namespace depthtouch::drivers {

void VsyncPacer::start(platform::TimePoint epoch, double refreshHz) noexcept
{
    epoch_ = epoch;
    refreshHz_ = refreshHz > 0.0 ? refreshHz : 60.0;
    lastBlank_ = 0;
    frames_ = 0;
}

platform::TimePoint VsyncPacer::blank(std::uint64_t k) const noexcept
{
    return epoch_ + platform::fromSeconds(static_cast<double>(k) / refreshHz_);
}

hal::PresentInfo VsyncPacer::next(platform::Clock &clock) noexcept
{
    const platform::TimePoint now = clock.now();
    std::uint64_t k = lastBlank_ + 1;
    if (blank(k) < now) {
        // Late: the frame shows at the first blank at or after now.
        const double elapsed = platform::toSeconds(now - epoch_) * refreshHz_;
        k = elapsed > 0.0 ? static_cast<std::uint64_t>(std::ceil(elapsed)) : 1;
        if (k <= lastBlank_)
            k = lastBlank_ + 1;
        while (blank(k) < now)
            ++k;
    }
    const platform::TimePoint t = blank(k);
    if (t > now)
        clock.sleepUntil(t);
    hal::PresentInfo info;
    info.vsyncTime = t;
    info.skippedVsyncs = static_cast<std::uint32_t>(k - lastBlank_ - 1);
    info.frameCounter = ++frames_;
    lastBlank_ = k;
    return info;
}

hal::PresentInfo VsyncPacer::observe(platform::TimePoint shown) noexcept
{
    const double periods = platform::toSeconds(shown - blank(lastBlank_)) * refreshHz_;
    const auto whole = periods > 1.5 ? static_cast<std::uint64_t>(std::llround(periods)) : 1u;
    const std::uint64_t k = lastBlank_ + whole;
    // Move the grid so that blank k is the observed one: later frames are paced from it.
    epoch_ = shown - platform::fromSeconds(static_cast<double>(k) / refreshHz_);
    hal::PresentInfo info;
    info.vsyncTime = shown;
    info.skippedVsyncs = static_cast<std::uint32_t>(whole - 1);
    info.frameCounter = ++frames_;
    lastBlank_ = k;
    return info;
}

hal::PresentInfo VsyncPacer::follow(platform::Clock &clock, unsigned interval) noexcept
{
    const platform::TimePoint now = clock.now();
    if (interval == 0)
        return observe(now);
    const platform::TimePoint due = blank(lastBlank_ + interval);
    if (now >= due)
        return observe(now);
    clock.sleepUntil(due);
    return observe(due);
}

} // namespace depthtouch::drivers
