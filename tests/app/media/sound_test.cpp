// The receiver's sound reader (media::AudioReader) on a WAV file written by media::writeWavFile
// from a built-in scene's soundtrack (synthetic::sceneSoundtrack): every sample read back as
// written (PCM is lossless), the blocks' media times, a sample-accurate seek, the end, a file
// without sound, and the soundtrack's events where the picture has them (the click at the clip's
// start, the head's tone loud as it passes the camera and silent where it turns back); a live
// input's sound decoded from the packets its demuxer hands over (in order, at their times); a
// header's rate outside 8..384 kHz refused.
#include "depthtouch/media/audio_reader.h"
#include "depthtouch/media/sound_file.h"
#include "depthtouch/synthetic/soundtrack.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace depthtouch::media {
namespace {

constexpr int kRate = 48000;

class SoundTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = std::filesystem::temp_directory_path() / ("dt-sound-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string path(const char *name) const { return (dir_ / name).string(); }

    /// Reads all of \a reader's sound, checking that the blocks follow each other.
    static std::vector<std::int16_t> readAll(hal::AudioSource &reader, double start)
    {
        std::vector<std::int16_t> all;
        std::vector<std::int16_t> buf(1000);
        double expected = start;
        for (;;) {
            auto b = reader.read(buf.data(), buf.size());
            EXPECT_TRUE(b) << b.error().what;
            if (!b || b->frames == 0)
                break;
            EXPECT_NEAR(b->start, expected, 0.5 / kRate);
            expected = b->start + static_cast<double>(b->frames) / kRate;
            all.insert(all.end(), buf.begin(), buf.begin() + static_cast<long>(b->frames));
        }
        return all;
    }

    std::filesystem::path dir_;
};

TEST_F(SoundTest, aWavFileReadsBackSampleForSampleWithItsMediaTimes)
{
    const auto pcm = synthetic::sceneSoundtrack("head", 2.0, kRate);
    ASSERT_EQ(pcm.size(), 2u * kRate);
    ASSERT_TRUE(writeWavFile(path("head.wav"), pcm, {kRate, 1}));
    auto reader = AudioReader::open(path("head.wav"));
    ASSERT_TRUE(reader) << reader.error().what;
    ASSERT_TRUE(*reader);
    EXPECT_EQ((*reader)->format().sampleRate, kRate);
    EXPECT_EQ((*reader)->format().channels, 1);
    EXPECT_EQ((*reader)->description(), "pcm_s16le 48000 Hz 1 ch");
    EXPECT_EQ(readAll(**reader, 0.0), pcm);
    // Ended: it stays ended until a seek, which finds the sound to the sample.
    std::vector<std::int16_t> buf(10);
    EXPECT_EQ((*reader)->read(buf.data(), buf.size())->frames, 0u);
    ASSERT_TRUE((*reader)->seek(1.25));
    const auto tail = readAll(**reader, 1.25);
    ASSERT_EQ(tail.size(), pcm.size() - 60000);
    EXPECT_TRUE(std::equal(tail.begin(), tail.end(), pcm.begin() + 60000));
}

TEST_F(SoundTest, aLiveInputsSoundIsDecodedFromThePacketsItsDemuxerHandsOver)
{
    // GIVEN a reader of a live stream's PCM sound (48 kHz mono), fed through its packet sink
    hal::AudioStreamInfo stream;
    stream.codec = "pcm_s16le";
    stream.sampleRate = kRate;
    stream.channels = 1;
    auto reader = AudioReader::fromPackets(stream);
    ASSERT_TRUE(reader) << reader.error().what;
    const std::shared_ptr<hal::AudioPacketSink> sink = (*reader)->packetSink();
    ASSERT_TRUE(sink);
    std::vector<std::int16_t> buf(2000);
    // WHEN nothing has come yet THEN it says so: not the end
    auto none = (*reader)->read(buf.data(), buf.size());
    ASSERT_TRUE(none);
    EXPECT_EQ(none->frames, 0u);
    EXPECT_TRUE(none->pending);
    // WHEN three packets of 480 frames come (media time 2.5 s on: a stream tuned in mid-way),
    // the second numbered on from the first
    auto push = [&](int first, double at) {
        std::vector<std::int16_t> pcm(480);
        for (int i = 0; i < 480; ++i)
            pcm[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(first + i);
        hal::Packet p;
        p.audio = true;
        p.data = reinterpret_cast<const std::uint8_t *>(pcm.data());
        p.size = pcm.size() * sizeof(std::int16_t);
        p.pts = std::chrono::duration_cast<hal::Pts>(std::chrono::duration<double>(at));
        sink->push(p); // a copy: pcm goes away
    };
    push(0, 2.5);
    push(480, 2.51);
    push(960, 2.52);
    // THEN every sample comes out once, in order, at its packet's time, then pending again
    std::vector<std::int16_t> got;
    for (int turn = 0; turn < 10; ++turn) {
        auto b = (*reader)->read(buf.data(), buf.size());
        ASSERT_TRUE(b) << b.error().what;
        if (b->frames == 0) {
            EXPECT_TRUE(b->pending);
            break;
        }
        EXPECT_NEAR(b->start, 2.5 + static_cast<double>(got.size()) / kRate, 0.5 / kRate);
        got.insert(got.end(), buf.begin(), buf.begin() + static_cast<long>(b->frames));
    }
    ASSERT_EQ(got.size(), 1440u);
    for (std::size_t i = 0; i < got.size(); ++i)
        ASSERT_EQ(got[i], static_cast<std::int16_t>(i)) << i;
    EXPECT_EQ((*reader)->seek(1.0).error().code, Errc::NotSupported); // one pass, as it comes
    // A codec without a decoder is refused
    stream.codec = "no-such-codec";
    EXPECT_EQ(AudioReader::fromPackets(stream).error().code, Errc::NotSupported);
}

TEST_F(SoundTest, aFileWithoutSoundOpensAsNoneAndANonMediaFileIsRefused)
{
    // A file that is no media at all
    {
        std::FILE *f = std::fopen(path("text.wav").c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs("not a sound\n", f);
        std::fclose(f);
    }
    EXPECT_EQ(AudioReader::open(path("text.wav")).error().code, Errc::InvalidArgument);
    EXPECT_EQ(AudioReader::open(path("missing.wav")).error().code, Errc::InvalidArgument);
    EXPECT_EQ(writeWavFile(path("bad.wav"), {1, 2, 3}, {kRate, 2}).error().code,
              Errc::InvalidArgument); // not whole frames
    EXPECT_EQ(writeWavFile(path("none/x.wav"), {1, 2}, {kRate, 2}).error().code, Errc::Io);
}

TEST_F(SoundTest, aRateOutsideEightTo384KilohertzIsRefusedAsBadAudio)
{
    // GIVEN WAV files whose header gives 1 Hz, 7999 Hz, 384001 Hz and 1e9 Hz (issue 60: 1 Hz was
    // resampled to 48 kHz with buffers sized by the ratio, gigabytes for 8 channels), and the
    // edges 8 kHz and 384 kHz
    const std::vector<std::int16_t> pcm(8 * 4800, 100);
    const auto wavAt = [&](const char *name, std::uint32_t rate) {
        EXPECT_TRUE(writeWavFile(path(name), pcm, {kRate, 8}));
        std::FILE *f = std::fopen(path(name).c_str(), "r+b");
        EXPECT_NE(f, nullptr);
        const std::uint8_t le[4] = {
            static_cast<std::uint8_t>(rate), static_cast<std::uint8_t>(rate >> 8),
            static_cast<std::uint8_t>(rate >> 16), static_cast<std::uint8_t>(rate >> 24)};
        std::fseek(f, 24, SEEK_SET); // the fmt chunk's nSamplesPerSec
        std::fwrite(le, 1, 4, f);
        std::fclose(f);
        return path(name);
    };
    // WHEN each is opened THEN the lying ones are InvalidArgument, the edges open as is
    for (const std::uint32_t rate : {1u, 7999u, 384001u, 1'000'000'000u}) {
        auto reader = AudioReader::open(wavAt("lying.wav", rate));
        ASSERT_FALSE(reader) << rate << " Hz";
        EXPECT_EQ(reader.error().code, Errc::InvalidArgument);
        EXPECT_NE(std::string(reader.error().what).find("8000..384000 Hz"), std::string::npos);
    }
    auto low = AudioReader::open(wavAt("low.wav", 8000));
    ASSERT_TRUE(low && *low);
    EXPECT_EQ((*low)->format().sampleRate, 8000);
    auto high = AudioReader::open(wavAt("high.wav", 384000));
    ASSERT_TRUE(high && *high);
    EXPECT_EQ((*high)->format().sampleRate, 48000); // above what an output takes: resampled
    std::vector<std::int16_t> buf(8 * 2048);
    std::size_t frames = 0;
    for (auto b = (*high)->read(buf.data(), 2048); b && b->frames > 0;
         b = (*high)->read(buf.data(), 2048))
        frames += b->frames;
    EXPECT_NEAR(static_cast<double>(frames), 4800.0 / 8.0, 20.0); // 12.5 ms at 48 kHz
    // AND a live stream's lying rate is refused as well
    hal::AudioStreamInfo stream;
    stream.codec = "pcm_s16le";
    stream.sampleRate = 1;
    stream.channels = 8;
    auto live = AudioReader::fromPackets(stream);
    ASSERT_FALSE(live);
    EXPECT_EQ(live.error().code, Errc::InvalidArgument);
}

TEST_F(SoundTest, theSoundtracksEventsAreThePicturesEvents)
{
    const auto pcm = synthetic::sceneSoundtrack("head", 4.0, kRate);
    const auto peak = [&](double from, double to) {
        int m = 0;
        for (auto i = static_cast<std::size_t>(from * kRate);
             i < static_cast<std::size_t>(to * kRate); ++i)
            m = std::max(m, std::abs(static_cast<int>(pcm[i])));
        return m;
    };
    // The click at the clip's start: half of full scale within its 5 ms, on the tone at its
    // loudest (0.15: the head passes the camera at t = 0)
    EXPECT_NEAR(peak(0.0, 0.005), 0.65 * 32767, 0.02 * 32767);
    // The tone: loud where the head passes the camera (t = 2 s), silent where it turns back
    // (t = 1 s, 3 s: only the 2 ms tick of the turn-around)
    EXPECT_GT(peak(1.95, 2.05), 0.14 * 32767);
    EXPECT_LT(peak(1.003, 1.01), 0.01 * 32767);
    EXPECT_NEAR(peak(1.0, 1.002), 0.3 * 32767, 0.02 * 32767); // the tick alone
    EXPECT_EQ(synthetic::soundtrackEvents("head", 4.0), (std::vector<double>{0.0, 1.0, 3.0}));
    EXPECT_EQ(synthetic::soundtrackEvents("spheres", 4.0), (std::vector<double>{0.0}));
    EXPECT_TRUE(synthetic::sceneSoundtrack("head", 0.0, kRate).empty());
}

} // namespace
} // namespace depthtouch::media
