// The evdev remote backend on a fake event stream: key mapping, auto-repeat policy, unplug, and the
// libevdev source's handling of paths that are not input devices.
#include "depthtouch/drivers/evdev/evdev_remote_input.h"

#include <cstdlib>
#include <map>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "drivers/evdev/fake_event_source.h"
#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using depthtouch::testing::errcOf;
using hal::Key;
using hal::KeyAction;
using platform::ManualClock;
using platform::TimePoint;
using std::chrono::milliseconds;
using std::chrono::seconds;
using test::FakeEventSource;

class EvdevRemoteInputTest : public ::testing::Test {
protected:
    std::unique_ptr<EvdevRemoteInput> make(std::string_view options = "")
    {
        auto source = std::make_unique<FakeEventSource>();
        fake_ = source.get();
        cfg_.clock = &clock_;
        cfg_.options = hal::OptionList(options);
        auto r = EvdevRemoteInput::createWithSource(cfg_, std::move(source));
        EXPECT_TRUE(r);
        return r ? std::move(*r) : nullptr;
    }

    /// Every key event until the stream is quiet for 10 s.
    std::vector<hal::KeyEvent> drain(EvdevRemoteInput &remote)
    {
        std::vector<hal::KeyEvent> out;
        for (;;) {
            auto e = remote.poll(clock_.now() + seconds(10));
            if (!e)
                break;
            out.push_back(*e);
        }
        return out;
    }

    ManualClock clock_{ManualClock::Mode::AutoAdvance, TimePoint(seconds(1))};
    hal::BackendConfig cfg_;
    FakeEventSource *fake_ = nullptr;
};

TEST_F(EvdevRemoteInputTest, mapsRemoteKeysAndSkipsOtherEvents)
{
    auto remote = make();
    const TimePoint t = clock_.now() + milliseconds(50);
    fake_->pushKey(t, KEY_PLAYPAUSE, 1);
    fake_->pushKey(t + milliseconds(80), KEY_PLAYPAUSE, 0);
    fake_->pushRaw(t + milliseconds(90), EV_REL, REL_X, 5);
    fake_->pushKey(t + milliseconds(100), KEY_A, 1); // not a remote key
    fake_->pushKey(t + milliseconds(110), KEY_MODE, 1); // alias of KEY_3D_MODE
    fake_->pushKey(t + milliseconds(120), KEY_STOPCD, 1);
    fake_->pushKey(t + milliseconds(130), KEY_3D_MODE, 1);
    fake_->pushKey(t + milliseconds(140), KEY_EXIT, 1);
    fake_->pushKey(t + milliseconds(150), KEY_FASTFORWARD, 7); // unknown value
    fake_->pushKey(t + milliseconds(160), KEY_PAGEUP, 1);      // a keyboard's CH+
    fake_->pushKey(t + milliseconds(170), KEY_CHANNELDOWN, 1);

    const auto events = drain(*remote);

    ASSERT_EQ(events.size(), 8u);
    EXPECT_EQ(events[0].key, Key::PlayPause);
    EXPECT_EQ(events[0].action, KeyAction::Press);
    EXPECT_EQ(events[0].time, t);
    EXPECT_EQ(events[1].action, KeyAction::Release);
    EXPECT_EQ(events[1].time, t + milliseconds(80));
    EXPECT_EQ(events[2].key, Key::Mode3d);
    EXPECT_EQ(events[3].key, Key::Stop);
    EXPECT_EQ(events[4].key, Key::Mode3d);
    EXPECT_EQ(events[5].key, Key::Exit);
    EXPECT_EQ(events[6].key, Key::ChannelUp);
    EXPECT_EQ(events[7].key, Key::ChannelDown);
    EXPECT_EQ(fake_->pending(), 0u);
}

TEST_F(EvdevRemoteInputTest, autoRepeatPassesOnlyForContinuousKeys)
{
    auto remote = make();
    const TimePoint t = clock_.now();
    for (const int key :
         {KEY_FASTFORWARD, KEY_PLAYPAUSE, KEY_UP, KEY_3D_MODE, KEY_REWIND, KEY_CHANNELUP}) {
        const auto code = static_cast<unsigned short>(key);
        fake_->pushKey(t, code, 1);
        fake_->pushKey(t + milliseconds(300), code, 2);
        fake_->pushKey(t + milliseconds(330), code, 2);
        fake_->pushKey(t + milliseconds(350), code, 0);
    }
    std::map<Key, int> repeats;
    for (const hal::KeyEvent &e : drain(*remote))
        if (e.action == KeyAction::Repeat)
            ++repeats[e.key];
    EXPECT_EQ(repeats[Key::FastForward], 2);
    EXPECT_EQ(repeats[Key::Up], 2);
    EXPECT_EQ(repeats[Key::Rewind], 2);
    EXPECT_EQ(repeats[Key::ChannelUp], 2) << "a held CH+ steps the stiffness on";
    EXPECT_EQ(repeats.count(Key::PlayPause), 0u) << "a held toggle must not repeat";
    EXPECT_EQ(repeats.count(Key::Mode3d), 0u);
}

TEST_F(EvdevRemoteInputTest, repeatOptionSelectsThePolicy)
{
    for (const auto &[option, expected] :
         {std::pair<const char *, std::size_t>{"repeat=all", 4}, {"repeat=none", 2}}) {
        auto remote = make(option);
        const TimePoint t = clock_.now();
        fake_->pushKey(t, KEY_PLAYPAUSE, 1);
        fake_->pushKey(t, KEY_PLAYPAUSE, 2);
        fake_->pushKey(t, KEY_RIGHT, 2);
        fake_->pushKey(t, KEY_PLAYPAUSE, 0);
        EXPECT_EQ(drain(*remote).size(), expected) << option;
    }
    cfg_.options = hal::OptionList("repeat=sometimes");
    EXPECT_FALSE(EvdevRemoteInput::createWithSource(cfg_, std::make_unique<FakeEventSource>()));
}

TEST_F(EvdevRemoteInputTest, unplugReportsNoDeviceFromThenOn)
{
    auto remote = make();
    const TimePoint t = clock_.now() + milliseconds(10);
    fake_->pushKey(t, KEY_STOP, 1);
    fake_->pushError(t + milliseconds(20), Errc::NoDevice);
    auto first = remote->poll(t + seconds(1));
    ASSERT_TRUE(first);
    EXPECT_EQ(first->key, Key::Stop);
    auto gone = remote->poll(t + seconds(1));
    ASSERT_FALSE(gone);
    EXPECT_EQ(gone.error().code, Errc::NoDevice);
    fake_->pushKey(clock_.now(), KEY_PLAY, 1);
    auto still = remote->poll(clock_.now() + seconds(1));
    ASSERT_FALSE(still);
    EXPECT_EQ(still.error().code, Errc::NoDevice);
}

TEST(EvdevKeysTest, aliasesAndContinuousKeys)
{
    EXPECT_EQ(keyFromEvdevCode(KEY_PLAYPAUSE), Key::PlayPause);
    EXPECT_EQ(keyFromEvdevCode(KEY_MODE), Key::Mode3d);
    EXPECT_EQ(keyFromEvdevCode(KEY_PLAYCD), Key::Play);
    EXPECT_EQ(keyFromEvdevCode(KEY_PAUSECD), Key::Pause);
    EXPECT_EQ(keyFromEvdevCode(KEY_SPACE), Key::PlayPause);
    EXPECT_EQ(keyFromEvdevCode(KEY_A), Key::Unknown);
    EXPECT_TRUE(isContinuousKey(Key::Left));
    EXPECT_TRUE(isContinuousKey(Key::VolumeUp));
    EXPECT_FALSE(isContinuousKey(Key::PlayPause));
    EXPECT_FALSE(isContinuousKey(Key::Exit));
}

TEST(LibevdevSourceTest, pathsThatAreNotInputDevicesAreRefused)
{
    auto missing = openLibevdevSource("/nonexistent/event0", false);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, Errc::NoDevice);
    // A file that is not an input device is a bad option (play exits 2), not a lost device
    auto notInput = openLibevdevSource("/dev/null", false);
    ASSERT_FALSE(notInput);
    EXPECT_EQ(notInput.error().code, Errc::InvalidArgument);
}

TEST(LibevdevSourceTest, discoveryInADirectoryWithoutInputDevicesFindsNothing)
{
    char tmpl[] = "/tmp/dt-input-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    const std::string dir = tmpl;
    // Files named like event devices that are not input devices.
    for (const char *name : {"event0", "event12", "mouse0"}) {
        const int fd = ::open((dir + "/" + name).c_str(), O_CREAT | O_WRONLY | O_CLOEXEC, 0600);
        ASSERT_GE(fd, 0);
        ::close(fd);
    }
    auto found = findRemoteDevice(dir);
    ASSERT_FALSE(found);
    EXPECT_EQ(found.error().code, Errc::NoDevice);
    for (const char *name : {"event0", "event12", "mouse0"})
        ::unlink((dir + "/" + name).c_str());
    ::rmdir(tmpl);
    EXPECT_FALSE(findRemoteDevice("/nonexistent-input-dir"));
}

TEST(EvdevFactoryTest, optionsAreChecked)
{
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("colour=red");
    EXPECT_EQ(errcOf(EvdevRemoteInput::create(cfg)), Errc::InvalidArgument);
    cfg.options = hal::OptionList("device=/dev/null");
    EXPECT_EQ(errcOf(EvdevRemoteInput::create(cfg)), Errc::InvalidArgument);
}

TEST(EvdevFactoryTest, theBackendsDevicePathIsOpenedWhenNoOptionNamesOne)
{
    // GIVEN "evdev:/dev/null" (the device after the backend's name, no device= option)
    hal::BackendConfig cfg;
    cfg.device = "/dev/null";
    // THEN that path is opened and refused as not an input device (a bad option: exit 2), where
    // an unopened path would read as a missing device
    auto r = EvdevRemoteInput::create(cfg);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::InvalidArgument) << r.error().what;
    // AND a device= option wins over it
    cfg.options = hal::OptionList("device=/nonexistent/event0");
    r = EvdevRemoteInput::create(cfg);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::NoDevice) << r.error().what;
}

TEST(EvdevFactoryTest, anAwaitedRemoteThatIsNotThereIsWaitedFor)
{
    // GIVEN a player that stays up (hal::BackendConfig::awaitDevice) and a remote not plugged in
    ManualClock clock(ManualClock::Mode::AutoAdvance, TimePoint(seconds(1)));
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    cfg.awaitDevice = true;
    cfg.options = hal::OptionList("device=/nonexistent/event0");
    // THEN the backend is made, says it waits, and a poll is a time-out, not a lost device
    auto r = EvdevRemoteInput::create(cfg);
    ASSERT_TRUE(r) << r.error().what;
    EXPECT_TRUE((*r)->awaitingDevice());
    EXPECT_EQ(errcOf((*r)->poll(clock.now() + milliseconds(50))), Errc::Timeout);
    EXPECT_EQ(errcOf((*r)->poll(clock.now() + seconds(2))), Errc::Timeout)
        << "still not there a retry later";
    // AND without awaitDevice the same remote is a missing device, as before
    cfg.awaitDevice = false;
    EXPECT_EQ(errcOf(EvdevRemoteInput::create(cfg)), Errc::NoDevice);
}

} // namespace
} // namespace depthtouch::drivers
