// Decode + pairing throughput of the receiver on the ffmpeg backends, one core (one decoder thread
// each, the receiver on the calling thread), for a 720×486 and a 1920×1080 color + depth H.264 clip
// written here (x264 veryfast, 2 B-frames, a moving noise texture so the pictures are not trivial
// to decode). Prints the median of the runs in frames per second and in multiples of real time at
// the clip's 30 fps, and writes receiver-throughput.csv and receiver-throughput.png (gnuplot) into
// the folder given as argument (default: receiver-bench-out).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "test_media.h"

namespace rt = depthtouch::receivertest;
using namespace depthtouch;

namespace {

struct Case {
    int width;
    int height;
    int frames;
};

/// Demux + decode of both streams through the HAL alone (frames dropped at once): the baseline the
/// receiver's copy and pairing add to. \return frames per second of color frames, 0 on failure.
double decodeOnlyFps(const std::string &path)
{
    auto src = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    if (!src || !(*src)->open(path.c_str()))
        return 0.0;
    std::unique_ptr<hal::VideoDecoder> dec[2];
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("threads=1");
    for (const hal::StreamInfo &si : (*src)->info().streams) {
        if (si.index > 1)
            continue;
        auto d = drivers::createVideoDecoder("ffmpeg", cfg);
        hal::StreamConfig sc = hal::StreamConfig::fromStream(si);
        if (si.index == 1) {
            sc.kind = hal::StreamKind::Depth;
            sc.format = hal::PixelFormat::Gray8;
        }
        if (!d || !(*d)->configure(sc))
            return 0.0;
        dec[si.index] = std::move(*d);
    }
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    const platform::TimePoint t0 = clock.now();
    std::uint64_t colorFrames = 0;
    const auto take = [&](int i) {
        for (;;) {
            auto f = dec[i]->dequeueFrame(hal::Deadline{});
            if (!f)
                return f.error().code;
            colorFrames += i == 0 ? 1u : 0u;
        }
    };
    for (;;) {
        auto p = (*src)->readPacket();
        if (!p)
            break;
        if (p->streamIndex < 0 || p->streamIndex > 1 || !dec[p->streamIndex])
            continue;
        while (dec[p->streamIndex]->queuePacket(*p).error().code == Errc::Busy)
            (void)take(p->streamIndex);
        (void)take(p->streamIndex);
    }
    for (int i = 0; i < 2; ++i) {
        if (!dec[i])
            continue;
        (void)dec[i]->queuePacket(hal::Packet::endOfStream(i));
        while (take(i) != Errc::EndOfStream) {
        }
    }
    return static_cast<double>(colorFrames) / platform::toSeconds(clock.now() - t0);
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

} // namespace

int main(int argc, char **argv)
{
    const std::string out = argc > 1 ? argv[1] : "receiver-bench-out";
    std::filesystem::create_directories(out);
    platform::setLogLevel(platform::LogLevel::Error);
    const Case cases[] = {{720, 486, 150}, {1920, 1080, 90}};
    constexpr int kRuns = 3;
    constexpr double kFps = 30.0;
    rt::TempDir tmp;
    std::ofstream csv(out + "/receiver-throughput.csv");
    csv << "size,run,frames,seconds,fps,realtime_x\n"; // receiver runs
    std::printf("receiver decode + pairing, one core, color + depth H.264 at %.0f fps\n", kFps);
    std::printf("%-10s %7s %9s %10s %10s %16s %14s\n", "size", "frames", "Mbit/s", "median fps",
                "x realtime", "decode-only fps", "runs (fps)");
    for (const Case &c : cases) {
        rt::Clip clip = rt::Clip::standard(c.width, c.height, c.frames, static_cast<int>(kFps));
        for (rt::ClipStream *s : {&clip.color, &clip.depth}) {
            s->bframes = 2;
            s->texture = 48;
            s->preset = "veryfast";
        }
        clip.depth.lossless = false;
        clip.gop = 30;
        const std::string path = tmp.path(std::to_string(c.width) + ".mkv");
        if (const std::string err = rt::writeClip(path, clip); !err.empty()) {
            std::fprintf(stderr, "receiver_throughput: cannot write the clip: %s\n", err.c_str());
            return 1;
        }
        const double mbps = static_cast<double>(std::filesystem::file_size(path)) * 8.0 /
                            (static_cast<double>(c.frames) / kFps) / 1e6;
        std::vector<double> fps;
        std::vector<double> baseline;
        std::string runs;
        for (int run = 0; run < kRuns; ++run) {
            auto r = rt::openFfmpeg(path, {}, 1);
            if (!r) {
                std::fprintf(stderr, "receiver_throughput: %s\n", r.error().what);
                return 1;
            }
            platform::SteadyClock &clock = platform::SteadyClock::instance();
            const platform::TimePoint t0 = clock.now();
            receiver::PairedFrame f;
            std::uint64_t n = 0;
            for (;;) {
                auto got = (*r)->next(f);
                if (!got || !*got)
                    break;
                ++n;
            }
            const double s = platform::toSeconds(clock.now() - t0);
            f = receiver::PairedFrame{};
            if (n != static_cast<std::uint64_t>(c.frames)) {
                std::fprintf(stderr, "receiver_throughput: %llu of %d frames paired\n",
                             static_cast<unsigned long long>(n), c.frames);
                return 1;
            }
            fps.push_back(static_cast<double>(n) / s);
            csv << c.width << "x" << c.height << "," << run << "," << n << "," << s << ","
                << fps.back() << "," << fps.back() / kFps << "\n";
            baseline.push_back(decodeOnlyFps(path));
            char buf[32];
            std::snprintf(buf, sizeof buf, "%s%.0f", runs.empty() ? "" : " ", fps.back());
            runs += buf;
        }
        const double m = median(fps);
        std::printf("%4dx%-5d %7d %9.1f %10.1f %10.1f %16.1f   %s\n", c.width, c.height, c.frames,
                    mbps, m, m / kFps, median(baseline), runs.c_str());
    }
    csv.close();
    const std::string plot = out + "/receiver-throughput.gp";
    std::ofstream(plot)
        << "set terminal pngcairo size 640,400\n"
        << "set output '" << out << "/receiver-throughput.png'\n"
        << "set datafile separator ','\n"
        << "set title 'Receiver decode + pairing, one core (x real time at 30 fps)'\n"
        << "set ylabel 'x real time'\nset style data points\nset key off\n"
        << "set xtics ('720x486' 0, '1920x1080' 1)\nset xrange [-0.5:1.5]\n"
        << "set yrange [0:*]\n"
        << "plot '" << out << "/receiver-throughput.csv' using "
        << "(strcol(1) eq '720x486' ? 0 : 1):6 every ::1 pt 7 ps 1.5\n";
    if (std::system(("gnuplot " + plot + " 2>/dev/null").c_str()) != 0)
        std::printf("(gnuplot failed: no chart)\n");
    std::printf("files: %s/receiver-throughput.csv, %s/receiver-throughput.png\n", out.c_str(),
                out.c_str());
    return 0;
}
