/// \file
/// \brief `depthtouch demo`: the whole receiver on the mock HAL, in real time.
///
/// A synthetic two-stream clip (color + a moving depth bump) is demuxed and decoded by the mock backends;
/// depth frame pairs (i, i+1) go to a SCHED_FIFO haptic task at the servo rate through a lock-free mailbox;
/// the task runs the modified proxy graph renderer against a scripted fingertip (mock haptic device) that
/// presses into the surface and strokes across it, commands the clamped force and pushes telemetry into a
/// lock-free ring; the main thread presents color frames on the mock display at the video rate and writes
/// the force log (DESIGN.md §4) and stats JSON. \todo #7: the player app replaces this with the real
/// pipeline on real backends (EGL display, simulated hand, encoded content).

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/mailbox.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/spsc_ring.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::cli {

namespace {

using platform::Duration;
using platform::TimePoint;

struct DemoOptions {
    double duration = 3.0;      ///< Seconds of playback.
    double rate = 1000.0;       ///< Haptic servo rate, Hz.
    double stiffness = 800.0;   ///< N/m.
    int width = 160;            ///< Clip size, pixels.
    int height = 120;
    int fps = 30;
    std::string outDir = "demo-out";
    bool requireRt = false;
};

/// Frame i and the buffered frame i+1 of the depth video, as the haptic task needs them (paper IV.B).
/// Preallocated to the clip size; handed over whole through the mailbox, never reallocated.
struct DepthPair {
    std::vector<std::uint8_t> current;
    std::vector<std::uint8_t> next;
    double currentPts = 0.0; ///< s
    double nextPts = 0.0;    ///< s
    bool hasNext = false;
    std::uint64_t sequence = 0; ///< 0: nothing published yet.
};

/// One haptic update, pushed by the haptic task and drained by the main thread.
struct TelemetrySample {
    double t = 0.0; ///< Haptic time, s since the first depth frame.
    glm::dvec3 hip{};
    glm::dvec3 proxy{};
    glm::dvec3 force{};
    bool contact = false;
    bool released = false;
    std::int64_t wakeLatencyNs = 0;
    std::int64_t updateNs = 0;
    bool overrun = false;
};

constexpr std::size_t kTelemetryCapacity = 16384; // 16 s at 1 kHz: the main thread drains every frame

/// Fingertip script in the device frame (m): hover, press 4 mm into the clip's flat background (nearness
/// 0.2, z = −12 mm in the 40 mm deep scene box), stroke left and right across the circling bump, lift.
std::vector<drivers::HapticWaypoint> fingertipScript(TimePoint start, double duration)
{
    const auto at = [&](double fraction) { return start + platform::fromSeconds(fraction * duration); };
    constexpr double kPress = -0.016;
    return {
        {at(0.00), {0.0, 0.0, 0.030}, 0},  {at(0.10), {0.0, 0.0, kPress}, 0},
        {at(0.35), {-0.030, 0.0, kPress}, 0}, {at(0.65), {0.030, 0.0, kPress}, 0},
        {at(0.85), {0.0, 0.010, kPress}, 0}, {at(1.00), {0.0, 0.0, 0.030}, 0},
    };
}

double percentile(std::vector<std::int64_t> v, double p)
{
    if (v.empty())
        return 0.0;
    const auto k = static_cast<std::size_t>(std::lround(p / 100.0 * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return static_cast<double>(v[k]);
}

void printError(const char *what, const Error &e)
{
    char buf[256];
    std::fprintf(stderr, "depthtouch demo: %s: %s\n", what, e.format(buf, sizeof buf));
}

int runDemo(const DemoOptions &opt)
{
    if (!(opt.duration > 0.0 && opt.duration <= 3600.0) || !(opt.rate >= 100.0 && opt.rate <= 10000.0) ||
        !(opt.stiffness > 0.0)) {
        std::fprintf(stderr, "depthtouch demo: --duration must be in (0, 3600] s, --rate in [100, 10000] "
                             "Hz and --stiffness > 0 N/m\n");
        return kExitBadInput;
    }
    std::error_code ec;
    std::filesystem::create_directories(opt.outDir, ec);
    if (ec) {
        std::fprintf(stderr, "depthtouch demo: cannot create '%s': %s\n", opt.outDir.c_str(),
                     ec.message().c_str());
        return kExitFailure;
    }

    platform::SteadyClock &clock = platform::SteadyClock::instance();
    const int frames = static_cast<int>(std::ceil(opt.duration * opt.fps)) + 1;
    const std::string mediaOptions = "width=" + std::to_string(opt.width) + ",height=" +
                                     std::to_string(opt.height) + ",fps=" + std::to_string(opt.fps) +
                                     ",frames=" + std::to_string(frames);
    hal::BackendConfig mediaCfg;
    mediaCfg.clock = &clock;
    mediaCfg.options = hal::OptionList(mediaOptions);

    // Demux + decode (mock backends).
    auto source = drivers::MockMediaSource::create(mediaCfg);
    if (!source) {
        printError("cannot create the media source", source.error());
        return kExitFailure;
    }
    if (auto r = (*source)->open("mock://demo"); !r) {
        printError("cannot open the clip", r.error());
        return kExitFailure;
    }
    const hal::MediaInfo &info = (*source)->info();
    std::unique_ptr<hal::VideoDecoder> decoders[2];
    int colorStream = -1;
    int depthStream = -1;
    for (const hal::StreamInfo &s : info.streams) {
        hal::BackendConfig decoderCfg;
        decoderCfg.clock = &clock;
        auto dec = drivers::MockVideoDecoder::create(decoderCfg);
        if (!dec) {
            printError("cannot create a decoder", dec.error());
            return kExitFailure;
        }
        if (auto r = (*dec)->configure(hal::StreamConfig::fromStream(s)); !r) {
            printError("cannot configure a decoder", r.error());
            return kExitFailure;
        }
        (s.kind == hal::StreamKind::Depth ? depthStream : colorStream) = s.index;
        decoders[s.kind == hal::StreamKind::Depth ? 1 : 0] = std::move(*dec);
    }
    if (depthStream < 0 || colorStream < 0) {
        std::fprintf(stderr, "depthtouch demo: the clip lacks a color or depth stream\n");
        return kExitFailure;
    }

    // Display (mock: paced at its refresh rate, no GL).
    hal::BackendConfig displayCfg;
    displayCfg.clock = &clock;
    auto display = drivers::MockDisplay::create(displayCfg);
    if (!display) {
        printError("cannot create the display", display.error());
        return kExitFailure;
    }
    hal::DisplayConfig dc;
    dc.width = 2 * opt.width; // side-by-side
    dc.height = opt.height;
    dc.refreshHz = 60.0;
    if (auto r = (*display)->open(dc); !r) {
        printError("cannot open the display", r.error());
        return kExitFailure;
    }

    // Haptic device (mock: scripted fingertip) and renderer.
    hal::BackendConfig hapticCfg;
    hapticCfg.clock = &clock;
    auto deviceResult = drivers::MockHapticDevice::create(hapticCfg);
    if (!deviceResult) {
        printError("cannot create the haptic device", deviceResult.error());
        return kExitFailure;
    }
    hal::HapticDevice &device = **deviceResult;
    if (auto r = device.open(); !r) {
        printError("cannot open the haptic device", r.error());
        return kExitFailure;
    }
    haptics::RendererConfig rc = haptics::RendererConfig::forMethod(haptics::Method::Modified);
    rc.stiffness = opt.stiffness;
    rc.maxForce = device.capabilities().maxForce;
    auto renderer = haptics::makeRenderer(haptics::Method::Modified, rc, opt.width, opt.height);
    if (!renderer) {
        printError("cannot create the haptic renderer", renderer.error());
        return kExitFailure;
    }

    // Everything the haptic task touches is allocated here, before it starts.
    const std::size_t frameBytes = static_cast<std::size_t>(opt.width) * static_cast<std::size_t>(opt.height);
    DepthPair prototype;
    prototype.current.resize(frameBytes);
    prototype.next.resize(frameBytes);
    platform::TripleBuffer<DepthPair> mailbox(prototype);
    auto telemetry = std::make_unique<platform::SpscRing<TelemetrySample, kTelemetryCapacity>>();
    const Duration period = platform::fromSeconds(1.0 / opt.rate);
    platform::PeriodicTimer timer(clock, period);
    TimePoint mediaStart{}; // haptic time 0 = the first depth frame's PTS (published with the first pair)
    std::uint64_t hapticUpdates = 0;

    auto hapticBody = [&](platform::StopToken stop) noexcept {
        haptics::HapticRenderer &r = **renderer;
        std::uint64_t seenSequence = 0;
        timer.start();
        while (!stop.stopRequested()) {
            const platform::PeriodicWait w = timer.wait();
            const TimePoint begin = clock.now();
            if (mailbox.update()) {
                const DepthPair &p = mailbox.readBuffer();
                haptics::DepthFrameView cur{p.current.data(), opt.width, opt.height,
                                            static_cast<std::size_t>(opt.width),
                                            haptics::SampleFormat::Gray8, p.currentPts};
                haptics::DepthFrameView nxt = cur;
                nxt.data = p.next.data();
                nxt.pts = p.nextPts;
                if (r.setFrames(cur, p.hasNext ? &nxt : nullptr))
                    seenSequence = p.sequence;
            }
            hal::HapticState state{};
            if (seenSequence == 0 || !device.read(state)) {
                (void)device.commandForce({});
                continue;
            }
            const double t = platform::toSeconds(begin - mediaStart);
            const haptics::HapticOutput out =
                r.update(glm::dvec3(state.position.x, state.position.y, state.position.z), t);
            (void)device.commandForce({out.force.x, out.force.y, out.force.z});
            TelemetrySample s;
            s.t = t;
            s.hip = out.hip;
            s.proxy = out.proxy;
            s.force = out.force;
            s.contact = out.contact;
            s.released = out.released;
            s.wakeLatencyNs = w.latency.count();
            s.overrun = w.overrun;
            s.updateNs = (clock.now() - begin).count();
            (void)telemetry->tryPush(s);
            ++hapticUpdates;
        }
        (void)device.commandForce({});
    };
    platform::RealtimeThreadOptions rtOptions;
    rtOptions.requireRt = opt.requireRt;
    platform::RealtimeThread hapticThread(platform::kHapticThread, rtOptions, hapticBody);

    // Force log, written by this (non-real-time) thread as the ring drains.
    const std::string forceLogPath = opt.outDir + "/force-log.csv";
    std::ofstream forceLog(forceLogPath);
    if (!forceLog) {
        std::fprintf(stderr, "depthtouch demo: cannot write '%s'\n", forceLogPath.c_str());
        return kExitFailure;
    }
    forceLog << "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released\n";
    std::vector<std::int64_t> latencies;
    std::vector<std::int64_t> updateTimes;
    latencies.reserve(static_cast<std::size_t>(opt.duration * opt.rate * 1.1) + 16);
    updateTimes.reserve(latencies.capacity());
    std::uint64_t contacts = 0;
    std::uint64_t releases = 0;
    std::uint64_t overruns = 0;
    double maxForce = 0.0;
    auto drainTelemetry = [&] {
        TelemetrySample s;
        char line[320];
        while (telemetry->tryPop(s)) {
            std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%d,%d\n",
                          s.t, s.hip.x, s.hip.y, s.hip.z, s.proxy.x, s.proxy.y, s.proxy.z, s.force.x,
                          s.force.y, s.force.z, s.contact ? 1 : 0, s.released ? 1 : 0);
            forceLog << line;
            latencies.push_back(s.wakeLatencyNs);
            updateTimes.push_back(s.updateNs);
            contacts += s.contact ? 1 : 0;
            releases += s.released ? 1 : 0;
            overruns += s.overrun ? 1 : 0;
            maxForce = std::max(maxForce, std::sqrt(s.force.x * s.force.x + s.force.y * s.force.y +
                                                    s.force.z * s.force.z));
        }
    };

    // Video loop: decode one frame ahead so frame i+1 is buffered when frame i is shown (paper IV.B).
    std::vector<std::vector<std::uint8_t>> depthFrames; // ring of 2 decoded depth frames
    std::vector<double> depthPts;
    std::uint64_t framesDecoded = 0;
    std::uint64_t framesPresented = 0;
    std::uint64_t framesLate = 0;
    std::uint64_t published = 0;
    bool endOfStream = false;

    // Reads packets until one more depth frame (and its color partner) is decoded. \return false at the end.
    auto decodeNextDepth = [&]() -> bool {
        while (!endOfStream) {
            auto pkt = (*source)->readPacket();
            if (!pkt) {
                if (pkt.error().code != Errc::EndOfStream)
                    printError("cannot read a packet", pkt.error());
                endOfStream = true;
                return false;
            }
            const bool isDepth = pkt->streamIndex == depthStream;
            hal::VideoDecoder &dec = *decoders[isDepth ? 1 : 0];
            if (auto r = dec.queuePacket(*pkt); !r) {
                printError("cannot queue a packet", r.error());
                continue;
            }
            auto frame = dec.dequeueFrame(clock.now());
            if (!frame)
                continue;
            ++framesDecoded;
            if (!isDepth)
                continue;
            const hal::ImageView &img = (*frame)->image;
            std::vector<std::uint8_t> pixels(frameBytes);
            for (int y = 0; y < img.height && y < opt.height; ++y)
                std::memcpy(pixels.data() + static_cast<std::size_t>(y * opt.width), img.row(0, y),
                            static_cast<std::size_t>(std::min(img.width, opt.width)));
            depthFrames.push_back(std::move(pixels));
            depthPts.push_back(platform::toSeconds((*frame)->pts));
            return true;
        }
        return false;
    };

    if (!decodeNextDepth()) {
        std::fprintf(stderr, "depthtouch demo: the clip has no depth frame\n");
        return kExitFailure;
    }
    const double firstPts = depthPts.front();
    // Start the haptic task first (locking memory and pre-faulting its stack take a while); it commands
    // zero force until the first depth frame pair arrives.
    if (auto r = hapticThread.start(); !r) {
        printError("cannot start the haptic task", r.error());
        return kExitFailure;
    }
    // Media time starts now, and so does the fingertip script. The task reads mediaStart and the device
    // only after it has taken the first pair from the mailbox, which orders these writes before those reads.
    mediaStart = clock.now();
    if (auto *mock = dynamic_cast<drivers::MockHapticDevice *>(&device))
        mock->setWaypoints(fingertipScript(mediaStart, opt.duration));

    for (std::size_t i = 0; !depthFrames.empty(); ++i) {
        const bool haveNext = decodeNextDepth();
        DepthPair &w = mailbox.writeBuffer();
        std::memcpy(w.current.data(), depthFrames.front().data(), frameBytes);
        w.currentPts = depthPts.front() - firstPts;
        w.hasNext = haveNext;
        if (haveNext) {
            std::memcpy(w.next.data(), depthFrames[1].data(), frameBytes);
            w.nextPts = depthPts[1] - firstPts;
        }
        w.sequence = ++published;
        mailbox.publish();

        // Show frame i at its PTS, then present (the mock display paces at its refresh rate).
        const TimePoint due = mediaStart + platform::fromSeconds(depthPts.front() - firstPts);
        if (!clock.sleepUntil(due))
            ++framesLate;
        if (auto r = (*display)->present(); r)
            ++framesPresented;
        drainTelemetry();
        depthFrames.erase(depthFrames.begin());
        depthPts.erase(depthPts.begin());
        if (platform::toSeconds(clock.now() - mediaStart) >= opt.duration)
            break;
    }
    clock.sleepUntil(mediaStart + platform::fromSeconds(opt.duration));
    hapticThread.requestStop();
    hapticThread.join();
    drainTelemetry();
    forceLog.close();

    char report[256];
    hapticThread.report().format(report, sizeof report);
    const double p50 = percentile(latencies, 50) * 1e-3;
    const double p99 = percentile(latencies, 99) * 1e-3;
    const double u50 = percentile(updateTimes, 50) * 1e-3;
    const double u99 = percentile(updateTimes, 99) * 1e-3;
    const auto stats = decoders[0]->stats();
    const auto dstats = decoders[1]->stats();
    nlohmann::json j = {
        {"frames_decoded", framesDecoded},
        {"frames_presented", framesPresented},
        {"frames_dropped", stats.framesDropped + dstats.framesDropped},
        {"frames_late", framesLate},
        {"haptic_updates", hapticUpdates},
        {"haptic_rate_hz", opt.rate},
        {"overruns", overruns},
        {"telemetry_dropped", telemetry->dropped()},
        {"wake_latency_us", {{"p50", p50}, {"p99", p99}, {"max", percentile(latencies, 100) * 1e-3}}},
        {"update_time_us", {{"p50", u50}, {"p99", u99}, {"max", percentile(updateTimes, 100) * 1e-3}}},
        {"contact_updates", contacts},
        {"safety_releases", releases},
        {"max_force_n", maxForce},
        {"device_max_force_n", device.capabilities().maxForce},
        {"haptic_thread", report},
    };
    const std::string statsPath = opt.outDir + "/stats.json";
    std::ofstream(statsPath) << j.dump(2) << '\n';

    std::printf("DepthTouch demo (mock HAL, %.1f s, %dx%d depth at %d fps, haptics at %.0f Hz)\n",
                opt.duration, opt.width, opt.height, opt.fps, opt.rate);
    std::printf("  haptic thread     %s\n", report);
    std::printf("  frames            %llu decoded, %llu presented, %llu late\n",
                static_cast<unsigned long long>(framesDecoded),
                static_cast<unsigned long long>(framesPresented),
                static_cast<unsigned long long>(framesLate));
    std::printf("  haptic updates    %llu (%llu in contact), %llu overruns, %llu safety releases\n",
                static_cast<unsigned long long>(hapticUpdates), static_cast<unsigned long long>(contacts),
                static_cast<unsigned long long>(overruns), static_cast<unsigned long long>(releases));
    std::printf("  wake latency      p50 %.1f us, p99 %.1f us; update time p50 %.2f us, p99 %.2f us\n",
                p50, p99, u50, u99);
    std::printf("  max force         %.2f N (device maximum %.2f N)\n", maxForce,
                device.capabilities().maxForce);
    std::printf("  files             %s, %s\n", forceLogPath.c_str(), statsPath.c_str());
    device.close();
    return maxForce <= device.capabilities().maxForce + 1e-9 ? kExitOk : kExitFailure;
}

} // namespace

void registerDemoCommand(CLI::App &app, int &exitCode)
{
    auto opt = std::make_shared<DemoOptions>();
    CLI::App *cmd = app.add_subcommand(
        "demo", "Run the receiver end to end on the mock HAL: decode, present, touch (the main job)");
    cmd->add_option("--duration", opt->duration, "Seconds of playback")->capture_default_str();
    cmd->add_option("--rate", opt->rate, "Haptic servo rate, Hz")->capture_default_str();
    cmd->add_option("--stiffness", opt->stiffness, "Surface stiffness, N/m")->capture_default_str();
    cmd->add_option("--out", opt->outDir, "Folder for the force log and stats")->capture_default_str();
    cmd->add_flag("--require-rt", opt->requireRt, "Fail when SCHED_FIFO is refused");
    cmd->callback([opt, &exitCode] { exitCode = runDemo(*opt); });
}

} // namespace depthtouch::cli
