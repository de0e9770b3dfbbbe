// FFmpeg backends on media made at run time with the ffmpeg CLI (label media; skipped without it).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "ffmpeg_test_support.h"

namespace depthtouch::ffmpegtest {
namespace {

using std::chrono::milliseconds;

/// \return a thread that calls \a act after \a delay.
std::thread after(milliseconds delay, std::function<void()> act)
{
    return std::thread([delay, act = std::move(act)] {
        std::this_thread::sleep_for(delay);
        act();
    });
}

class FfmpegMediaTest : public FfmpegCliTest {
protected:
    FfmpegMediaTest() : FfmpegCliTest("dt-ffmpeg-media-test-") {}
    static std::unique_ptr<hal::MediaSource> source(const std::string &options = "")
    {
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(options);
        auto src = drivers::createMediaSource("ffmpeg", cfg);
        EXPECT_TRUE(src);
        return src ? std::move(*src) : nullptr;
    }
    /// \return a source with the live stream \a fifo open and its first \a packets packets read
    /// (a test failure where fewer come); nullptr, a test failure, where it does not open.
    static std::unique_ptr<hal::MediaSource> liveSource(const std::string &fifo, int packets)
    {
        auto src = source();
        if (!src)
            return nullptr;
        const auto opened = src->open(fifo.c_str());
        EXPECT_TRUE(opened);
        if (!opened)
            return nullptr;
        int read = 0;
        while (read < packets && src->readPacket())
            ++read;
        EXPECT_EQ(read, packets);
        return src;
    }
    std::string twoStreamClip()
    {
        const std::string out = tmp_.path("two.mkv");
        EXPECT_TRUE(ffmpeg(
            "-f lavfi -i testsrc=size=64x48:rate=30:duration=1 "
            "-f lavfi -i testsrc=size=64x48:rate=30:duration=1 -map 0 -map 1 "
            "-c:v:0 libx264 -pix_fmt:v:0 yuv420p -g 10 -bf 0 -c:v:1 ffv1 -pix_fmt:v:1 gray -g 1 "
            "-metadata:s:v:0 title=color -metadata:s:v:1 title=depth "
            "-metadata:s:v:1 depth_near=0.5 -metadata:s:v:1 depth_far=4 "
            "-metadata:s:v:1 depth_mapping=inverse_z -metadata:s:v:1 depth_bits=8 "
            "-metadata:s:v:1 depth_occupancy=24 " +
            out));
        return out;
    }
};

TEST_F(FfmpegMediaTest, twoStreamFileListsKindsMetadataAndMatchingPts)
{
    const std::string url = twoStreamClip();
    auto src = source();
    ASSERT_TRUE(src->open(url.c_str()));
    const hal::MediaInfo &info = src->info();
    ASSERT_EQ(info.streams.size(), 2u);
    const hal::StreamInfo &c = info.streams[0];
    const hal::StreamInfo &d = info.streams[1];
    EXPECT_EQ(c.kind, hal::StreamKind::Color);
    EXPECT_EQ(c.title, "color");
    EXPECT_EQ(c.codec, hal::CodecId::H264);
    EXPECT_EQ(c.format, hal::PixelFormat::Yuv420p);
    EXPECT_FALSE(c.extradata.empty());
    EXPECT_EQ(d.kind, hal::StreamKind::Depth);
    EXPECT_EQ(d.title, "depth");
    EXPECT_EQ(d.codec, hal::CodecId::Ffv1);
    EXPECT_EQ(d.format, hal::PixelFormat::Gray8);
    EXPECT_DOUBLE_EQ(d.depth.nearMetres, 0.5);
    EXPECT_DOUBLE_EQ(d.depth.farMetres, 4.0);
    EXPECT_EQ(d.depth.mapping, "inverse_z");
    EXPECT_EQ(d.depth.bits, 8);
    EXPECT_EQ(d.depth.occupancy, 24u);
    EXPECT_EQ(c.depth.occupancy, 0u) << "an untagged stream has no holes";
    for (const auto &s : info.streams) {
        EXPECT_EQ(s.width, 64);
        EXPECT_EQ(s.height, 48);
        EXPECT_DOUBLE_EQ(s.frameRate.toDouble(), 30.0);
    }
    EXPECT_NEAR(std::chrono::duration<double>(info.duration).count(), 1.0, 0.05);
    EXPECT_TRUE(info.seekable);

    std::vector<hal::Pts> pts[2];
    for (int guard = 0; guard < 1000; ++guard) {
        auto p = src->readPacket();
        if (!p) {
            EXPECT_EQ(p.error().code, Errc::EndOfStream);
            break;
        }
        auto &v = pts[p->streamIndex];
        if (!v.empty()) {
            EXPECT_GT(p->pts, v.back()) << "stream " << p->streamIndex;
        }
        v.push_back(p->pts);
    }
    ASSERT_EQ(pts[0].size(), 30u);
    EXPECT_EQ(pts[0], pts[1]) << "color and depth frames share their times";
    EXPECT_EQ(pts[0].front(), hal::Pts{0});
    EXPECT_NEAR(std::chrono::duration<double>(pts[0][3]).count(), 0.1, 0.002);

    // Decoded frames carry the packets' times.
    const Decoded dd = decodeAll(url, hal::StreamKind::Depth);
    const Decoded dc = decodeAll(url, hal::StreamKind::Color);
    EXPECT_EQ(dd.frames.size(), 30u);
    EXPECT_EQ(dc.frames.size(), 30u);
    EXPECT_EQ(dd.pts, pts[1]);
    EXPECT_EQ(dc.pts, pts[0]);
}

// GIVEN a file whose first container stream is sound WHEN opened THEN its video stream is listed
// first (StreamInfo::index 0) with its number in the container (containerIndex 1), by which
// another reader of the file finds it.
TEST_F(FfmpegMediaTest, aVideoStreamAfterASoundStreamKeepsItsContainerNumber)
{
    const std::string mkv = tmp_.path("sound-first.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i sine=duration=0.2 -f lavfi "
                       "-i testsrc=size=64x48:rate=30:duration=0.2 -map 0 -map 1 -c:a pcm_s16le "
                       "-c:v ffv1 " +
                       mkv));
    auto src = source();
    ASSERT_TRUE(src->open(mkv.c_str()));
    const hal::MediaInfo &info = src->info();
    ASSERT_EQ(info.streams.size(), 1u);
    EXPECT_EQ(info.streams[0].index, 0);
    EXPECT_EQ(info.streams[0].containerIndex, 1);
    ASSERT_EQ(info.audio.size(), 1u);
    EXPECT_EQ(info.audio[0].containerIndex, 0);
}

// Lossless round trip: 16-bit PNG frames → FFV1 gray16le in MKV → our decode, bit-exact against
// the PNGs (decoded through the image-sequence path) and against the CLI's own raw decode.
TEST_F(FfmpegMediaTest, ffv1Gray16AndGray8RoundTripBitExact)
{
    for (const std::string fmt : {"gray16be", "gray"}) {
        SCOPED_TRACE(fmt);
        const std::string pngs = tmp_.path(fmt + "-%03d.png");
        const std::string mkv = tmp_.path(fmt + ".mkv");
        const std::string raw = tmp_.path(fmt + ".raw");
        ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=40x30:rate=10:duration=1 -pix_fmt " + fmt +
                           " -start_number 0 " + pngs));
        ASSERT_TRUE(ffmpeg("-framerate 10 -i " + pngs + " -c:v ffv1 -pix_fmt " +
                           (fmt == "gray" ? std::string("gray") : std::string("gray16le")) +
                           " -metadata:s:v:0 title=depth " + mkv));
        ASSERT_TRUE(ffmpeg("-i " + mkv + " -f rawvideo -pix_fmt " +
                           (fmt == "gray" ? std::string("gray") : std::string("gray16le")) + " " +
                           raw));
        const Decoded fromPng = decodeAll(pngs, hal::StreamKind::Depth, "fps=10");
        const Decoded fromMkv = decodeAll(mkv, hal::StreamKind::Depth);
        const hal::PixelFormat want =
            fmt == "gray" ? hal::PixelFormat::Gray8 : hal::PixelFormat::Gray16;
        EXPECT_EQ(fromPng.stream.kind, hal::StreamKind::Depth);
        EXPECT_EQ(fromPng.stream.codec, hal::CodecId::RawVideo);
        EXPECT_EQ(fromPng.stream.format, want);
        EXPECT_DOUBLE_EQ(fromPng.stream.frameRate.toDouble(), 10.0);
        EXPECT_EQ(fromMkv.stream.format, want);
        ASSERT_EQ(fromPng.frames.size(), 10u);
        ASSERT_EQ(fromMkv.frames.size(), 10u);
        EXPECT_EQ(fromPng.pts, fromMkv.pts);
        const std::vector<std::uint8_t> reference = readBytes(raw);
        std::vector<std::uint8_t> ours;
        for (std::size_t i = 0; i < fromMkv.frames.size(); ++i) {
            EXPECT_TRUE(fromPng.frames[i] == fromMkv.frames[i]) << "frame " << i;
            ours.insert(ours.end(), fromMkv.frames[i].begin(), fromMkv.frames[i].end());
        }
        EXPECT_TRUE(ours == reference) << "differs from ffmpeg's own decode";
        if (want == hal::PixelFormat::Gray16) {
            // Really 16-bit: some sample uses the low byte and some the high byte.
            std::set<std::uint16_t> values;
            for (std::size_t i = 0; i + 1 < ours.size(); i += 2) {
                std::uint16_t v;
                std::memcpy(&v, &ours[i], 2);
                values.insert(v);
            }
            EXPECT_GT(*values.rbegin(), 255);
            EXPECT_GT(values.size(), 10u);
        }
    }
}

TEST_F(FfmpegMediaTest, grayH264IsLumaAsIs)
{
    const std::string mkv = tmp_.path("gray264.mkv");
    const std::string raw = tmp_.path("gray264.raw");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -c:v libx264 "
                       "-pix_fmt gray " +
                       mkv));
    // The CLI's decode of the luma with no range conversion.
    ASSERT_TRUE(ffmpeg("-i " + mkv + " -vf extractplanes=y -f rawvideo -pix_fmt gray " + raw));
    const Decoded d = decodeAll(mkv, hal::StreamKind::Depth);
    // libavcodec reports gray H.264 as yuv(j)420p; its SPS says 4:0:0, so it is depth.
    EXPECT_EQ(d.stream.kind, hal::StreamKind::Depth);
    EXPECT_EQ(d.stream.format, hal::PixelFormat::Gray8);
    ASSERT_EQ(d.frames.size(), 15u);
    std::vector<std::uint8_t> luma;
    const std::size_t ySize = 64u * 48u;
    for (const auto &f : d.frames)
        luma.insert(luma.end(), f.begin(), f.begin() + static_cast<std::ptrdiff_t>(ySize));
    EXPECT_TRUE(luma == readBytes(raw));

    // Asking for depth gives Gray8 frames of the same bytes.
    auto src = source();
    ASSERT_TRUE(src->open(mkv.c_str()));
    hal::StreamConfig sc = hal::StreamConfig::fromStream(src->info().streams[0]);
    sc.kind = hal::StreamKind::Depth;
    sc.format = hal::PixelFormat::Gray8;
    hal::BackendConfig cfg;
    auto dec = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_TRUE(dec);
    ASSERT_TRUE((*dec)->configure(sc));
    auto p = src->readPacket();
    ASSERT_TRUE(p);
    ASSERT_TRUE((*dec)->queuePacket(*p));
    ASSERT_TRUE((*dec)->queuePacket(hal::Packet::endOfStream()));
    auto f = (*dec)->dequeueFrame(platform::SteadyClock::instance().now() + milliseconds(500));
    ASSERT_TRUE(f);
    EXPECT_EQ((*f)->image.format, hal::PixelFormat::Gray8);
    EXPECT_EQ((*f)->kind, hal::StreamKind::Depth);
    EXPECT_EQ(std::memcmp((*f)->image.row(0, 0), luma.data(), 64), 0);
}

TEST_F(FfmpegMediaTest, grayH264IsDepthInEveryContainerAndColorH264StaysColor)
{
    // GIVEN untitled one-stream H.264 files: 4:0:0 (8 and 10 bit) in MKV (avcC), MPEG-TS and MP4,
    // and 4:2:0 color
    struct Case {
        const char *name;
        const char *pixFmt;
        hal::StreamKind kind;
        hal::PixelFormat format;
    } cases[] = {
        {"gray.mkv", "gray", hal::StreamKind::Depth, hal::PixelFormat::Gray8},
        {"gray.ts", "gray", hal::StreamKind::Depth, hal::PixelFormat::Gray8},
        {"gray.mp4", "gray", hal::StreamKind::Depth, hal::PixelFormat::Gray8},
        {"gray10.mkv", "gray10le", hal::StreamKind::Depth, hal::PixelFormat::Gray10},
        {"color.mkv", "yuv420p", hal::StreamKind::Color, hal::PixelFormat::Yuv420p},
        {"colorj.ts", "yuvj420p", hal::StreamKind::Color, hal::PixelFormat::Yuv420p},
    };
    for (const Case &c : cases) {
        const std::string path = tmp_.path(c.name);
        ASSERT_TRUE(
            ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.2 -c:v libx264 -pix_fmt " +
                   std::string(c.pixFmt) + " " + path));
        // WHEN opened
        auto src = source();
        ASSERT_TRUE(src->open(path.c_str())) << c.name;
        ASSERT_EQ(src->info().streams.size(), 1u);
        // THEN gray is depth (its luma as it is), color stays color
        EXPECT_EQ(src->info().streams[0].kind, c.kind) << c.name;
        EXPECT_EQ(src->info().streams[0].format, c.format) << c.name;
    }
}

TEST_F(FfmpegMediaTest, nonsenseDepthBitsTagIsIgnored)
{
    // GIVEN a depth stream tagged depth_bits=inf (once: printed as -2147483648 bits)
    const std::string path = tmp_.path("inf.mkv");
    ASSERT_TRUE(
        ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.2 -c:v libx264 -pix_fmt gray "
               "-metadata:s:v:0 title=depth -metadata:s:v:0 depth_bits=inf "
               "-metadata:s:v:0 depth_near=nan -metadata:s:v:0 depth_far=1e999 "
               "-metadata:s:v:0 depth_occupancy=2.5 " +
               path));
    auto src = source();
    ASSERT_TRUE(src->open(path.c_str()));
    const hal::DepthMetadata &m = src->info().streams[0].depth;
    EXPECT_EQ(m.bits, 0);
    EXPECT_EQ(m.nearMetres, 0.0);
    EXPECT_EQ(m.farMetres, 0.0);
    EXPECT_EQ(m.occupancy, 0u) << "a threshold that is not a whole number is ignored";
}

TEST_F(FfmpegMediaTest, aFifoWithoutAWriterTimesOutAndOneWithAWriterIsRead)
{
    // GIVEN a FIFO and a 300 ms source timeout
    const std::string fifo = tmp_.path("in.fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto src = source("timeout_ms=300");
    // WHEN no writer comes THEN open gives up after that time instead of blocking in open(2): it
    // waited as long as it was told (less the millisecond the wait rounds down), and well under the
    // 10 s default (the bound tells the option from the default; it is no speed goal)
    const auto t0 = std::chrono::steady_clock::now();
    auto r = src->open(fifo.c_str());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Timeout);
    const auto waited = std::chrono::steady_clock::now() - t0;
    EXPECT_GE(waited, std::chrono::milliseconds(299));
    EXPECT_LT(waited, std::chrono::seconds(10));
    // AND with a writer the stream is read to its end
    const std::string clip = twoStreamClip();
    std::thread writer([&] { (void)std::system(("cat '" + clip + "' > '" + fifo + "'").c_str()); });
    auto src2 = source("timeout_ms=5000");
    const bool opened = static_cast<bool>(src2->open(fifo.c_str()));
    int packets = 0;
    while (opened && src2->readPacket())
        ++packets;
    writer.join();
    ASSERT_TRUE(opened);
    EXPECT_EQ(src2->info().streams.size(), 2u);
    EXPECT_EQ(packets, 60);
    EXPECT_FALSE(src2->info().seekable);
}

TEST_F(FfmpegMediaTest, interruptEndsAReadBlockedOnASilentStreamAtOnce)
{
    // GIVEN a live stream (a FIFO) that sent a one-second clip and then went silent, open, on a
    // source with the default 10 s I/O timeout
    const std::string fifo = tmp_.path("live.fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string clip = twoStreamClip();
    LiveFifo sender(fifo, readBytes(clip));
    auto src = liveSource(fifo, 60);
    ASSERT_TRUE(src);
    // WHEN another thread asks the source to stop while the next read waits for data
    std::thread stopper = after(milliseconds(300), [&] { src->interrupt(); });
    const auto t0 = std::chrono::steady_clock::now();
    auto blocked = src->readPacket();
    const auto waited = std::chrono::steady_clock::now() - t0;
    stopper.join();
    // THEN that read returns soon after the request (generous bound: 2 s against the 10 s the
    // time-out took before) with Timeout, and the next one fails at once
    ASSERT_FALSE(blocked);
    EXPECT_EQ(blocked.error().code, Errc::Timeout);
    EXPECT_LT(waited, std::chrono::seconds(2));
    const auto t1 = std::chrono::steady_clock::now();
    EXPECT_FALSE(src->readPacket());
    EXPECT_LT(std::chrono::steady_clock::now() - t1, std::chrono::seconds(1));
    src->close();
    sender.stop();
}

TEST_F(FfmpegMediaTest, cancelReadEndsOneBlockedReadAndTheSourceReadsOn)
{
    // GIVEN an MPEG-TS live stream (a FIFO) that sent a one-second clip and then went silent
    const std::string fifo = tmp_.path("cancel.fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string clip = tmp_.path("live.ts");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=1 -c:v libx264 "
                       "-preset ultrafast -pix_fmt yuv420p -f mpegts " +
                       clip));
    LiveFifo sender(fifo, readBytes(clip));
    auto src = liveSource(fifo, 25);
    ASSERT_TRUE(src);
    // WHEN a seek's cancelRead() comes while a read waits for data
    std::thread canceller = after(milliseconds(300), [&] { src->cancelRead(); });
    Result<hal::Packet> blocked = src->readPacket();
    for (int i = 0; i < 10 && blocked; ++i) // the demuxer may still hold a packet or two
        blocked = src->readPacket();
    canceller.join();
    // THEN that read returns with Timeout, once: with data again the source reads on
    ASSERT_FALSE(blocked);
    EXPECT_EQ(blocked.error().code, Errc::Timeout);
    sender.sendAgain();
    EXPECT_TRUE(src->readPacket());
    src->close();
    sender.stop();
}

TEST_F(FfmpegMediaTest, drmPrimeFallsBackToTheSameCpuFrames)
{
    // GIVEN a colour H.264 clip and the software decoder, which cannot export DRM PRIME
    const std::string mkv = tmp_.path("color264.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.2 -c:v libx264 "
                       "-pix_fmt yuv420p " +
                       mkv));
    const auto firstFrame = [&](const char *options, hal::DecoderStats &stats) {
        std::vector<std::uint8_t> bytes;
        auto src = source();
        EXPECT_TRUE(src->open(mkv.c_str()));
        hal::StreamConfig sc = hal::StreamConfig::fromStream(src->info().streams[0]);
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(options);
        auto dec = drivers::createVideoDecoder("ffmpeg", cfg);
        if (!dec || !(*dec)->configure(sc))
            return bytes;
        for (int i = 0; i < 64 && bytes.empty(); ++i) {
            auto p = src->readPacket();
            if (!p || !(*dec)->queuePacket(*p))
                (void)(*dec)->queuePacket(hal::Packet::endOfStream());
            auto f =
                (*dec)->dequeueFrame(platform::SteadyClock::instance().now() + milliseconds(200));
            if (!f)
                continue;
            // THEN the frame has CPU planes and no dma-buf
            EXPECT_TRUE((*f)->dmabuf.empty());
            EXPECT_FALSE((*f)->image.empty());
            const hal::ImageView &img = (*f)->image;
            for (int plane = 0; plane < 3; ++plane) {
                const hal::PlaneLayout l =
                    hal::planeLayout(img.format, img.width, img.height, plane);
                for (int y = 0; y < l.rows; ++y)
                    bytes.insert(bytes.end(), img.row(plane, y), img.row(plane, y) + l.rowBytes);
            }
        }
        stats = (*dec)->stats();
        return bytes;
    };
    // WHEN the first frame is decoded with and without drm-prime
    hal::DecoderStats plainStats, primeStats;
    const auto plain = firstFrame("", plainStats);
    const auto prime = firstFrame("drm-prime", primeStats);
    // THEN both are the same pixels, and no frame was lent as a dma-buf
    ASSERT_FALSE(plain.empty());
    EXPECT_TRUE(prime == plain);
    EXPECT_EQ(primeStats.framesDmaBuf, 0u);
    EXPECT_GE(primeStats.framesDecoded, 1u);
}

TEST_F(FfmpegMediaTest, imageSequenceWithFrameRateOption)
{
    const std::string pngs = tmp_.path("frame-%06d.depth.png");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=32x24:rate=30:duration=0.2 -pix_fmt gray16be "
                       "-start_number 0 " +
                       pngs));
    auto src = source("fps=15");
    ASSERT_TRUE(src->open(pngs.c_str()));
    ASSERT_EQ(src->info().streams.size(), 1u);
    const hal::StreamInfo &s = src->info().streams[0];
    EXPECT_EQ(s.kind, hal::StreamKind::Depth);
    EXPECT_EQ(s.format, hal::PixelFormat::Gray16);
    EXPECT_DOUBLE_EQ(s.frameRate.toDouble(), 15.0);
    std::vector<hal::Pts> pts;
    for (int guard = 0; guard < 100; ++guard) {
        auto p = src->readPacket();
        if (!p)
            break;
        EXPECT_EQ(p->size, 32u * 24u * 2u);
        EXPECT_TRUE(p->keyframe);
        pts.push_back(p->pts);
    }
    ASSERT_EQ(pts.size(), 6u);
    EXPECT_NEAR(std::chrono::duration<double>(pts[3]).count(), 0.2, 1e-6);
    ASSERT_TRUE(src->seek(milliseconds(140)));
    auto p = src->readPacket();
    ASSERT_TRUE(p);
    EXPECT_LE(p->pts, milliseconds(140));
}

TEST_F(FfmpegMediaTest, badInputsGiveClearErrors)
{
    auto src = source();
    auto missing = src->open(tmp_.path("missing.mkv").c_str());
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, Errc::NoDevice);
    EXPECT_EQ(src->state(), hal::MediaSource::State::Closed);

    const std::string text = tmp_.path("text.mkv");
    std::ofstream(text) << "this is not a video file\n";
    auto bad = src->open(text.c_str());
    ASSERT_FALSE(bad);
    EXPECT_TRUE(bad.error().code == Errc::InvalidArgument || bad.error().code == Errc::NotSupported)
        << errcName(bad.error().code);

    const std::string audio = tmp_.path("audio.wav");
    ASSERT_TRUE(ffmpeg("-f lavfi -i sine=duration=0.2 " + audio));
    auto noVideo = src->open(audio.c_str());
    ASSERT_FALSE(noVideo);
    EXPECT_EQ(noVideo.error().code, Errc::InvalidArgument);
    EXPECT_STREQ(noVideo.error().what, "The input has no video stream");
    EXPECT_EQ(src->state(), hal::MediaSource::State::Closed);
}

TEST_F(FfmpegMediaTest, truncatedAndCorruptFilesEndWithoutHanging)
{
    const std::string url = twoStreamClip();
    const std::vector<std::uint8_t> bytes = readBytes(url);
    ASSERT_GT(bytes.size(), 1000u);
    {
        const std::string cut = tmp_.path("cut.mkv");
        std::ofstream(cut, std::ios::binary)
            .write(reinterpret_cast<const char *>(bytes.data()),
                   static_cast<std::streamsize>(bytes.size() * 6 / 10));
        for (auto kind : {hal::StreamKind::Color, hal::StreamKind::Depth}) {
            const Decoded d = decodeAll(cut, kind);
            EXPECT_GT(d.frames.size(), 5u);
            EXPECT_LT(d.frames.size(), 30u);
            EXPECT_EQ(d.stats.framesDecoded + d.stats.framesDropped, d.stats.packetsQueued);
        }
    }
    {
        std::vector<std::uint8_t> damaged = bytes;
        std::mt19937 rng(7);
        for (std::size_t i = damaged.size() / 3; i < damaged.size() * 2 / 3; i += 7)
            damaged[i] = static_cast<std::uint8_t>(rng());
        const std::string bad = tmp_.path("damaged.mkv");
        std::ofstream(bad, std::ios::binary)
            .write(reinterpret_cast<const char *>(damaged.data()),
                   static_cast<std::streamsize>(damaged.size()));
        for (auto kind : {hal::StreamKind::Color, hal::StreamKind::Depth}) {
            const Decoded d = decodeAll(bad, kind);
            EXPECT_GT(d.frames.size(), 0u);
            EXPECT_EQ(d.stats.framesDecoded + d.stats.framesDropped, d.stats.packetsQueued);
        }
    }
}

bool smashMiddle(int index, std::vector<std::uint8_t> &bytes)
{
    if (index < 5 || index > 12 || bytes.size() < 16)
        return false;
    for (std::size_t i = bytes.size() / 4; i < bytes.size(); ++i)
        bytes[i] = static_cast<std::uint8_t>(i * 37u + 11u);
    return true;
}

TEST_F(FfmpegMediaTest, damagedPacketsAreConcealedOrDroppedAndDecodingGoesOn)
{
    const std::string url = twoStreamClip();
    for (auto kind : {hal::StreamKind::Color, hal::StreamKind::Depth}) {
        SCOPED_TRACE(hal::streamKindName(kind));
        const Decoded d = decodeAll(url, kind, "", &smashMiddle);
        EXPECT_EQ(d.packets, 30);
        EXPECT_EQ(d.stats.packetsQueued, 30u);
        EXPECT_EQ(d.stats.framesDecoded + d.stats.framesDropped, 30u);
        if (kind == hal::StreamKind::Color) {
            // H.264 notices the damage; FFV1 level 1 has no slice CRC, so damaged depth decodes
            // silently (only the accounting and the absence of a hang are checked there).
            EXPECT_GT(d.stats.framesConcealed + d.stats.framesDropped, 0u);
        }
        EXPECT_GE(d.frames.size(), 22u) << "frames after the damage still decode";
        EXPECT_EQ(static_cast<std::uint64_t>(std::count(d.corrupt.begin(), d.corrupt.end(), true)),
                  d.stats.framesConcealed);
    }
}

TEST_F(FfmpegMediaTest, aFlushedDecoderLendsNoPictureBeforeTheNextKeyFrame)
{
    // The pictures between a flush() (a seek, a drained stream's resume) and the next key frame
    // predict from pictures the decoder no longer has: libavcodec withholds them and the decoder
    // does not ask for them (no AV_CODEC_FLAG_OUTPUT_CORRUPT): as depth, they would be a made-up
    // surface under the finger. Without the flush the same packets all decode.
    const std::string url = tmp_.path("gop.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.5 -c:v libx264 "
                       "-pix_fmt yuv420p -g 10 -bf 0 " +
                       url));
    auto src = source();
    ASSERT_TRUE(src);
    ASSERT_TRUE(src->open(url.c_str()));
    struct Stored {
        std::vector<std::uint8_t> bytes;
        hal::Pts pts, dts;
        bool keyframe;
    };
    std::vector<Stored> packets;
    while (auto p = src->readPacket())
        packets.push_back({{p->data, p->data + p->size}, p->pts, p->dts, p->keyframe});
    ASSERT_EQ(packets.size(), 15u);
    for (std::size_t i = 0; i < packets.size(); ++i)
        ASSERT_EQ(packets[i].keyframe, i % 10 == 0) << i;
    const int stream = src->info().streams[0].index;
    hal::StreamConfig sc = hal::StreamConfig::fromStream(src->info().streams[0]);
    sc.kind = hal::StreamKind::Depth; // its luma as 8-bit depth
    sc.format = hal::PixelFormat::Gray8;

    for (const std::size_t flushAt : {std::size_t{0}, std::size_t{5}}) {
        SCOPED_TRACE(flushAt == 0 ? "not flushed" : "flushed after 5 packets");
        auto dec = drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
        ASSERT_TRUE(dec);
        ASSERT_TRUE((*dec)->configure(sc));
        std::vector<std::size_t> lent; // packet numbers of the frames lent
        bool corrupt = false;
        const auto takeAll = [&] {
            for (int guard = 0; guard < 100; ++guard) {
                auto f = (*dec)->dequeueFrame(hal::Deadline{});
                if (!f)
                    return f.error().code;
                for (std::size_t i = 0; i < packets.size(); ++i)
                    if (packets[i].pts == (*f)->pts)
                        lent.push_back(i);
                corrupt = corrupt || (*f)->corrupt;
            }
            return Errc::Busy;
        };
        for (std::size_t i = 0; i < packets.size(); ++i) {
            if (i == flushAt && i > 0) {
                ASSERT_TRUE((*dec)->flush());
            }
            hal::Packet p;
            p.streamIndex = stream;
            p.data = packets[i].bytes.data();
            p.size = packets[i].bytes.size();
            p.pts = packets[i].pts;
            p.dts = packets[i].dts;
            p.keyframe = packets[i].keyframe;
            ASSERT_TRUE((*dec)->queuePacket(p));
            EXPECT_EQ(takeAll(), Errc::Timeout) << i;
        }
        ASSERT_TRUE((*dec)->queuePacket(hal::Packet::endOfStream(stream)));
        EXPECT_EQ(takeAll(), Errc::EndOfStream);
        std::vector<std::size_t> want;
        for (std::size_t i = 0; i < packets.size(); ++i)
            if (flushAt == 0 || i < flushAt || i >= 10)
                want.push_back(i);
        EXPECT_EQ(lent, want);
        EXPECT_FALSE(corrupt);
        EXPECT_EQ((*dec)->stats().framesDropped, flushAt == 0 ? 0u : 5u) << "the withheld ones";
    }
}

TEST_F(FfmpegMediaTest, decodesEveryFrameOfAFiveSecond640x480H264Clip)
{
    // The speed goal lives in `depthtouch bench media` (decode + pairing throughput); here the
    // frame rate is only reported.
    const std::string url = tmp_.path("speed.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=640x480:rate=30:duration=5 -c:v libx264 "
                       "-pix_fmt yuv420p " +
                       url));
    const auto t0 = std::chrono::steady_clock::now();
    const Decoded d = decodeAll(url, hal::StreamKind::Color);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(d.frames.size(), 150u);
    EXPECT_EQ(d.stats.framesDecoded, 150u);
    EXPECT_EQ(d.stats.framesDropped, 0u);
    ASSERT_EQ(d.pts.size(), 150u);
    for (std::size_t i = 1; i < d.pts.size(); ++i) {
        EXPECT_GT(d.pts[i], d.pts[i - 1]) << "frame " << i;
    }
    for (const std::vector<std::uint8_t> &f : d.frames) {
        EXPECT_GE(f.size(), 640u * 480u);
    }
    const double fps = 150.0 / s;
    RecordProperty("decode_fps_640x480_h264", std::to_string(fps));
    std::printf("ffmpeg backend: 640x480 H.264 demux+decode+copy %.0f frames/s\n", fps);
}

} // namespace
} // namespace depthtouch::ffmpegtest
