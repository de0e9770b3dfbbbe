/// \file
/// \brief `depthtouch demo`: the whole receiver on the mock HAL, in real time.
///
/// A synthetic two-stream clip (color + a moving depth bump) is demuxed and decoded by the mock
/// backends; depth frame pairs (i, i+1) go to the SCHED_FIFO haptic task (haptic_task::HapticTask)
/// at the servo rate through the lock-free DepthHandoff; the task runs the modified proxy graph
/// renderer against a scripted fingertip (mock haptic device, or `--haptic sim`: the simulated
/// hand) that presses into the surface and strokes across it, commands the clamped, rate-limited
/// force and pushes telemetry, which its telemetry thread writes to the force log (DESIGN.md §4);
/// the main thread presents color frames on the mock display at the video rate and writes the stats
/// JSON. \todo #7: the player app replaces this with the real pipeline on real backends (EGL
/// display, simulated hand, encoded content).

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::cli {

namespace {

using platform::TimePoint;

struct DemoOptions {
    double duration = 3.0;    ///< Seconds of playback.
    double rate = 1000.0;     ///< Haptic servo rate, Hz.
    double stiffness = 800.0; ///< N/m.
    int width = 160;          ///< Clip size, pixels.
    int height = 120;
    int fps = 30;
    std::string outDir = "demo-out";
    std::string haptic = "mock"; ///< Haptic device backend(s).
    std::string hapticOptions;   ///< Its options.
    bool requireRt = false;
};

haptic_task::HapticTask *gDemoTask = nullptr;

/// SIGINT/SIGTERM: zero force and stop (async-signal-safe: one atomic store).
extern "C" void onDemoStopSignal(int)
{
    if (gDemoTask != nullptr)
        gDemoTask->requestStop();
}

/// Fingertip script in the device frame (m): hover, press 4 mm into the clip's flat background
/// (nearness 0.2, z = −12 mm in the 40 mm deep scene box), stroke left and right across the
/// circling bump, lift.
std::vector<drivers::HapticWaypoint> fingertipScript(TimePoint start, double duration)
{
    const auto at = [&](double fraction) {
        return start + platform::fromSeconds(fraction * duration);
    };
    constexpr double kPress = -0.016;
    return {
        {at(0.00), {0.0, 0.0, 0.030}, 0},     {at(0.10), {0.0, 0.0, kPress}, 0},
        {at(0.35), {-0.030, 0.0, kPress}, 0}, {at(0.65), {0.030, 0.0, kPress}, 0},
        {at(0.85), {0.0, 0.010, kPress}, 0},  {at(1.00), {0.0, 0.0, 0.030}, 0},
    };
}

void printError(const char *what, const Error &e)
{
    char buf[256];
    std::fprintf(stderr, "depthtouch demo: %s: %s\n", what, e.format(buf, sizeof buf));
}

int runDemo(const DemoOptions &opt)
{
    if (!(opt.duration > 0.0 && opt.duration <= 3600.0) ||
        !(opt.rate >= 100.0 && opt.rate <= 10000.0) || !(opt.stiffness > 0.0)) {
        std::fprintf(stderr,
                     "depthtouch demo: --duration must be in (0, 3600] s, --rate in [100, 10000] "
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
    const std::string mediaOptions =
        "width=" + std::to_string(opt.width) + ",height=" + std::to_string(opt.height) +
        ",fps=" + std::to_string(opt.fps) + ",frames=" + std::to_string(frames);
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

    // Haptic device: the mock's scripted fingertip by default, or any backend of the table (`sim`:
    // the simulated hand, pushed back by the force).
    hal::BackendConfig hapticCfg;
    hapticCfg.clock = &clock;
    hapticCfg.options = hal::OptionList(opt.hapticOptions);
    hal::SelectionReport hapticReport;
    auto deviceResult = drivers::createHapticDevice(opt.haptic, hapticCfg, &hapticReport);
    if (!deviceResult) {
        std::fprintf(stderr, "depthtouch demo: %s\n", hapticReport.message.c_str());
        return deviceResult.error().code == Errc::InvalidArgument ? kExitBadInput : kExitFailure;
    }
    hal::HapticDevice &device = **deviceResult;
    if (auto r = device.open(); !r && r.error().code != Errc::NoDevice) {
        printError("cannot open the haptic device", r.error());
        return kExitFailure;
    }

    // The haptic task and the depth handoff: everything the haptic thread touches is allocated
    // here.
    auto handoff =
        haptic_task::DepthHandoff::create(opt.width, opt.height, haptics::SampleFormat::Gray8);
    if (!handoff) {
        printError("cannot allocate the depth frames", handoff.error());
        return kExitFailure;
    }
    haptic_task::HapticTaskConfig taskConfig;
    taskConfig.servoRateHz = opt.rate;
    taskConfig.renderer.stiffness = opt.stiffness;
    taskConfig.requireRt = opt.requireRt;
    const std::string forceLogPath = opt.outDir + "/force-log.csv";
    taskConfig.forceLogPath = forceLogPath;
    auto task = haptic_task::HapticTask::create(taskConfig, device, **handoff, clock);
    if (!task) {
        printError("cannot create the haptic task", task.error());
        return kExitFailure;
    }

    // Video: decode one frame ahead so frame i+1 is buffered when frame i is shown (paper IV.B).
    const std::size_t frameBytes =
        static_cast<std::size_t>(opt.width) * static_cast<std::size_t>(opt.height);
    std::vector<std::uint8_t> pixels(frameBytes);
    std::uint64_t framesDecoded = 0;
    std::uint64_t framesPresented = 0;
    std::uint64_t framesLate = 0;
    bool endOfStream = false;
    double firstPts = 0.0;
    bool haveFirst = false;
    std::vector<double> depthPts; // PTS of the frames pushed, s from the first one

    // Reads packets until one more depth frame (and its color partner) is decoded and pushes it
    // into the handoff, which publishes (previous frame, this frame). \return false at the end.
    auto decodeAndPushDepth = [&]() -> bool {
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
            std::fill(pixels.begin(), pixels.end(), std::uint8_t{0});
            for (int y = 0; y < img.height && y < opt.height; ++y)
                std::memcpy(pixels.data() + static_cast<std::size_t>(y * opt.width), img.row(0, y),
                            static_cast<std::size_t>(std::min(img.width, opt.width)));
            const double pts = platform::toSeconds((*frame)->pts);
            if (!haveFirst) {
                firstPts = pts;
                haveFirst = true;
            }
            const haptics::DepthFrameView view{pixels.data(),
                                               opt.width,
                                               opt.height,
                                               static_cast<std::size_t>(opt.width),
                                               haptics::SampleFormat::Gray8,
                                               pts - firstPts};
            if (auto r = (*handoff)->push(view); !r) {
                printError("cannot hand a depth frame to the haptic task", r.error());
                continue;
            }
            depthPts.push_back(pts - firstPts);
            return true;
        }
        return false;
    };

    // Frames 0 and 1: the first pair.
    if (!decodeAndPushDepth()) {
        std::fprintf(stderr, "depthtouch demo: the clip has no depth frame\n");
        return kExitFailure;
    }
    if (!decodeAndPushDepth())
        (*handoff)->finish();

    // Start the haptic task first (locking memory and pre-faulting its stack take a while); it
    // commands zero force until media time starts. SIGINT/SIGTERM stop it with zero force.
    if (auto r = (*task)->start(); !r) {
        printError("cannot start the haptic task", r.error());
        return kExitFailure;
    }
    gDemoTask = task->get();
    std::signal(SIGINT, &onDemoStopSignal);
    std::signal(SIGTERM, &onDemoStopSignal);
    // Media time starts now, and so does the fingertip script.
    const TimePoint mediaStart = clock.now();
    (*handoff)->setMediaOrigin(mediaStart);
    if (auto *mock = dynamic_cast<drivers::MockHapticDevice *>(&device))
        mock->setWaypoints(fingertipScript(mediaStart, opt.duration));

    for (std::size_t i = 0; i < depthPts.size(); ++i) {
        if ((*task)->stopRequested())
            break;
        // Show frame i at its PTS (the mock display paces at its refresh rate), then buffer frame
        // i+2 so the pair (i+1, i+2) is ready when frame i+1 goes on screen.
        const TimePoint due = mediaStart + platform::fromSeconds(depthPts[i]);
        if (!clock.sleepUntil(due))
            ++framesLate;
        if (auto r = (*display)->present(); r)
            ++framesPresented;
        if (i >= 1 && !endOfStream && !decodeAndPushDepth())
            (*handoff)->finish();
        if (platform::toSeconds(clock.now() - mediaStart) >= opt.duration)
            break;
    }
    if (!(*task)->stopRequested())
        clock.sleepUntil(mediaStart + platform::fromSeconds(opt.duration));
    (*task)->stop();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    gDemoTask = nullptr;

    const haptic_task::HapticStats hs = (*task)->stats();
    const auto stats = decoders[0]->stats();
    const auto dstats = decoders[1]->stats();
    nlohmann::json j = nlohmann::json::parse(hs.toJson());
    j["frames_decoded"] = framesDecoded;
    j["frames_presented"] = framesPresented;
    j["frames_dropped"] = stats.framesDropped + dstats.framesDropped;
    j["frames_late"] = framesLate;
    const std::string statsPath = opt.outDir + "/stats.json";
    std::ofstream(statsPath) << j.dump(2) << '\n';

    std::printf("DepthTouch demo (mock HAL, %.1f s, %dx%d depth at %d fps, haptics at %.0f Hz)\n",
                opt.duration, opt.width, opt.height, opt.fps, opt.rate);
    std::printf("  haptic device     %s\n", hapticReport.chosen.c_str());
    std::printf("  haptic thread     %s\n", hs.thread.c_str());
    std::printf("  frames            %llu decoded, %llu presented, %llu late\n",
                static_cast<unsigned long long>(framesDecoded),
                static_cast<unsigned long long>(framesPresented),
                static_cast<unsigned long long>(framesLate));
    std::printf("  haptic updates    %llu (%llu in contact), %llu overruns, %llu safety releases\n",
                static_cast<unsigned long long>(hs.updates),
                static_cast<unsigned long long>(hs.contactUpdates),
                static_cast<unsigned long long>(hs.overruns),
                static_cast<unsigned long long>(hs.safetyReleases));
    std::printf(
        "  wake latency      p50 %.1f us, p99 %.1f us; update time p50 %.2f us, p99 %.2f us\n",
        hs.wakeLatency.p50Us, hs.wakeLatency.p99Us, hs.updateTime.p50Us, hs.updateTime.p99Us);
    std::printf("  max force         %.2f N (device maximum %.2f N)\n", hs.maxForce,
                device.capabilities().maxForce);
    std::printf("  files             %s, %s\n", forceLogPath.c_str(), statsPath.c_str());
    device.close();
    return hs.maxForce <= device.capabilities().maxForce + 1e-9 ? kExitOk : kExitFailure;
}

} // namespace

void registerDemoCommand(CLI::App &app, int &exitCode)
{
    auto opt = std::make_shared<DemoOptions>();
    CLI::App *cmd = app.add_subcommand(
        "demo",
        "Run the receiver end to end on the mock HAL: decode, present, touch (the main job)");
    cmd->add_option("--duration", opt->duration, "Seconds of playback")->capture_default_str();
    cmd->add_option("--rate", opt->rate, "Haptic servo rate, Hz")->capture_default_str();
    cmd->add_option("--stiffness", opt->stiffness, "Surface stiffness, N/m")->capture_default_str();
    cmd->add_option("--out", opt->outDir, "Folder for the force log and stats")
        ->capture_default_str();
    cmd->add_option("--haptic", opt->haptic,
                    "Haptic device backend: mock (scripted fingertip), sim, none")
        ->capture_default_str();
    cmd->add_option("--haptic-options", opt->hapticOptions,
                    "Options of the haptic device, e.g. intent=stroke,force=1.5 for sim");
    cmd->add_flag("--require-rt", opt->requireRt, "Fail when SCHED_FIFO is refused");
    cmd->callback([opt, &exitCode] { exitCode = runDemo(*opt); });
}

} // namespace depthtouch::cli
