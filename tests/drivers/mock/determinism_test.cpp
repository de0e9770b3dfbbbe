// Two runs of the same scripted session on fresh ManualClocks give bit-identical outputs.
#include <cstring>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_depth_camera.h"
#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_remote_input.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::hashImage;
using testing::hashValue;

/// Runs every mock backend through a short scripted session and hashes all it produced.
std::uint64_t runSession()
{
    platform::ManualClock clock;
    std::uint64_t h = 1469598103934665603ull;

    // Decode both streams of a synthetic file with one damaged packet.
    MockMediaSettings ms;
    ms.width = 24;
    ms.height = 16;
    ms.frames = 12;
    MockMediaSource src(ms);
    src.corruptPacket(5);
    EXPECT_TRUE(src.open("mock:"));
    MockVideoDecoder color(clock);
    MockVideoDecoder depth(clock);
    EXPECT_TRUE(color.configure(hal::StreamConfig::fromStream(src.info().streams[0])));
    EXPECT_TRUE(depth.configure(hal::StreamConfig::fromStream(src.info().streams[1])));
    while (auto p = src.readPacket()) {
        MockVideoDecoder &dec = p->streamIndex == 0 ? color : depth;
        EXPECT_TRUE(dec.queuePacket(*p));
        auto f = dec.dequeueFrame(clock.now() + milliseconds(10));
        EXPECT_TRUE(f);
        if (f) {
            h = hashImage((*f)->image, h);
            h = hashValue(h, (*f)->pts.count());
            h = hashValue(h, (*f)->corrupt);
        }
        clock.advance(milliseconds(20));
    }

    // Present a few frames, one late.
    MockDisplay display(clock);
    EXPECT_TRUE(display.open({}));
    for (int i = 0; i < 5; ++i) {
        if (i == 3)
            clock.advance(milliseconds(40));
        auto info = display.present();
        EXPECT_TRUE(info);
        if (info) {
            h = hashValue(h, info->vsyncTime.time_since_epoch().count());
            h = hashValue(h, info->skippedVsyncs);
        }
    }

    // A servo loop over a scripted hand, 1 ms steps.
    MockHapticDevice hand(clock);
    const platform::TimePoint t0 = clock.now();
    hand.setWaypoints({{t0, {0.0, 0.0, 0.04}, 0},
                       {t0 + milliseconds(30), {0.01, -0.02, -0.03}, 1},
                       {t0 + milliseconds(60), {0.0, 0.0, 0.0}, 0}});
    EXPECT_TRUE(hand.open());
    for (int i = 0; i < 80; ++i) {
        hal::HapticState s;
        EXPECT_TRUE(hand.read(s));
        h = hashValue(h, s.position.x);
        h = hashValue(h, s.position.y);
        h = hashValue(h, s.position.z);
        h = hashValue(h, s.time.time_since_epoch().count());
        EXPECT_TRUE(hand.commandForce(hal::Vec3{0.0, 0.0, -800.0 * s.position.z}));
        clock.advance(milliseconds(1));
    }
    h = hashValue(h, hand.maxForceMagnitude());

    // Keys.
    MockRemoteInput remote(clock);
    auto script = parseKeyScript("KEY_PLAYPAUSE@0.01+KEY_RIGHT@0.02");
    EXPECT_TRUE(script);
    if (script)
        for (hal::KeyEvent e : *script) {
            e.time += clock.now().time_since_epoch();
            remote.push(e);
        }
    while (auto e = remote.poll(clock.now() + milliseconds(500))) {
        h = hashValue(h, e->key);
        h = hashValue(h, e->time.time_since_epoch().count());
    }

    // Camera frames.
    MockDepthCamera camera(clock);
    hal::CameraConfig cc;
    cc.width = 160;
    cc.height = 120;
    cc.fps = 30.0;
    EXPECT_TRUE(camera.configure(cc));
    EXPECT_TRUE(camera.start());
    for (int i = 0; i < 3; ++i) {
        auto c = camera.capture(clock.now() + milliseconds(100));
        EXPECT_TRUE(c);
        if (c) {
            h = hashImage(c->depth->image, h);
            h = hashImage(c->color->image, h);
            h = hashValue(h, c->depth->time.time_since_epoch().count());
        }
    }
    return h;
}

TEST(MockDeterminismTest, twoRunsGiveIdenticalOutputs)
{
    const std::uint64_t first = runSession();
    const std::uint64_t second = runSession();
    EXPECT_EQ(first, second);
    EXPECT_NE(first, 1469598103934665603ull); // something was hashed
}

} // namespace
} // namespace depthtouch::drivers
