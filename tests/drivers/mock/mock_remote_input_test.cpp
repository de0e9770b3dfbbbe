#include "depthtouch/drivers/mock/mock_remote_input.h"

#include <gtest/gtest.h>

#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::at;
using testing::errcOf;

TEST(MockRemoteInputTest, deliversScriptedKeysAtTheirTimes)
{
    platform::ManualClock clock;
    MockRemoteInput remote(clock);
    remote.pushKey(hal::Key::Right, at(300));
    remote.pushKey(hal::Key::PlayPause, at(100), milliseconds(50));
    EXPECT_EQ(remote.pending(), 4u);

    // WHEN polling with a deadline before the first key  THEN Timeout at the deadline
    EXPECT_EQ(errcOf(remote.poll(at(80))), Errc::Timeout);
    EXPECT_EQ(clock.now(), at(80));
    // WHEN polling with a later deadline  THEN the key arrives at its time, not the deadline
    auto e = remote.poll(at(1000));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key, hal::Key::PlayPause);
    EXPECT_EQ(e->action, hal::KeyAction::Press);
    EXPECT_EQ(e->time, at(100));
    EXPECT_EQ(clock.now(), at(100));
    e = remote.poll(at(1000));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->action, hal::KeyAction::Release);
    EXPECT_EQ(e->time, at(150));
    e = remote.poll(at(1000));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key, hal::Key::Right);
    EXPECT_EQ(e->time, at(300));
    // An event already due is returned without waiting.
    clock.advanceTo(at(900));
    e = remote.poll(at(0));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->time, at(400));
    EXPECT_EQ(clock.now(), at(900));
    EXPECT_EQ(remote.pending(), 0u);
}

TEST(MockRemoteInputTest, parsesKeyScripts)
{
    auto events = parseKeyScript(" KEY_PLAYPAUSE@1+right@0.5  3d_mode@2 ");
    ASSERT_TRUE(events);
    ASSERT_EQ(events->size(), 6u);
    EXPECT_EQ((*events)[0].key, hal::Key::Right);
    EXPECT_EQ((*events)[0].time, at(500));
    EXPECT_EQ((*events)[1].action, hal::KeyAction::Release);
    EXPECT_EQ((*events)[1].time, at(600));
    EXPECT_EQ((*events)[2].key, hal::Key::PlayPause);
    EXPECT_EQ((*events)[5].key, hal::Key::Mode3d);
    EXPECT_TRUE(parseKeyScript("")->empty());
    EXPECT_EQ(errcOf(parseKeyScript("KEY_PLAY")), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(parseKeyScript("KEY_NOPE@1")), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(parseKeyScript("KEY_PLAY@-1")), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(parseKeyScript("KEY_PLAY@1s")), Errc::InvalidArgument);
}

TEST(MockRemoteInputTest, keysOptionIsRelativeToCreation)
{
    platform::ManualClock clock(platform::ManualClock::Mode::AutoAdvance, at(5000));
    const hal::BackendConfig cfg = testing::configWith(&clock, "keys=KEY_OK@0.25");
    auto remote = MockRemoteInput::create(cfg);
    ASSERT_TRUE(remote);
    auto e = (*remote)->poll(at(10000));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key, hal::Key::Ok);
    EXPECT_EQ(e->time, at(5250));
    testing::expectOptionsRefused(&MockRemoteInput::create, cfg, {"keys=KEY_OK@x", "key=KEY_OK@1"});
}

TEST(MockRemoteInputTest, unplugReportsNoDeviceAndKeepsTheScript)
{
    platform::ManualClock clock;
    MockRemoteInput remote(clock);
    remote.pushKey(hal::Key::Stop, at(10));
    remote.unplug();
    EXPECT_EQ(errcOf(remote.poll(at(100))), Errc::NoDevice);
    remote.replug();
    auto e = remote.poll(at(100));
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key, hal::Key::Stop);
}

TEST(NullRemoteInputTest, neverDeliversAKey)
{
    platform::ManualClock clock;
    NullRemoteInput remote(clock);
    EXPECT_EQ(errcOf(remote.poll(at(250))), Errc::Timeout);
    EXPECT_EQ(clock.now(), at(250));
}

} // namespace
} // namespace depthtouch::drivers
