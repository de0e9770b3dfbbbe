// libFuzzer target over demux + decode + pairing.
//
// Input: byte 0 picks the demuxer (0 Matroska, 1 MPEG-TS, 2 MP4/MOV, 3 probe); the rest is the
// file, handed to the receiver on the ffmpeg backends as an in-memory file (memfd). The same bytes
// also drive the pairing rules directly (PtsPairer) as a stream of timestamp events, with the
// pairing invariants checked on every output. Any violation traps.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "depthtouch/drivers/ffmpeg/ffmpeg_media_source.h"
#include "depthtouch/drivers/ffmpeg/ffmpeg_video_decoder.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/receiver/pts_pairer.h"
#include "depthtouch/receiver/receiver.h"

namespace {

using namespace depthtouch;
using receiver::PairStream;

void check(bool ok)
{
    if (!ok)
        __builtin_trap();
}

/// Output invariants shared by both paths.
struct OutputChecker {
    hal::Pts last = hal::kNoPts;
    std::uint64_t index = 0;
    void operator()(hal::Pts pts, std::uint64_t idx, bool hasDepth, bool hasNext, hal::Pts depthPts,
                    hal::Pts nextPts, bool missing, bool duplicated)
    {
        check(idx == index++);
        check(pts != hal::kNoPts);
        check(last == hal::kNoPts || pts > last); // strictly increasing output time
        last = pts;
        check(!(missing && hasDepth));
        check(!(duplicated && !hasDepth));
        check(!hasNext || hasDepth);
        check(!hasNext || nextPts > depthPts); // frame i+1 is after frame i
    }
};

/// Pairing rules on timestamp events: 3 bytes each (stream/flags, PTS step, jitter).
void fuzzPairing(const std::uint8_t *data, std::size_t size)
{
    if (size < 3)
        return;
    receiver::PairerConfig cfg;
    cfg.color = (data[0] & 1) == 0 || (data[0] & 2) == 0;
    cfg.depth = (data[0] & 2) == 0 || !cfg.color;
    cfg.window = 1 + (data[1] & 15);
    cfg.colorPeriod = hal::Pts(1'000'000 * (1 + (data[2] & 63)));
    cfg.depthPeriod = hal::Pts(1'000'000 * (1 + (data[2] >> 2)));
    receiver::PtsPairer<int> pairer(cfg);
    OutputChecker checker;
    hal::Pts t[2] = {hal::Pts{0}, hal::Pts{0}};
    receiver::PtsPairer<int>::Output o;
    const auto pullAll = [&] {
        while (pairer.pull(o))
            checker(o.pts, o.index, o.hasDepth, o.hasNext, o.depth.pts, o.depthNext.pts,
                    o.depthMissing, o.depthDuplicated);
    };
    for (std::size_t i = 3; i + 3 <= size; i += 3) {
        const std::uint8_t op = data[i];
        PairStream s = (op & 1) != 0 ? PairStream::Depth : PairStream::Color;
        if ((s == PairStream::Color && !cfg.color) || (s == PairStream::Depth && !cfg.depth))
            s = cfg.color ? PairStream::Color : PairStream::Depth;
        const auto k = static_cast<std::size_t>(s);
        if ((op & 0xf0) == 0xf0) {
            pairer.endOfStream(s);
        } else if ((op & 0xf0) == 0xe0) {
            pairer.resume(s);
        } else if ((op & 0xf0) == 0xd0) {
            pairer.reset();
            checker = OutputChecker{};
        } else {
            t[k] += hal::Pts(static_cast<std::int64_t>(static_cast<std::int8_t>(data[i + 1])) *
                             1'000'000);
            receiver::PtsPairer<int>::Item item;
            item.pts = (op & 2) != 0 ? hal::kNoPts : t[k] + hal::Pts(data[i + 2] * 10'000);
            item.corrupt = (op & 4) != 0;
            item.payload = static_cast<int>(i);
            check(pairer.canPush(s)); // bounded queues: always room after pulling
            (void)pairer.push(s, std::move(item));
        }
        pullAll();
    }
    pairer.endOfStream(PairStream::Color);
    pairer.endOfStream(PairStream::Depth);
    pullAll();
    check(pairer.finished());
}

int memFile()
{
    static const int fd = memfd_create("dt-receiver-fuzz", MFD_CLOEXEC);
    return fd;
}

void fuzzMedia(const std::uint8_t *data, std::size_t size)
{
    static const char *kFormats[] = {"format=matroska", "format=mpegts", "format=mov", ""};
    const int fd = memFile();
    if (fd < 0 || size < 1)
        return;
    if (ftruncate(fd, 0) != 0 ||
        pwrite(fd, data + 1, size - 1, 0) != static_cast<ssize_t>(size - 1))
        return;
    const std::string url = "/proc/self/fd/" + std::to_string(fd);

    hal::BackendConfig srcCfg;
    const std::string options = std::string(kFormats[data[0] & 3]) +
                                (kFormats[data[0] & 3][0] != '\0' ? "," : "") + "timeout_ms=2000";
    srcCfg.options = hal::OptionList(options);
    auto src = drivers::FfmpegMediaSource::create(srcCfg);
    if (!src)
        return;
    receiver::DecoderFactory factory = [](const hal::StreamInfo &) {
        hal::BackendConfig c;
        c.options = hal::OptionList("threads=1,pool=2,queue=4");
        return drivers::FfmpegVideoDecoder::create(c);
    };
    receiver::ReceiverConfig cfg;
    cfg.maxWidth = 1024;
    cfg.maxHeight = 1024;
    cfg.maxPoolBytes = std::size_t{64} << 20;
    cfg.pairingWindow = 4;
    cfg.consumerFrames = 2;
    auto r = receiver::Receiver::open(std::move(*src), url.c_str(), factory, cfg);
    if (!r)
        return;
    OutputChecker checker;
    for (int pass = 0; pass < 2; ++pass) {
        receiver::PairedFrame f;
        for (int i = 0; i < 200; ++i) {
            auto n = (*r)->next(f);
            check(static_cast<bool>(n)); // Busy is impossible: every frame is dropped at once
            if (!*n)
                break;
            const receiver::StoredDepthPair p = f.depthPair();
            checker(f.pts, f.index, p.current != nullptr, p.next != nullptr, p.currentPts,
                    p.nextPts, f.depthMissing, f.depthDuplicated);
            check(static_cast<bool>(f.color) == (*r)->info().hasColor);
            f = receiver::PairedFrame{};
        }
        if (pass == 0 && !(*r)->seek(hal::Pts{0}))
            break;
        checker = OutputChecker{};
    }
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int *, char ***)
{
    platform::setLogLevel(platform::LogLevel::Off);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    fuzzPairing(data, size);
    fuzzMedia(data, size);
    return 0;
}
