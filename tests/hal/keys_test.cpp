#include "depthtouch/hal/remote_input.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

#if __has_include(<linux/input-event-codes.h>)
#include <linux/input-event-codes.h>
#define DT_TEST_HAVE_INPUT_CODES 1
#endif

namespace depthtouch::hal {
namespace {

TEST(KeysTest, everyKeyRoundTripsThroughItsName)
{
    std::size_t count = 0;
    const Key *keys = allKeys(count);
    ASSERT_EQ(count, 37u);
    std::set<std::string> names;
    for (std::size_t i = 0; i < count; ++i) {
        const Key k = keys[i];
        EXPECT_NE(k, Key::Unknown);
        const std::string name = keyName(k);
        EXPECT_EQ(name.rfind("KEY_", 0), 0u) << name;
        EXPECT_EQ(keyFromName(name.c_str()), k) << name;
        EXPECT_EQ(keyFromCode(static_cast<int>(k)), k) << name;
        names.insert(name);
    }
    EXPECT_EQ(names.size(), count);
}

TEST(KeysTest, namesAreForgiving)
{
    EXPECT_EQ(keyFromName("KEY_PLAYPAUSE"), Key::PlayPause);
    EXPECT_EQ(keyFromName("playpause"), Key::PlayPause);
    EXPECT_EQ(keyFromName("PlayPause"), Key::PlayPause);
    EXPECT_EQ(keyFromName("key_fast_forward"), Key::FastForward);
    EXPECT_EQ(keyFromName("3d_mode"), Key::Mode3d);
    EXPECT_EQ(keyFromName("KEY_3D_MODE"), Key::Mode3d);
    EXPECT_EQ(keyFromName("0"), Key::Digit0);
    EXPECT_EQ(keyFromName("OK"), Key::Ok);
    EXPECT_EQ(keyFromName("CHANNEL_UP"), Key::ChannelUp); // mpv's name
    EXPECT_EQ(keyFromName("KEY_CHANNELDOWN"), Key::ChannelDown);
}

TEST(KeysTest, unknownNamesAndCodes)
{
    EXPECT_EQ(keyFromName(nullptr), Key::Unknown);
    EXPECT_EQ(keyFromName(""), Key::Unknown);
    EXPECT_EQ(keyFromName("KEY_"), Key::Unknown);
    EXPECT_EQ(keyFromName("KEY_WARP_DRIVE"), Key::Unknown);
    EXPECT_EQ(keyFromName("PLAYPAUSEX"), Key::Unknown);
    EXPECT_EQ(keyFromCode(1), Key::Unknown); // KEY_ESC is not a remote key
    EXPECT_STREQ(keyName(Key::Unknown), "KEY_RESERVED");
    EXPECT_STREQ(keyName(static_cast<Key>(9999)), "KEY_RESERVED");
    EXPECT_STREQ(keyActionName(KeyAction::Repeat), "repeat");
}

#ifdef DT_TEST_HAVE_INPUT_CODES
TEST(KeysTest, valuesAreTheLinuxCodes)
{
    EXPECT_EQ(static_cast<int>(Key::PlayPause), KEY_PLAYPAUSE);
    EXPECT_EQ(static_cast<int>(Key::Play), KEY_PLAY);
    EXPECT_EQ(static_cast<int>(Key::Pause), KEY_PAUSE);
    EXPECT_EQ(static_cast<int>(Key::Stop), KEY_STOP);
    EXPECT_EQ(static_cast<int>(Key::FastForward), KEY_FASTFORWARD);
    EXPECT_EQ(static_cast<int>(Key::Rewind), KEY_REWIND);
    EXPECT_EQ(static_cast<int>(Key::Up), KEY_UP);
    EXPECT_EQ(static_cast<int>(Key::Down), KEY_DOWN);
    EXPECT_EQ(static_cast<int>(Key::Left), KEY_LEFT);
    EXPECT_EQ(static_cast<int>(Key::Right), KEY_RIGHT);
    EXPECT_EQ(static_cast<int>(Key::Ok), KEY_OK);
    EXPECT_EQ(static_cast<int>(Key::Enter), KEY_ENTER);
    EXPECT_EQ(static_cast<int>(Key::Back), KEY_BACK);
    EXPECT_EQ(static_cast<int>(Key::Exit), KEY_EXIT);
    EXPECT_EQ(static_cast<int>(Key::Menu), KEY_MENU);
    EXPECT_EQ(static_cast<int>(Key::Info), KEY_INFO);
    EXPECT_EQ(static_cast<int>(Key::Mode3d), KEY_3D_MODE);
    EXPECT_EQ(static_cast<int>(Key::ChannelUp), KEY_CHANNELUP);
    EXPECT_EQ(static_cast<int>(Key::ChannelDown), KEY_CHANNELDOWN);
    EXPECT_EQ(static_cast<int>(Key::Digit0), KEY_0);
    EXPECT_EQ(static_cast<int>(Key::Digit1), KEY_1);
    EXPECT_EQ(static_cast<int>(Key::Digit9), KEY_9);
    EXPECT_EQ(static_cast<int>(Key::Red), KEY_RED);
    EXPECT_EQ(static_cast<int>(Key::Green), KEY_GREEN);
    EXPECT_EQ(static_cast<int>(Key::Yellow), KEY_YELLOW);
    EXPECT_EQ(static_cast<int>(Key::Blue), KEY_BLUE);
    EXPECT_EQ(static_cast<int>(Key::VolumeUp), KEY_VOLUMEUP);
    EXPECT_EQ(static_cast<int>(Key::VolumeDown), KEY_VOLUMEDOWN);
    EXPECT_EQ(static_cast<int>(Key::Mute), KEY_MUTE);
    EXPECT_EQ(static_cast<int>(Key::Power), KEY_POWER);
}
#endif

} // namespace
} // namespace depthtouch::hal
