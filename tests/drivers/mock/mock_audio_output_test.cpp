// The audio outputs without a sound card (`null`, `mock`, `wav`): the hal::AudioOutput contract
// (states, refused arguments), time kept as a sound card keeps it (frames heard at the sample rate,
// the delay, underruns, pause, flush, drain) on a ManualClock, the mock's faults (unplug, refused
// format), and the WAV file read back by its RIFF chunks, not by the library that wrote it.
#include "depthtouch/drivers/mock/mock_audio_output.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "depthtouch/drivers/backends.h"
#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::configWith;
using testing::errcOf;
using State = hal::AudioOutput::State;

constexpr int kRate = 48000;

/// Frames heard in \a ms milliseconds at kRate.
constexpr std::size_t framesIn(int ms)
{
    return static_cast<std::size_t>(kRate / 1000 * ms);
}

class AudioOutputTest : public ::testing::Test {
protected:
    std::unique_ptr<hal::AudioOutput> make(const char *backend, const char *options = "")
    {
        auto out = createAudioOutput(backend, configWith(&clock_, options));
        EXPECT_TRUE(out) << backend << " " << options;
        return out ? std::move(*out) : nullptr;
    }
    /// Stereo silence of \a frames frames.
    std::vector<std::int16_t> silence(std::size_t frames)
    {
        return std::vector<std::int16_t>(2 * frames);
    }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance};
};

TEST_F(AudioOutputTest, theContractRefusesCallsOutOfStateAndFormatsOutOfRange)
{
    auto out = make("null");
    ASSERT_TRUE(out);
    const auto s = silence(10);
    EXPECT_EQ(out->state(), State::Closed);
    EXPECT_EQ(errcOf(out->write(s.data(), 10)), Errc::InvalidState);
    EXPECT_EQ(errcOf(out->delayFrames()), Errc::InvalidState);
    EXPECT_EQ(errcOf(out->pause(true)), Errc::InvalidState);
    EXPECT_EQ(out->bufferFrames(), 0u);
    for (const hal::AudioFormat bad : {hal::AudioFormat{7999, 2}, hal::AudioFormat{192001, 2},
                                       hal::AudioFormat{48000, 0}, hal::AudioFormat{48000, 9}})
        EXPECT_EQ(errcOf(out->open(bad)), Errc::InvalidArgument)
            << bad.sampleRate << "/" << bad.channels;
    ASSERT_TRUE(out->open({kRate, 2}));
    EXPECT_EQ(out->state(), State::Open);
    EXPECT_EQ(errcOf(out->open({kRate, 2})), Errc::InvalidState);
    EXPECT_EQ(errcOf(out->write(nullptr, 4)), Errc::InvalidArgument);
    auto none = out->write(nullptr, 0);
    ASSERT_TRUE(none);
    EXPECT_EQ(*none, 0u);
    ASSERT_TRUE(out->pause(true));
    EXPECT_EQ(out->state(), State::Paused);
    EXPECT_EQ(errcOf(out->drain()), Errc::InvalidState) << "a paused device never drains";
    out->close();
    EXPECT_EQ(out->state(), State::Closed);
    EXPECT_EQ(out->bufferFrames(), 0u);
}

TEST_F(AudioOutputTest, theNullOutputPlaysAtTheSampleRateAndCountsAnUnderrun)
{
    // GIVEN a null output with a 100 ms buffer at 48 kHz
    auto out = make("null", "buffer=100");
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open({kRate, 2}));
    EXPECT_EQ(out->bufferFrames(), framesIn(100));
    // WHEN more than the buffer is written: it takes what fits, without blocking
    const auto s = silence(framesIn(300));
    const platform::TimePoint t0 = clock_.now();
    auto taken = out->write(s.data(), framesIn(300));
    ASSERT_TRUE(taken);
    EXPECT_EQ(*taken, framesIn(100));
    EXPECT_EQ(clock_.now(), t0);
    // THEN after 25 ms a quarter of it was heard and the rest is the delay
    clock_.advance(milliseconds(25));
    auto delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(out->framesPlayed(), framesIn(25));
    EXPECT_EQ(*delay, framesIn(75));
    // AND what was heard frees room for as much
    taken = out->write(s.data(), framesIn(300));
    ASSERT_TRUE(taken);
    EXPECT_EQ(*taken, framesIn(25));
    // WHEN nothing is written for 150 ms: the 100 ms queued are heard, then the device runs dry
    clock_.advance(milliseconds(150));
    delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(*delay, 0u);
    EXPECT_EQ(out->framesPlayed(), framesIn(125));
    EXPECT_EQ(out->underruns(), 1u);
    // AND the next write starts it again: one underrun, not one per query
    ASSERT_TRUE(out->write(s.data(), framesIn(10)));
    clock_.advance(milliseconds(5));
    ASSERT_TRUE(out->delayFrames());
    EXPECT_EQ(out->framesPlayed(), framesIn(130));
    EXPECT_EQ(out->underruns(), 1u);
}

TEST_F(AudioOutputTest, pauseHoldsTheQueueFlushDropsItDrainPlaysItOut)
{
    auto out = make("null");
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open({kRate, 2}));
    const auto s = silence(framesIn(80));
    ASSERT_TRUE(out->write(s.data(), framesIn(80)));
    clock_.advance(milliseconds(20));
    // paused for a second: nothing heard, nothing lost, no underrun
    ASSERT_TRUE(out->pause(true));
    clock_.advance(milliseconds(1000));
    auto delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(*delay, framesIn(60));
    EXPECT_EQ(out->framesPlayed(), framesIn(20));
    EXPECT_EQ(out->underruns(), 0u);
    // resumed: it plays on from where it was
    ASSERT_TRUE(out->pause(false));
    clock_.advance(milliseconds(30));
    delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(*delay, framesIn(30));
    // a flush (a seek) drops the rest at once and says how much: what played until then (5 ms
    // since the queue was asked for) was heard, not dropped; it is no underrun
    clock_.advance(milliseconds(5));
    const auto dropped = out->flush();
    ASSERT_TRUE(dropped);
    EXPECT_EQ(*dropped, framesIn(25));
    delay = out->delayFrames();
    ASSERT_TRUE(delay);
    EXPECT_EQ(*delay, 0u);
    clock_.advance(milliseconds(100));
    ASSERT_TRUE(out->delayFrames());
    EXPECT_EQ(out->underruns(), 0u);
    EXPECT_EQ(out->framesPlayed(), framesIn(55));
    // drain waits on the clock until the queue is heard, and the silence after is no underrun
    ASSERT_TRUE(out->write(s.data(), framesIn(40)));
    const platform::TimePoint before = clock_.now();
    ASSERT_TRUE(out->drain());
    EXPECT_EQ(clock_.now() - before, milliseconds(40));
    EXPECT_EQ(out->framesPlayed(), framesIn(95));
    clock_.advance(milliseconds(100));
    ASSERT_TRUE(out->delayFrames());
    EXPECT_EQ(out->underruns(), 0u);
}

TEST_F(AudioOutputTest, theMockIsUnpluggedAndRefusesFormatsAsAsked)
{
    auto out = make("mock", "unplug=0.05,refuse_rate=44100,refuse_channels=6");
    ASSERT_TRUE(out);
    EXPECT_EQ(errcOf(out->open({44100, 2})), Errc::NotSupported);
    EXPECT_EQ(errcOf(out->open({kRate, 6})), Errc::NotSupported);
    EXPECT_EQ(out->state(), State::Closed);
    ASSERT_TRUE(out->open({kRate, 2}));
    // 50 ms of sound go out, then the device is gone
    const auto s = silence(framesIn(80));
    auto taken = out->write(s.data(), framesIn(80));
    ASSERT_TRUE(taken);
    EXPECT_EQ(*taken, framesIn(50));
    EXPECT_EQ(errcOf(out->write(s.data(), framesIn(10))), Errc::NoDevice);
    EXPECT_EQ(out->state(), State::Lost);
    EXPECT_EQ(errcOf(out->delayFrames()), Errc::NoDevice);
    EXPECT_EQ(errcOf(out->pause(true)), Errc::NoDevice);
    // closed and opened again, the device is back
    out->close();
    EXPECT_EQ(out->state(), State::Closed);
    ASSERT_TRUE(out->open({kRate, 2}));
    taken = out->write(s.data(), framesIn(10));
    ASSERT_TRUE(taken);
    EXPECT_EQ(*taken, framesIn(10));
}

TEST_F(AudioOutputTest, optionsAreCheckedAndAutoprobeFindsASoundCardOrNull)
{
    testing::expectOptionsRefused(&createMockAudioOutput, configWith(&clock_, ""),
                                  {"bufer=100", "buffer=5", "buffer=x", "unplug=-1"});
    testing::expectOptionsRefused(&createNullAudioOutput, configWith(&clock_, ""),
                                  {"unplug=1", "buffer=3000"});
    // autoprobe: a sound card where ALSA has one, else null (never a simulated one with faults)
    hal::SelectionReport report;
    ASSERT_TRUE(createAudioOutput("", configWith(&clock_, ""), &report));
    EXPECT_TRUE(report.chosen == "alsa" || report.chosen == "null") << report.chosen;
    if (backendNames(BackendKind::AudioOutput).find("alsa") != std::string::npos) {
        hal::BackendConfig missing = configWith(&clock_, "");
        missing.device = "no_such_pcm";
        ASSERT_TRUE(createAudioOutput("alsa,null", missing, &report));
        EXPECT_EQ(report.chosen, "null") << "an ALSA device that is not there falls back to null";
    }
}

/// One RIFF chunk of a WAV file.
struct Chunk {
    std::string id;
    std::vector<char> data;
};

std::vector<Chunk> riffChunks(const std::string &path, std::string &form)
{
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<Chunk> chunks;
    if (bytes.size() < 12)
        return chunks;
    form = std::string(bytes.data(), 4) + std::string(bytes.data() + 8, 4);
    std::size_t at = 12;
    while (at + 8 <= bytes.size()) {
        std::uint32_t size = 0;
        std::memcpy(&size, bytes.data() + at + 4, 4); // little-endian host (x86-64, aarch64)
        Chunk c{std::string(bytes.data() + at, 4), {}};
        const std::size_t end = std::min(bytes.size(), at + 8 + size);
        c.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at + 8),
                      bytes.begin() + static_cast<std::ptrdiff_t>(end));
        chunks.push_back(std::move(c));
        at = end + (size & 1u);
    }
    return chunks;
}

/// The `wav` output's tests: skipped in a build without it (it comes with FFmpeg).
class WavOutputTest : public AudioOutputTest {
protected:
    void SetUp() override
    {
        if (backendNames(BackendKind::AudioOutput).find("wav") == std::string::npos)
            GTEST_SKIP() << "no wav backend in this build (no FFmpeg)";
    }
    /// \return a `wav` output writing the file \a path (removed first) with a \a bufferMs ms
    /// buffer; nullptr, a test failure, where it cannot be made.
    std::unique_ptr<hal::AudioOutput> wav(const std::string &path, int bufferMs)
    {
        std::filesystem::remove(path);
        const std::string options = "path=" + path + ",buffer=" + std::to_string(bufferMs);
        auto made = createAudioOutput("wav", configWith(&clock_, options.c_str()));
        EXPECT_TRUE(made) << made.error().what;
        return made ? std::move(*made) : nullptr;
    }
};

template <class T> T field(const std::vector<char> &data, std::size_t offset)
{
    T v{};
    std::memcpy(&v, data.data() + offset, sizeof v);
    return v;
}

TEST_F(WavOutputTest, theWavOutputWritesEveryFrameItPlayedInOrder)
{
    const std::string path = ::testing::TempDir() + "/dt_audio_output_test.wav";
    auto out = wav(path, 50);
    ASSERT_TRUE(out);
    // GIVEN a 1 kHz tone on the left, its negative on the right, written in 7 ms pieces
    ASSERT_TRUE(out->open({kRate, 2}));
    std::vector<std::int16_t> tone(2 * framesIn(250));
    for (std::size_t i = 0; i < framesIn(250); ++i) {
        const auto v = static_cast<std::int16_t>(std::lround(
            12000.0 * std::sin(2.0 * std::numbers::pi * 1000.0 * static_cast<double>(i) / kRate)));
        tone[2 * i] = v;
        tone[2 * i + 1] = static_cast<std::int16_t>(-v);
    }
    std::size_t sent = 0;
    while (sent < framesIn(250)) {
        auto taken =
            out->write(tone.data() + 2 * sent, std::min(framesIn(7), framesIn(250) - sent));
        ASSERT_TRUE(taken);
        sent += *taken;
        clock_.advance(milliseconds(5));
    }
    ASSERT_TRUE(out->drain());
    EXPECT_EQ(out->framesPlayed(), framesIn(250));
    out->close();
    // THEN the file is a PCM WAV of that format whose samples are the tone, every frame once
    std::string form;
    const std::vector<Chunk> chunks = riffChunks(path, form);
    EXPECT_EQ(form, "RIFFWAVE");
    const Chunk *fmt = nullptr;
    const Chunk *data = nullptr;
    for (const Chunk &c : chunks) {
        fmt = c.id == "fmt " ? &c : fmt;
        data = c.id == "data" ? &c : data;
    }
    ASSERT_NE(fmt, nullptr);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(field<std::uint16_t>(fmt->data, 0), 1u); // WAVE_FORMAT_PCM
    EXPECT_EQ(field<std::uint16_t>(fmt->data, 2), 2u);
    EXPECT_EQ(field<std::uint32_t>(fmt->data, 4), static_cast<std::uint32_t>(kRate));
    EXPECT_EQ(field<std::uint16_t>(fmt->data, 14), 16u);
    ASSERT_EQ(data->data.size(), tone.size() * 2);
    EXPECT_EQ(std::memcmp(data->data.data(), tone.data(), data->data.size()), 0);
}

TEST_F(WavOutputTest, theWavOutputHoldsWhatWasHeardNotWhatAFlushDropped)
{
    const std::string path = ::testing::TempDir() + "/dt_audio_output_flush.wav";
    auto out = wav(path, 200);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open({kRate, 1}));
    // GIVEN 100 ms of frames numbered 1.., of which 40 ms are heard before a flush (a seek)
    std::vector<std::int16_t> first(framesIn(100));
    for (std::size_t i = 0; i < first.size(); ++i)
        first[i] = static_cast<std::int16_t>(i + 1);
    ASSERT_EQ(*out->write(first.data(), first.size()), first.size());
    clock_.advance(milliseconds(40));
    ASSERT_TRUE(out->flush());
    // AND then 30 ms of -7, drained
    const std::vector<std::int16_t> second(framesIn(30), -7);
    ASSERT_EQ(*out->write(second.data(), second.size()), second.size());
    ASSERT_TRUE(out->drain());
    out->close();
    // THEN the file is the 40 ms heard, then the 30 ms: the dropped 60 ms are not in it
    std::string form;
    const Chunk *data = nullptr;
    const std::vector<Chunk> chunks = riffChunks(path, form);
    for (const Chunk &c : chunks)
        data = c.id == "data" ? &c : data;
    ASSERT_NE(data, nullptr);
    ASSERT_EQ(data->data.size(), 2 * framesIn(70));
    std::vector<std::int16_t> heard(framesIn(70));
    std::memcpy(heard.data(), data->data.data(), data->data.size());
    for (std::size_t i = 0; i < framesIn(40); ++i)
        ASSERT_EQ(heard[i], first[i]) << i;
    for (std::size_t i = framesIn(40); i < heard.size(); ++i)
        ASSERT_EQ(heard[i], -7) << i;
}

TEST_F(WavOutputTest, theWavOutputSaysWhenItsFileCannotBeMade)
{
    auto made = createAudioOutput("wav", configWith(&clock_, "path=/nonexistent-dir/x.wav"));
    ASSERT_TRUE(made) << made.error().what;
    EXPECT_EQ(errcOf((*made)->open({kRate, 2})), Errc::Io);
    EXPECT_EQ((*made)->state(), State::Closed);
    EXPECT_NE((*made)->lostOutput().find("'/nonexistent-dir/x.wav'"), std::string::npos)
        << (*made)->lostOutput();
}

TEST_F(WavOutputTest, theWavFileIsUnderItsNameOnlyWhenWhole)
{
    const std::string path = ::testing::TempDir() + "/dt_audio_output_whole.wav";
    const std::string temp = path + ".tmp." + std::to_string(::getpid());
    auto out = wav(path, 50);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open({kRate, 2}));
    const std::vector<std::int16_t> silence(2 * framesIn(100), 0);
    ASSERT_TRUE(out->write(silence.data(), framesIn(40)));
    clock_.advance(milliseconds(60));
    ASSERT_TRUE(out->delayFrames());
    // WHILE it plays, the sound goes to the temporary name beside it: nothing under its name
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_TRUE(std::filesystem::exists(temp));
    out->close();
    // THEN closed, the file is whole under its name (RIFF size = size - 8), no temporary left
    EXPECT_FALSE(std::filesystem::exists(temp));
    EXPECT_EQ(out->lostOutput(), "");
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                  std::istreambuf_iterator<char>()};
    ASSERT_GT(bytes.size(), 44u);
    EXPECT_EQ(field<std::uint32_t>(bytes, 4), bytes.size() - 8);
    std::filesystem::remove(path);
}

TEST_F(WavOutputTest, aFifoWithoutAReaderIsRefusedAtOnce)
{
    const std::string fifo = ::testing::TempDir() + "/dt_audio_output_noreader.fifo";
    std::filesystem::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto made = createAudioOutput("wav", configWith(&clock_, ("path=" + fifo).c_str()));
    ASSERT_TRUE(made) << made.error().what;
    // open(2) with O_NONBLOCK: ENXIO at once instead of waiting for a reader forever
    EXPECT_EQ(errcOf((*made)->open({kRate, 2})), Errc::Io);
    EXPECT_NE((*made)->lostOutput().find("no reader"), std::string::npos) << (*made)->lostOutput();
    std::filesystem::remove(fifo);
}

} // namespace
} // namespace depthtouch::drivers
