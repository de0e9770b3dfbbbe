// The `alsa` audio output on libasound's own `null` PCM (alsa-lib's null plugin: a device that
// takes every frame, present on any machine with alsa-lib), so the real library calls run here:
// the probe in the factory, the format set-up, non-blocking writes, the delay, pause, flush, drain
// and close; an ALSA name that is not a PCM is NoDevice (autoprobe then falls back to `null`).
#include "depthtouch/drivers/alsa/alsa_audio_output.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace depthtouch::drivers {
namespace {

using State = hal::AudioOutput::State;

hal::BackendConfig pcm(const char *options)
{
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList(options);
    return cfg;
}

TEST(AlsaAudioOutputTest, playsIntoAlsasNullDeviceThroughTheWholeContract)
{
    auto made = AlsaAudioOutput::create(pcm("device=null,buffer=50"));
    ASSERT_TRUE(made) << made.error().what;
    auto &out = *made;
    ASSERT_TRUE(out->open({48000, 2}));
    EXPECT_EQ(out->state(), State::Open);
    // ALSA chose a buffer near the 50 ms asked for
    EXPECT_GT(out->bufferFrames(), 480u);
    EXPECT_LE(out->bufferFrames(), 48000u);
    std::vector<std::int16_t> tone(2 * 4800, 1000);
    std::size_t sent = 0;
    for (int i = 0; i < 50 && sent < 4800; ++i) {
        auto taken = out->write(tone.data() + 2 * sent, 4800 - sent);
        ASSERT_TRUE(taken) << taken.error().what;
        sent += *taken;
    }
    EXPECT_GT(sent, 0u);
    auto delay = out->delayFrames();
    ASSERT_TRUE(delay) << delay.error().what;
    EXPECT_LE(*delay, sent);
    EXPECT_LE(out->framesPlayed(), sent);
    const auto paused = out->pause(true);
    if (paused) {
        EXPECT_EQ(out->state(), State::Paused);
        ASSERT_TRUE(out->pause(false));
    } else {
        EXPECT_EQ(paused.error().code, Errc::NotSupported);
        EXPECT_EQ(out->state(), State::Open);
    }
    ASSERT_TRUE(out->flush());
    delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(*delay, 0u) << "a flush leaves nothing queued";
    auto taken = out->write(tone.data(), 480);
    ASSERT_TRUE(taken);
    ASSERT_TRUE(out->drain());
    out->close();
    EXPECT_EQ(out->state(), State::Closed);
    // opened again at another format
    ASSERT_TRUE(out->open({44100, 1}));
    out->close();
}

TEST(AlsaAudioOutputTest, aNameThatIsNoPcmIsNoDeviceAndBadOptionsAreRefused)
{
    auto none = AlsaAudioOutput::create(pcm("device=no_such_pcm_here"));
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, Errc::NoDevice);
    for (const char *bad : {"buffer=5", "buffer=x", "devise=null"}) {
        auto r = AlsaAudioOutput::create(pcm(bad));
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument) << bad;
    }
}

} // namespace
} // namespace depthtouch::drivers
