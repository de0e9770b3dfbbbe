// The remote that is plugged in after the start, unplugged and plugged in again
// (HotplugEventSource, hal::BackendConfig::awaitDevice): keys are read while a device is there,
// poll() waits (Timeout, never NoDevice) while none is, and the device is looked for again once a
// retry interval has passed, on a ManualClock.
#include "depthtouch/drivers/evdev/hotplug_event_source.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/evdev/fake_event_source.h"
#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using depthtouch::testing::errcOf;
using platform::ManualClock;
using platform::TimePoint;
using std::chrono::milliseconds;
using std::chrono::seconds;
using test::FakeEventSource;

/// A bus on which a fake remote is plugged in at a time and unplugged at another; the opener
/// counts its calls.
struct Bus {
    ManualClock &clock;
    TimePoint pluggedAt;
    std::vector<TimePoint> opens; ///< When the opener was called.
    FakeEventSource *remote = nullptr;

    HotplugEventSource::Opener opener()
    {
        return [this]() -> Result<std::unique_ptr<EventSource>> {
            opens.push_back(clock.now());
            if (clock.now() < pluggedAt)
                return unexpected(Errc::NoDevice, "No input device with media keys");
            auto source = std::make_unique<FakeEventSource>();
            remote = source.get();
            return std::unique_ptr<EventSource>(std::move(source));
        };
    }
};

class HotplugEventSourceTest : public ::testing::Test {
protected:
    ManualClock clock_{ManualClock::Mode::AutoAdvance, TimePoint(seconds(1))};
    Bus bus_{clock_, TimePoint(seconds(5)), {}, nullptr};
    HotplugEventSource source_{bus_.opener(), seconds(1)};
};

TEST_F(HotplugEventSourceTest, aRemotePluggedInAfterTheStartIsFoundWithinOneRetry)
{
    EXPECT_FALSE(source_.look(clock_.now())) << "nothing on the bus at the start";
    EXPECT_FALSE(source_.connected());
    // The player polls in slices; each poll waits to its deadline with nothing read.
    while (clock_.now() + milliseconds(300) < bus_.pluggedAt) {
        const auto r = source_.next(clock_, clock_.now() + milliseconds(300));
        ASSERT_FALSE(r);
        EXPECT_EQ(errcOf(r), Errc::Timeout) << "an absent remote is waited for, not lost";
        EXPECT_FALSE(source_.connected());
    }
    EXPECT_LE(bus_.opens.size(), 5u) << "looked for at most once a second (4 s absent)";

    while (!source_.connected() && clock_.now() < bus_.pluggedAt + seconds(3))
        (void)source_.next(clock_, clock_.now() + milliseconds(300));
    EXPECT_TRUE(source_.connected());
    ASSERT_NE(bus_.remote, nullptr);
    EXPECT_LE(bus_.opens.back() - bus_.pluggedAt, seconds(1))
        << "found within one retry interval of being plugged in";
    EXPECT_EQ(source_.arrivals(), 1u);

    bus_.remote->pushKey(clock_.now() + milliseconds(10), KEY_PLAYPAUSE, 1);
    Result<input_event> key = unexpected(Errc::Timeout, "");
    for (int i = 0; i < 4 && (!key || key->type != EV_KEY); ++i)
        key = source_.next(clock_, clock_.now() + seconds(1));
    ASSERT_TRUE(key);
    EXPECT_EQ(key->code, KEY_PLAYPAUSE);
}

TEST_F(HotplugEventSourceTest, anUnpluggedRemoteIsWaitedForAndReadAgainWhenItIsBack)
{
    bus_.pluggedAt = clock_.now();
    ASSERT_TRUE(source_.look(clock_.now()));
    FakeEventSource *first = bus_.remote;
    first->pushError(clock_.now() + milliseconds(100), Errc::NoDevice);
    bus_.pluggedAt = clock_.now() + seconds(3); // unplugged for about 3 s

    const auto gone = source_.next(clock_, clock_.now() + milliseconds(500));
    ASSERT_FALSE(gone);
    EXPECT_EQ(errcOf(gone), Errc::Timeout) << "an unplug is never NoDevice to the player";
    EXPECT_FALSE(source_.connected());

    const TimePoint back = bus_.pluggedAt;
    while (!source_.connected() && clock_.now() < back + seconds(3))
        (void)source_.next(clock_, clock_.now() + milliseconds(200));
    EXPECT_TRUE(source_.connected()) << "plugged in again: read again";
    EXPECT_EQ(source_.arrivals(), 2u) << "opened a second time";
    EXPECT_LE(clock_.now() - back, seconds(1) + milliseconds(200));
}

TEST_F(HotplugEventSourceTest, aPastDeadlineDoesNotWaitWhateverTheBus)
{
    const TimePoint start = clock_.now();
    const auto r = source_.next(clock_, start - milliseconds(1));
    EXPECT_EQ(errcOf(r), Errc::Timeout);
    EXPECT_EQ(clock_.now(), start) << "a poll with a past deadline returns at once";
}

} // namespace
} // namespace depthtouch::drivers
