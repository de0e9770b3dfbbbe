// The player's sound (playback::AudioPlayer) on simulated time: a source whose every sample says
// which frame of the sound it is, a sound card simulated on a ManualClock (drivers::
// PacedAudioOutput) that keeps what it was given. Checked against the source's own numbering and
// the clock: where the sound starts (sample-accurate, silence before the source's first sample),
// the audio clock (the media time heard, which the picture follows), pause, a seek's restart, the
// volume's gain and its 10 ms ramp (no click), joins without a click (every start fades in, every
// cut fades out: judged on what the card played), mute, the end of the sound and an unplugged
// device.
#include "depthtouch/playback/audio_player.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <vector>

#include "depthtouch/drivers/common/paced_audio_output.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::playback {
namespace {

using std::chrono::milliseconds;

constexpr int kRate = 48000;

/// Mono sound whose frame i (from its first) has the value value(i); it starts at media time
/// `begin` and lasts `length` seconds.
class NumberedSource final : public hal::AudioSource {
public:
    NumberedSource(double begin, double length) : begin_(begin), frames_(framesOf(length)) {}

    static std::int16_t value(std::int64_t i) { return static_cast<std::int16_t>(i % 30000); }
    static std::int64_t framesOf(double seconds) { return std::llround(seconds * kRate); }

    [[nodiscard]] hal::AudioFormat format() const noexcept override { return {kRate, 1}; }
    [[nodiscard]] Result<hal::PcmBlock> read(std::int16_t *samples, std::size_t frames) override
    {
        hal::PcmBlock b;
        b.start = begin_ + static_cast<double>(next_) / kRate;
        const std::int64_t n =
            std::min<std::int64_t>(static_cast<std::int64_t>(frames), frames_ - next_);
        for (std::int64_t i = 0; i < n; ++i)
            samples[i] = level_ >= 0 ? level_ : value(next_ + i);
        b.frames = static_cast<std::size_t>(std::max<std::int64_t>(n, 0));
        next_ += n;
        return b;
    }
    [[nodiscard]] Result<void> seek(double seconds) override
    {
        next_ = std::clamp<std::int64_t>(framesOf(seconds - begin_), 0, frames_);
        return ok();
    }
    /// Every sample \a level instead of its number (a steady tone for the volume).
    void setLevel(std::int16_t level) { level_ = level; }

private:
    double begin_;
    std::int64_t frames_;
    std::int64_t next_ = 0;
    std::int16_t level_ = -1;
};

/// The simulated sound card, keeping every sample it played (a flush drops the rest).
class KeepingOutput final : public drivers::PacedAudioOutput {
public:
    KeepingOutput(platform::Clock &clock, const drivers::PacedAudioSettings &s)
        : PacedAudioOutput(clock, s)
    {
    }
    std::vector<std::int16_t> kept;
    /// Runs after every answer to delayFrames(): the audio thread descheduled between asking for
    /// the queue and acting on the answer (a loaded machine), while the card plays on.
    std::function<void()> afterDelay;

private:
    Result<std::size_t> delayDevice() override
    {
        auto d = PacedAudioOutput::delayDevice();
        if (afterDelay)
            afterDelay();
        return d;
    }
    Result<void> keep(const std::int16_t *samples, std::size_t frames) override
    {
        kept.insert(kept.end(), samples, samples + frames);
        return ok();
    }
};

class AudioPlayerTest : public ::testing::Test {
protected:
    void make(double begin = 0.0, double length = 10.0, AudioPlayerConfig config = {},
              double unplugSeconds = 0.0)
    {
        drivers::PacedAudioSettings s;
        s.bufferMs = 500.0;
        s.unplugSeconds = unplugSeconds;
        source_ = std::make_unique<NumberedSource>(begin, length);
        output_ = std::make_unique<KeepingOutput>(clock_, s);
        auto p = AudioPlayer::create(*source_, *output_, clock_, config);
        ASSERT_TRUE(p) << p.error().what;
        player_ = std::move(*p);
    }
    /// Runs the audio thread's turns every 25 ms for \a ms.
    void play(int ms)
    {
        for (int t = 0; t < ms; t += 25) {
            player_->step();
            clock_.advance(milliseconds(25));
        }
        player_->step();
    }
    /// The media time heard now, from the published clock.
    double heardNow() const
    {
        const MasterClock c = player_->clock();
        return c.mediaTime + platform::toSeconds(clock_.now() - c.at);
    }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance};
    std::unique_ptr<NumberedSource> source_;
    std::unique_ptr<KeepingOutput> output_;
    std::unique_ptr<AudioPlayer> player_;
};

TEST_F(AudioPlayerTest, theSoundStartsAtTheStartTimeToTheSample)
{
    make();
    player_->start(1.25);
    play(200);
    ASSERT_GE(output_->kept.size(), 100u);
    // Frame 60000 of the source is media time 1.25 s; the sound fades in over 10 ms (480 frames:
    // frame i at gain (i + 1) / 480), then plays as it is.
    for (std::size_t i = 0; i < 1000; ++i) {
        const double gain = std::min(1.0, static_cast<double>(i + 1) / 480.0);
        const double want = NumberedSource::value(60000 + static_cast<std::int64_t>(i)) * gain;
        ASSERT_NEAR(output_->kept[i], want, 0.5) << "frame " << i;
    }
    const AudioStats st = player_->stats();
    EXPECT_EQ(st.silenceFrames, 0u);
    EXPECT_EQ(st.underruns, 0u);
}

TEST_F(AudioPlayerTest, whereTheSourceHasNoSoundYetSilencePlaysUntilItsFirstSample)
{
    make(/*begin=*/0.2);
    player_->start(0.0);
    play(400);
    const auto gap = static_cast<std::size_t>(0.2 * kRate);
    ASSERT_GT(output_->kept.size(), gap + 10);
    EXPECT_TRUE(std::all_of(output_->kept.begin(), output_->kept.begin() + gap,
                            [](std::int16_t v) { return v == 0; }));
    for (std::size_t i = 0; i < 10; ++i) // fading in from the source's first sample
        EXPECT_NEAR(output_->kept[gap + i],
                    NumberedSource::value(static_cast<std::int64_t>(i)) *
                        static_cast<double>(i + 1) / 480.0,
                    0.5);
    EXPECT_EQ(output_->kept[gap + 480], NumberedSource::value(480));
    EXPECT_EQ(player_->stats().silenceFrames, gap);
}

TEST_F(AudioPlayerTest, theClockIsTheMediaTimeTheSpeakerPlays)
{
    AudioPlayerConfig c;
    c.queueSeconds = 0.1;
    make(0.0, 10.0, c);
    EXPECT_FALSE(player_->clock().running); // nothing plays before start()
    player_->start(2.0);
    player_->step();
    // Nothing heard yet: the sound written is 0.1 s ahead of the speaker.
    EXPECT_TRUE(player_->clock().running);
    EXPECT_NEAR(heardNow(), 2.0, 1.0 / kRate);
    EXPECT_NEAR(player_->stats().delaySeconds, 0.1, 1.0 / kRate);
    play(500);
    EXPECT_NEAR(heardNow(), 2.5, 1.0 / kRate);
    // The queue stays near its setting: between three quarters of it and all of it.
    EXPECT_GE(player_->stats().delaySeconds, 0.075 - 1e-9);
    EXPECT_LE(player_->stats().delaySeconds, 0.1 + 1e-9);
}

TEST_F(AudioPlayerTest, pauseStopsTheClockAndResumeGoesOnWhereItStopped)
{
    make();
    player_->start(0.0);
    play(300);
    const double before = heardNow();
    const auto pausedAt = static_cast<std::size_t>(std::llround(before * kRate));
    ASSERT_EQ(output_->kept.size(), pausedAt); // the card keeps what it played
    player_->setPaused(true);
    EXPECT_FALSE(player_->clock().running);
    play(1000);
    EXPECT_FALSE(player_->clock().running);
    EXPECT_EQ(player_->stats().underruns, 0u); // silence kept the device going
    // Heard while paused: the next 10 ms faded out, then silence.
    const auto &k = output_->kept;
    ASSERT_GE(k.size(), pausedAt + 48000); // a second of pause heard
    for (std::size_t i = 0; i < 480; ++i)
        ASSERT_NEAR(k[pausedAt + i],
                    NumberedSource::value(static_cast<std::int64_t>(pausedAt + i)) *
                        (1.0 - static_cast<double>(i + 1) / 480.0),
                    1.0)
            << i;
    EXPECT_TRUE(std::all_of(k.begin() + static_cast<std::ptrdiff_t>(pausedAt + 480), k.end(),
                            [](std::int16_t v) { return v == 0; }));
    // Resumed within one turn of the audio thread, where it stopped...
    player_->setPaused(false);
    player_->step();
    const std::size_t resumedAt = k.size();
    ASSERT_TRUE(player_->clock().running);
    EXPECT_NEAR(heardNow(), before, 2.0 / kRate);
    // ...faded in, then not one frame lost or repeated across the pause.
    play(300);
    ASSERT_GT(k.size(), resumedAt + 9600);
    // The silence queued while paused was dropped: the sound at the pause, at the ramp's first
    // step.
    EXPECT_NEAR(k[resumedAt], NumberedSource::value(static_cast<std::int64_t>(pausedAt)) / 480.0,
                0.5);
    for (std::size_t i = 480; i < 9600; ++i)
        ASSERT_EQ(k[resumedAt + i], NumberedSource::value(static_cast<std::int64_t>(pausedAt + i)))
            << i;
    EXPECT_EQ(player_->stats().underruns, 0u);
}

TEST_F(AudioPlayerTest, aPauseOnABusyMachineFadesOutFromTheLastFrameHeardAndResumesThere)
{
    // GIVEN the numbered sound playing, and an audio thread descheduled for 0.1 ms (5 frames)
    // after each time it asks the card for its queue
    make();
    player_->start(0.0);
    play(300);
    output_->afterDelay = [this] { clock_.advance(std::chrono::microseconds(104)); };
    // WHEN the viewer pauses, and resumes a while later
    player_->setPaused(true);
    play(200);
    const std::size_t resumedAt = output_->kept.size();
    player_->setPaused(false);
    play(100);
    // THEN the card heard every frame once, in order, from the start's fade-in up to the pause
    // (the first frame not at its full level), then the frames that follow it faded out over
    // 10 ms: none heard twice
    const auto &k = output_->kept;
    std::size_t last = 480;
    while (last < k.size() && k[last] == NumberedSource::value(static_cast<std::int64_t>(last)))
        ++last;
    ASSERT_GT(last, static_cast<std::size_t>(kRate / 4));
    for (std::size_t i = 0; i < 480; ++i)
        ASSERT_NEAR(k[last + i],
                    NumberedSource::value(static_cast<std::int64_t>(last + i)) *
                        (1.0 - static_cast<double>(i + 1) / 480.0),
                    1.0)
            << "fade-out frame " << i;
    // AND the resume fades in from that frame (the first sound after the pause's silence)
    std::size_t resumed = resumedAt;
    while (resumed < k.size() && k[resumed] == 0)
        ++resumed;
    ASSERT_GT(k.size(), resumed + 960);
    EXPECT_NEAR(k[resumed], NumberedSource::value(static_cast<std::int64_t>(last)) / 480.0, 0.5);
    for (std::size_t i = 480; i < 960; ++i)
        ASSERT_EQ(k[resumed + i], NumberedSource::value(static_cast<std::int64_t>(last + i)))
            << "resumed frame " << i;
}

TEST_F(AudioPlayerTest, aSeekSilencesAtOnceAndPlaysOnFromTheNewPlace)
{
    make();
    player_->start(0.0);
    play(300);
    const std::size_t heard = output_->kept.size();
    player_->halt();
    player_->step();
    EXPECT_FALSE(player_->clock().running);
    // The 0.1 s queue was dropped; what is left is the fade-out of its first 10 ms.
    EXPECT_EQ(*output_->delayFrames(), 480u);
    play(200); // halted: nothing more is written
    const std::size_t before = output_->kept.size();
    EXPECT_EQ(before, heard + 480);
    EXPECT_NEAR(output_->kept[heard + 240],
                NumberedSource::value(static_cast<std::int64_t>(heard) + 240) * 0.4979, 1.0);
    EXPECT_EQ(output_->kept[before - 1], 0);
    player_->start(5.0);
    play(100);
    ASSERT_GT(output_->kept.size(), before + 480);
    // From the new place, faded in: no step at the join larger than the ramp's
    EXPECT_EQ(output_->kept[before], 0);
    EXPECT_EQ(output_->kept[before + 479], NumberedSource::value(5 * kRate + 479));
    EXPECT_NEAR(heardNow(), 5.1, 1.0 / kRate);
    EXPECT_EQ(player_->stats().underruns, 0u); // the card running dry while halted is none
}

/// The largest step between two neighbouring samples of \a k from \a from on.
int largestStep(const std::vector<std::int16_t> &k, std::size_t from = 1)
{
    int largest = 0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < k.size(); ++i)
        largest = std::max(largest, std::abs(k[i] - k[i - 1]));
    return largest;
}

TEST_F(AudioPlayerTest, noJoinClicksStartPauseResumeSeekAndRestartWhilePlaying)
{
    // GIVEN a steady level of 20000 (any cut without a ramp steps by 20000)
    make();
    source_->setLevel(20000);
    player_->start(0.0);
    play(200);
    player_->setPaused(true); // pause, and resume while the fade-out still plays
    player_->step();
    clock_.advance(milliseconds(4));
    player_->setPaused(false);
    play(200);
    player_->setPaused(true); // a long pause
    play(500);
    player_->setPaused(false);
    play(200);
    player_->halt(); // a seek: halt, then the new place a while later
    play(100);
    player_->start(3.0);
    play(200);
    player_->start(6.0); // a loop's restart while sound plays: the cut and the start cross-fade
    play(200);
    player_->halt();
    play(100);
    // THEN what the card played never steps by more than a ramp's step (20000 / 480 = 41.7)
    const auto &k = output_->kept;
    ASSERT_GT(k.size(), static_cast<std::size_t>(kRate));
    EXPECT_LE(largestStep(k), 42);
    EXPECT_EQ(k.front(), 42); // the first sample is the fade-in's first step: 20000 / 480
    EXPECT_EQ(k.back(), 0);   // and it ends faded out
    // Sound and silence both there: 8 ramps (4 in, 4 out) and full level between them.
    EXPECT_GT(std::count(k.begin(), k.end(), std::int16_t{20000}), 4 * 4800);
    EXPECT_GT(std::count(k.begin(), k.end(), std::int16_t{0}), 4 * 4800);
    EXPECT_EQ(player_->stats().underruns, 0u);
}

TEST_F(AudioPlayerTest, aPauseWhenTheQueueHasNearlyRunDryStillFadesOverTheWholeRamp)
{
    // GIVEN a steady level of 20000 and a 0.1 s queue, the audio thread late until only about
    // 1 ms of sound is left in the device (a loaded machine)
    AudioPlayerConfig c;
    c.queueSeconds = 0.1;
    make(0.0, 10.0, c);
    source_->setLevel(20000);
    player_->start(0.0);
    play(200);
    const double queuedBefore = player_->stats().delaySeconds;
    clock_.advance(std::chrono::microseconds(std::llround((queuedBefore - 0.001) * 1e6)));
    // WHEN the viewer pauses then
    player_->setPaused(true);
    play(100);
    // THEN the fade-out still takes the whole 10 ms ramp (20000 / 480 = 41.7 a sample), taking
    // the sound that would have come next where the queue holds less; no underrun
    const auto &k = output_->kept;
    ASSERT_GT(k.size(), static_cast<std::size_t>(kRate / 5));
    EXPECT_LE(largestStep(k), 42);
    EXPECT_EQ(k.back(), 0);
    EXPECT_EQ(player_->stats().underruns, 0u);
}

TEST_F(AudioPlayerTest, theVolumeIsMpvsCubicGainReachedIn10MsWithoutAClick)
{
    make();
    source_->setLevel(16000);
    player_->start(0.0);
    play(200);
    // The change applies from the next frame written (the card plays what it holds first).
    const auto change = static_cast<std::size_t>(output_->framesWritten());
    player_->setVolume(50.0); // (0.5)^3 = 0.125
    play(300);
    const auto &k = output_->kept;
    EXPECT_EQ(k[change - 1], 16000);
    const std::size_t ramp = kRate / 100; // 10 ms
    EXPECT_EQ(k[change + ramp + 10], 2000);
    EXPECT_EQ(k.back(), 2000);
    // The gain moves at most 1/480 a frame (full scale in 10 ms): the largest step between two
    // samples is 16000 / 480 = 33.3, where an instant change would step by 14000.
    int largest = 0;
    for (std::size_t i = change; i < change + ramp + 10; ++i)
        largest = std::max(largest, std::abs(k[i] - k[i - 1]));
    EXPECT_LE(largest, 34);
    EXPECT_GT(largest, 0);
    player_->setMute(true);
    play(300); // the 0.1 s queued plays first
    EXPECT_EQ(output_->kept.back(), 0);
    EXPECT_TRUE(player_->muted());
    EXPECT_EQ(player_->volume(), 50.0); // kept through mute, as the OSD shows it
    player_->setVolume(1e9);
    EXPECT_EQ(player_->volume(), AudioPlayerConfig::kMaxVolume);
    EXPECT_DOUBLE_EQ(volumeGain(100.0, false), 1.0);
    EXPECT_DOUBLE_EQ(volumeGain(130.0, false), 1.3 * 1.3 * 1.3);
    EXPECT_DOUBLE_EQ(volumeGain(500.0, false), 1.3 * 1.3 * 1.3);
    EXPECT_DOUBLE_EQ(volumeGain(80.0, true), 0.0);
}

TEST_F(AudioPlayerTest, theSoundEndsWhenTheSourceDoesAndTheClockStopsWhenItIsHeard)
{
    AudioPlayerConfig c;
    c.queueSeconds = 0.1;
    make(0.0, /*length=*/0.5, c);
    player_->start(0.0);
    play(450);
    EXPECT_TRUE(player_->clock().running);
    EXPECT_FALSE(player_->stats().ended);
    play(200);
    EXPECT_FALSE(player_->clock().running);
    EXPECT_TRUE(player_->stats().ended);
    EXPECT_EQ(player_->stats().framesWritten, static_cast<std::uint64_t>(kRate / 2));
    // The device ran dry after the last sound: the end, not an underrun, also when a loop starts
    // the sound again at once.
    EXPECT_EQ(output_->underruns(), 1u);
    EXPECT_EQ(player_->stats().underruns, 0u);
}

TEST_F(AudioPlayerTest, aLoopThatStartsTheSoundAgainAfterItRanOutCountsNoUnderrun)
{
    AudioPlayerConfig c;
    c.queueSeconds = 0.1;
    make(0.0, /*length=*/0.5, c);
    player_->start(0.0);
    play(450);                         // all the sound written; the device plays its last 0.05 s
    clock_.advance(milliseconds(200)); // it runs dry before the next turn...
    player_->start(0.0);               // ...which is the loop's start
    play(200);
    EXPECT_GE(output_->underruns(), 1u);
    EXPECT_EQ(player_->stats().underruns, 0u);
    EXPECT_TRUE(player_->clock().running);
}

TEST_F(AudioPlayerTest, aThreadLateForLongerThanTheQueueIsAnUnderrunAndTheSoundGoesOn)
{
    AudioPlayerConfig c;
    c.queueSeconds = 0.1;
    make(0.0, 10.0, c);
    player_->start(0.0);
    play(200);
    EXPECT_EQ(player_->stats().underruns, 0u);
    clock_.advance(milliseconds(300)); // no turn for 0.3 s: the 0.1 s queued runs out
    play(100);
    EXPECT_EQ(player_->stats().underruns, 1u);
    EXPECT_TRUE(player_->clock().running);
    // Nothing of the sound was skipped: it goes on with the next frame of the source.
    for (std::size_t i = 480; i < output_->kept.size(); ++i)
        ASSERT_EQ(output_->kept[i], NumberedSource::value(static_cast<std::int64_t>(i))) << i;
}

TEST_F(AudioPlayerTest, anUnpluggedDeviceEndsTheSoundWithAReasonAndTheClockStops)
{
    make(0.0, 10.0, {}, /*unplugSeconds=*/0.3);
    player_->start(0.0);
    play(600);
    const AudioStats st = player_->stats();
    EXPECT_NE(st.lost.find("unplugged"), std::string::npos) << st.lost;
    EXPECT_FALSE(player_->clock().running);
    EXPECT_EQ(st.framesWritten, static_cast<std::uint64_t>(0.3 * kRate));
    player_->start(1.0); // later commands are no-ops, never a crash
    play(100);
    EXPECT_FALSE(player_->clock().running);
}

/// A device that takes every frame at once and says none is queued (ALSA's `null` PCM).
class InstantOutput final : public drivers::PacedAudioOutput {
public:
    explicit InstantOutput(platform::Clock &clock) : PacedAudioOutput(clock, {}) {}
    std::uint64_t taken = 0;

private:
    Result<std::size_t> writeDevice(const std::int16_t *, std::size_t frames) override
    {
        taken += frames;
        return frames;
    }
    Result<std::size_t> delayDevice() override { return std::size_t{0}; }
};

TEST_F(AudioPlayerTest, aDeviceThatTakesEverythingAtOnceDoesNotRunTheClockAhead)
{
    NumberedSource src(0.0, 10.0);
    InstantOutput out(clock_);
    auto made = AudioPlayer::create(src, out, clock_, {});
    ASSERT_TRUE(made) << made.error().what;
    player_ = std::move(*made);
    player_->start(0.0);
    play(2000);
    // The clock keeps real time (at most 0.5 % fast and 20 ms ahead), where the device's word
    // alone would have it at 8 s (0.1 s queued every 25 ms turn, none ever said queued).
    ASSERT_TRUE(player_->clock().running);
    EXPECT_GE(heardNow(), 2.0 - 1e-9);
    EXPECT_LE(heardNow(), 2.0 * 1.005 + 0.02 + 1e-9);
    // And only that much more than the queue is written.
    EXPECT_LE(out.taken, static_cast<std::uint64_t>((2.0 * 1.005 + 0.02 + 0.1) * kRate) + 1);
    player_.reset(); // before the source and the output it uses go
}

TEST_F(AudioPlayerTest, aConfigOutOfRangeIsRefused)
{
    NumberedSource src(0.0, 1.0);
    drivers::PacedAudioSettings s;
    KeepingOutput out(clock_, s);
    AudioPlayerConfig c;
    c.volume = 131.0;
    EXPECT_EQ(AudioPlayer::create(src, out, clock_, c).error().code, Errc::InvalidArgument);
    c.volume = 100.0;
    c.queueSeconds = 0.0;
    EXPECT_EQ(AudioPlayer::create(src, out, clock_, c).error().code, Errc::InvalidArgument);
}

} // namespace
} // namespace depthtouch::playback
