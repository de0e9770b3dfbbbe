#include "ffmpeg_test_support.h"

#include <chrono>
#include <fstream>
#include <iterator>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace depthtouch::ffmpegtest {

bool haveFfmpegCli()
{
    static const bool have = std::system("ffmpeg -version >/dev/null 2>&1") == 0;
    return have;
}

bool ffmpeg(const std::string &args)
{
    const std::string cmd = "ffmpeg -nostdin -hide_banner -v error -y " + args + " </dev/null";
    return std::system(cmd.c_str()) == 0;
}

std::vector<std::uint8_t> readBytes(const std::string &path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

LiveFifo::LiveFifo(std::string path, std::vector<std::uint8_t> clip)
    : path_(std::move(path)), clip_(std::move(clip)), thread_([this] { run(); })
{
}

LiveFifo::~LiveFifo()
{
    stop();
}

void LiveFifo::stop()
{
    quit_.store(true);
    if (thread_.joinable())
        thread_.join();
}

void LiveFifo::run()
{
    // Without a reader a non-blocking open fails (ENXIO): retry, so that stop() always ends this
    // thread, then write blocking as a live source does.
    int fd = -1;
    while (fd < 0 && !quit_.load()) {
        fd = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd < 0)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (fd < 0)
        return;
    (void)::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    int sent = 0;
    while (!quit_.load()) {
        if (sent < sends_.load()) {
            writeClip(fd);
            ++sent;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::close(fd);
}

void LiveFifo::writeClip(int fd) const
{
    std::size_t done = 0;
    while (done < clip_.size()) {
        const ssize_t n = ::write(fd, clip_.data() + done, clip_.size() - done);
        if (n <= 0)
            break;
        done += static_cast<std::size_t>(n);
    }
}

Decoded decodeAll(const std::string &url, hal::StreamKind kind, const std::string &sourceOptions,
                  bool (*mutate)(int index, std::vector<std::uint8_t> &bytes),
                  const std::string &decoderOptions, platform::Clock *sourceClock)
{
    Decoded out;
    hal::BackendConfig srcCfg;
    srcCfg.options = hal::OptionList(sourceOptions);
    srcCfg.clock = sourceClock;
    auto src = drivers::createMediaSource("ffmpeg", srcCfg);
    EXPECT_TRUE(src);
    if (!src)
        return out;
    auto opened = (*src)->open(url.c_str());
    EXPECT_TRUE(opened) << url << ": " << (opened ? "" : opened.error().what);
    if (!opened)
        return out;
    const auto &streams = (*src)->info().streams;
    const hal::StreamInfo *chosen = streams.size() == 1 ? &streams[0] : nullptr;
    for (const auto &s : streams)
        if (chosen == nullptr && s.kind == kind)
            chosen = &s;
    EXPECT_NE(chosen, nullptr);
    if (chosen == nullptr)
        return out;
    out.stream = *chosen;
    hal::BackendConfig decCfg;
    decCfg.options = hal::OptionList(decoderOptions);
    auto dec = drivers::createVideoDecoder("ffmpeg", decCfg);
    EXPECT_TRUE(dec);
    if (!dec)
        return out;
    hal::StreamConfig sc = hal::StreamConfig::fromStream(out.stream);
    auto configured = (*dec)->configure(sc);
    EXPECT_TRUE(configured) << (configured ? "" : configured.error().what);
    if (!configured)
        return out;

    const auto take = [&](hal::Deadline until) -> Errc {
        auto f = (*dec)->dequeueFrame(until);
        if (!f)
            return f.error().code;
        const hal::ImageView &img = (*f)->image;
        std::vector<std::uint8_t> bytes;
        for (int p = 0; p < hal::planeCount(img.format); ++p) {
            const hal::PlaneLayout l = hal::planeLayout(img.format, img.width, img.height, p);
            for (int y = 0; y < l.rows; ++y)
                bytes.insert(bytes.end(), img.row(p, y), img.row(p, y) + l.rowBytes);
        }
        out.frames.push_back(std::move(bytes));
        out.pts.push_back((*f)->pts);
        out.corrupt.push_back((*f)->corrupt);
        return Errc::InvalidArgument; // "a frame": not an error code used below
    };
    const auto soon = [] { return platform::SteadyClock::instance().now(); };
    std::vector<std::uint8_t> copy;
    bool eosQueued = false;
    for (int guard = 0; guard < 200'000; ++guard) {
        if (!eosQueued) {
            auto p = (*src)->readPacket();
            if (!p) {
                out.readEnd = p.error().code;
                EXPECT_TRUE(p.error().code == Errc::EndOfStream || p.error().code == Errc::Io)
                    << errcName(p.error().code);
                // Drain.
                while (!(*dec)->queuePacket(hal::Packet::endOfStream(out.stream.index)))
                    if (take(soon()) == Errc::EndOfStream)
                        break;
                eosQueued = true;
                continue;
            }
            if (p->streamIndex != out.stream.index)
                continue;
            ++out.packets;
            hal::Packet pkt = *p;
            if (mutate != nullptr) {
                copy.assign(p->data, p->data + p->size);
                if (mutate(out.packets - 1, copy)) {
                    pkt.data = copy.data();
                    pkt.size = copy.size();
                }
            }
            for (int tries = 0; tries < 1000; ++tries) {
                auto q = (*dec)->queuePacket(pkt);
                if (q)
                    break;
                EXPECT_EQ(q.error().code, Errc::Busy);
                if (q.error().code != Errc::Busy)
                    break;
                (void)take(soon());
            }
            continue;
        }
        if (take(soon()) == Errc::EndOfStream) {
            out.stats = (*dec)->stats();
            return out;
        }
    }
    ADD_FAILURE() << "decode loop did not end";
    return out;
}

} // namespace depthtouch::ffmpegtest
