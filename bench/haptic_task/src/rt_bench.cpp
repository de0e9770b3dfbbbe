#include "depthtouch/haptic_task/rt_bench.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sys/mman.h>
#include <thread>

#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/report_file.h"

namespace depthtouch::haptic_task::bench {

namespace {

using platform::SchedPolicy;
using platform::SteadyClock;

const char *policyShort(SchedPolicy p)
{
    return p == SchedPolicy::Fifo ? "FIFO" : "OTHER";
}

platform::ThreadConfig loopConfig(SchedPolicy policy)
{
    platform::ThreadConfig c = platform::kHapticThread;
    if (policy == SchedPolicy::Other) {
        c.policy = SchedPolicy::Other;
        c.relativePriority = 0;
    }
    return c;
}

/// Decoder-like load: threads copying 4 MB frames and doing arithmetic on them, at normal priority.
class Load {
public:
    explicit Load(int threads)
    {
        for (int i = 0; i < threads; ++i)
            threads_.emplace_back([this] {
                std::vector<std::uint8_t> a(4 << 20, 1);
                std::vector<std::uint8_t> b(4 << 20, 2);
                std::uint32_t acc = 0;
                while (!stop_.load(std::memory_order_relaxed)) {
                    std::memcpy(b.data(), a.data(), a.size());
                    for (std::size_t k = 0; k < b.size(); k += 64)
                        acc += b[k] * 31u + static_cast<std::uint32_t>(k);
                    a[acc % a.size()] = static_cast<std::uint8_t>(acc);
                }
                sink_.fetch_add(acc, std::memory_order_relaxed);
            });
    }
    ~Load()
    {
        stop_.store(true);
        for (std::thread &t : threads_)
            t.join();
    }
    Load(const Load &) = delete;
    Load &operator=(const Load &) = delete;

private:
    std::vector<std::thread> threads_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint32_t> sink_{0};
};

/// Undoes a process-wide lock of a case (mlockall of All/OnFault) so that the next case starts from
/// an unlocked process, and records what the case held.
void endLock(RtCase &c)
{
    c.lockedMiB = platform::lockedMiB();
    c.residentMiB = platform::residentMiB();
    if (c.lockMode == platform::MemoryLockMode::All ||
        c.lockMode == platform::MemoryLockMode::OnFault)
        (void)munlockall();
}

/// A case of the \a loop kind ("bare" or "task") at \a rateHz (Hz), before it runs.
RtCase newCase(const char *loop, double rateHz, SchedPolicy policy, platform::MemoryLockMode lock)
{
    RtCase c;
    c.loop = loop;
    c.rateHz = rateHz;
    c.policy = policy;
    c.lockMode = lock;
    return c;
}

/// Records on \a c how long it ran since \a begin (s), what the kernel refused its thread
/// (SCHED_FIFO, the memory lock) as \a report says, and its loop's \a cycles, \a overruns, \a wake
/// latency and \a periodError.
void recordRun(RtCase &c, platform::TimePoint begin, const platform::RealtimeThreadReport &report,
               std::uint64_t cycles, std::uint64_t overruns, const LatencySummary &wake,
               const LatencySummary &periodError)
{
    c.seconds = platform::toSeconds(SteadyClock::instance().now() - begin);
    c.fifoRefused = report.rtRefused;
    c.lockRefused = !report.memoryLocked && platform::memoryLockingAvailable();
    c.cycles = cycles;
    c.overruns = overruns;
    c.wake = wake;
    c.periodError = periodError;
}

RtCase runBare(double rateHz, SchedPolicy policy, platform::MemoryLockMode lock, double seconds)
{
    RtCase c = newCase("bare", rateHz, policy, lock);
    SteadyClock &clock = SteadyClock::instance();
    const platform::Duration period = platform::fromSeconds(1.0 / rateHz);
    platform::PeriodicTimer timer(clock, period);
    auto wake = std::make_unique<LatencyHistogram>();
    auto periodError = std::make_unique<LatencyHistogram>();
    platform::RealtimeThreadOptions options;
    options.lockMode = lock;
    const platform::MemoryRegion regions[] = {
        {&timer, sizeof(timer)},
        {wake.get(), sizeof(LatencyHistogram)},
        {periodError.get(), sizeof(LatencyHistogram)},
    };
    options.regions = regions;
    options.regionCount = 3;
    platform::RealtimeThread thread(
        loopConfig(policy), options, [&](platform::StopToken stop) noexcept {
            timer.start();
            std::int64_t previous = -1;
            while (!stop.stopRequested()) {
                const platform::PeriodicWait w = timer.wait();
                wake->add(w.latency.count());
                const std::int64_t now = w.wakeTime.time_since_epoch().count();
                if (!w.overrun && previous >= 0)
                    periodError->add(std::llabs(now - previous - period.count()));
                previous = now;
            }
        });
    const platform::TimePoint begin = clock.now();
    if (!thread.start())
        return c;
    clock.sleepFor(platform::fromSeconds(seconds));
    endLock(c);
    thread.requestStop();
    thread.join();
    recordRun(c, begin, thread.report(), timer.cycles(), timer.overruns(), wake->summary(),
              periodError->summary());
    return c;
}

Result<RtCase> runTask(double rateHz, SchedPolicy policy, platform::MemoryLockMode lock,
                       double seconds, const DeviceFactory &make)
{
    RtCase c = newCase("task", rateHz, policy, lock);
    SteadyClock &clock = SteadyClock::instance();
    constexpr int kW = 320;
    constexpr int kH = 240;
    auto handoff = DepthHandoff::create(kW, kH, scene::SampleFormat::Gray8);
    if (!handoff)
        return unexpected(handoff.error());
    auto device = make();
    if (!device)
        return unexpected(device.error());
    HapticTaskConfig config;
    config.servoRateHz = rateHz;
    config.policy = policy;
    config.memoryLock = lock;
    auto task = HapticTask::create(config, **device, **handoff, clock);
    if (!task)
        return unexpected(task.error());

    // The decoder: a bump circling over a slanted floor, 30 frames per second in real time.
    std::atomic<bool> decoding{true};
    const platform::TimePoint origin = clock.now();
    (*handoff)->setMediaOrigin(origin);
    std::thread decoder([&] {
        std::vector<std::uint8_t> pixels(static_cast<std::size_t>(kW * kH));
        for (int i = 0; decoding.load(); ++i) {
            const double t = i / 30.0;
            const double cx = 0.5 * kW + 0.3 * kW * std::cos(2.0 * t);
            const double cy = 0.5 * kH + 0.3 * kH * std::sin(2.0 * t);
            for (int r = 0; r < kH; ++r)
                for (int col = 0; col < kW; ++col) {
                    const double d2 = (col - cx) * (col - cx) + (r - cy) * (r - cy);
                    const double v = 60.0 + 0.2 * r + 150.0 * std::exp(-d2 / 800.0);
                    pixels[static_cast<std::size_t>(r * kW + col)] =
                        static_cast<std::uint8_t>(std::lround(std::fmin(v, 255.0)));
                }
            const scene::DepthFrameView view{
                pixels.data(), kW, kH, static_cast<std::size_t>(kW), scene::SampleFormat::Gray8, t};
            (void)(*handoff)->push(view);
            clock.sleepUntil(origin + platform::fromSeconds(t)); // frame i+1 out at frame i's PTS
        }
    });
    const platform::TimePoint begin = clock.now();
    auto started = (*task)->start();
    if (started) {
        clock.sleepFor(platform::fromSeconds(seconds));
        endLock(c);
        (*task)->stop();
    }
    decoding.store(false);
    decoder.join();
    (*device)->close();
    if (!started)
        return unexpected(started.error());
    const HapticStats s = (*task)->stats();
    recordRun(c, begin, (*task)->threadReport(), s.updates, s.overruns, s.wakeLatency,
              s.periodError);
    c.update = s.updateTime;
    c.deviceCallMaxUs = s.deviceCallMaxUs;
    return c;
}

/// \return " | device call max X us" for a task case, else empty.
std::string deviceCallText(const RtCase &c)
{
    if (c.loop != "task")
        return {};
    char text[64];
    std::snprintf(text, sizeof text, " | device call max %.1f us", c.deviceCallMaxUs);
    return text;
}

std::string caseLine(const RtCase &c)
{
    char line[512];
    std::snprintf(line, sizeof line,
                  "%-22s wake p50 %7.1f p99 %8.1f p99.9 %8.1f max %8.1f us | period err p50 %6.1f "
                  "p99 %7.1f p99.9 %7.1f max %8.1f us | %6.1f overruns/min | %5.1f MiB locked, "
                  "%5.1f MiB resident%s%s%s",
                  c.label().c_str(), c.wake.p50Us, c.wake.p99Us, c.wake.p999Us, c.wake.maxUs,
                  c.periodError.p50Us, c.periodError.p99Us, c.periodError.p999Us,
                  c.periodError.maxUs, c.overrunsPerMinute(), c.lockedMiB, c.residentMiB,
                  c.fifoRefused ? "  (SCHED_FIFO REFUSED: ran at SCHED_OTHER)" : "",
                  c.lockRefused ? "  (MEMORY LOCK REFUSED)" : "", deviceCallText(c).c_str());
    return line;
}

const RtCase *findCase(const RtBenchReport &r, const std::string &loop, double rate,
                       SchedPolicy policy, bool loaded,
                       platform::MemoryLockMode lock = platform::MemoryLockMode::Owned)
{
    for (const RtCase &c : r.cases)
        if (c.loop == loop && c.rateHz == rate && c.policy == policy && c.loaded == loaded &&
            c.lockMode == lock)
            return &c;
    return nullptr;
}

} // namespace

std::string RtCase::label() const
{
    char text[64];
    std::snprintf(text, sizeof text, "%s %gk %s %s%s", loop.c_str(), rateHz / 1000.0,
                  policyShort(policy), platform::memoryLockModeName(lockMode),
                  loaded ? " load" : "");
    return text;
}

namespace {

/// Measures the bare loop and the task at one rate, policy, lock and load; adds them to \a report.
void runCasePair(const RtBenchOptions &options, double rate, SchedPolicy policy,
                 platform::MemoryLockMode lock, bool loaded, RtBenchReport &report)
{
    RtCase bare = runBare(rate, policy, lock, options.secondsPerCase);
    bare.loaded = loaded;
    if (bare.cycles > 0) {
        if (options.progress)
            options.progress(caseLine(bare));
        report.cases.push_back(bare);
    }
    if (!options.makeDevice) {
        report.taskError = "no haptic device for the task cases";
        return;
    }
    auto task = runTask(rate, policy, lock, options.secondsPerCase, options.makeDevice);
    if (!task) {
        char buf[256];
        report.taskError = task.error().format(buf, sizeof buf);
        return;
    }
    task->loaded = loaded;
    if (options.progress)
        options.progress(caseLine(*task));
    report.cases.push_back(*task);
}

} // namespace

RtBenchReport runRtBenchmark(const RtBenchOptions &options)
{
    RtBenchReport report;
    std::vector<bool> loads{false};
    if (options.load)
        loads.push_back(true);
    for (const bool loaded : loads) {
        std::shared_ptr<void> load;
        if (loaded)
            load = options.makeLoad ? options.makeLoad()
                                    : std::make_shared<Load>(std::max(options.loadThreads, 1));
        for (const double rate : options.ratesHz)
            for (const SchedPolicy policy : options.policies)
                for (const platform::MemoryLockMode lock : options.lockModes)
                    runCasePair(options, rate, policy, lock, loaded, report);
    }
    return report;
}

void printRtReport(const RtBenchReport &report)
{
    std::printf("\nwake latency (wake time - deadline) and period error |wake_k - wake_k-1 - "
                "period|:\n");
    for (const RtCase &c : report.cases)
        std::printf("  %s\n", caseLine(c).c_str());
    bool refused = false;
    for (const RtCase &c : report.cases)
        refused = refused || c.fifoRefused;
    if (refused)
        std::printf("note: SCHED_FIFO was refused (no CAP_SYS_NICE / RLIMIT_RTPRIO): the FIFO rows "
                    "ran at SCHED_OTHER\n");
    if (!report.taskError.empty())
        std::printf("note: the task cases did not run: %s\n", report.taskError.c_str());
    std::printf("\ngoals (this run):\n");
    for (const RtGoalRatio &g : rtGoalRatios(report))
        std::printf("  %-40s %.2f (goal <= %.2f): %s\n", g.label.c_str(), g.ratio, g.goal,
                    g.ratio <= g.goal ? "met" : "NOT met");
}

std::vector<RtGoalRatio> rtGoalRatios(const RtBenchReport &report)
{
    std::vector<RtGoalRatio> out;
    for (const RtCase &task : report.cases) {
        if (task.loop != "task")
            continue;
        if (const RtCase *bare =
                findCase(report, "bare", task.rateHz, task.policy, task.loaded, task.lockMode)) {
            out.push_back({task.label() + " task/bare wake p50",
                           bare->wake.p50Us > 0 ? task.wake.p50Us / bare->wake.p50Us : 0.0, 1.10});
            out.push_back({task.label() + " task/bare wake p99",
                           bare->wake.p99Us > 0 ? task.wake.p99Us / bare->wake.p99Us : 0.0, 1.10});
        }
    }
    for (const RtCase &loaded : report.cases) {
        if (!loaded.loaded)
            continue;
        if (const RtCase *idle =
                findCase(report, loaded.loop, loaded.rateHz, loaded.policy, false, loaded.lockMode))
            out.push_back({loaded.label() + " loaded/idle wake p99",
                           idle->wake.p99Us > 0 ? loaded.wake.p99Us / idle->wake.p99Us : 0.0,
                           1.20});
    }
    for (const RtCase &owned : report.cases) {
        if (owned.lockMode != platform::MemoryLockMode::Owned)
            continue;
        if (const RtCase *all = findCase(report, owned.loop, owned.rateHz, owned.policy,
                                         owned.loaded, platform::MemoryLockMode::All))
            out.push_back({owned.label() + " owned/all wake p99",
                           all->wake.p99Us > 0 ? owned.wake.p99Us / all->wake.p99Us : 0.0, 1.00});
    }
    return out;
}

bool writeRtBenchOutputs(const RtBenchReport &report, const std::string &dir, std::string &error,
                         std::string &note)
{
    namespace fs = std::filesystem;
    if (!platform::createReportFolder(dir, "cannot create '" + dir + "'", error))
        return false;
    const fs::path base(dir);
    const fs::path csv = base / "rt_bench.csv";
    platform::ReportFile out(csv.string()); // close() reports a failed open as well
    out.print("label,loop,rate_hz,policy,load,fifo_refused,seconds,cycles,wake_p50_us,wake_p99_us,"
              "wake_p999_us,wake_max_us,period_err_p50_us,period_err_p99_us,period_err_p999_us,"
              "period_err_max_us,overruns,overruns_per_min,update_p50_us,update_p99_us,"
              "memory_lock,locked_mib,resident_mib,device_call_max_us\n");
    for (const RtCase &c : report.cases)
        out.print("%s,%s,%.0f,%s,%d,%d,%.3f,%llu,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,"
                  "%llu,%.2f,%.2f,%.2f,%s,%.1f,%.1f,%.2f\n",
                  c.label().c_str(), c.loop.c_str(), c.rateHz, platform::schedPolicyName(c.policy),
                  c.loaded ? 1 : 0, c.fifoRefused ? 1 : 0, c.seconds,
                  static_cast<unsigned long long>(c.cycles), c.wake.p50Us, c.wake.p99Us,
                  c.wake.p999Us, c.wake.maxUs, c.periodError.p50Us, c.periodError.p99Us,
                  c.periodError.p999Us, c.periodError.maxUs,
                  static_cast<unsigned long long>(c.overruns), c.overrunsPerMinute(),
                  c.update.p50Us, c.update.p99Us, platform::memoryLockModeName(c.lockMode),
                  c.lockedMiB, c.residentMiB, c.deviceCallMaxUs);
    if (!out.close()) {
        error = "cannot write '" + csv.string() + "'";
        return false;
    }
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
        note = "gnuplot not found: wrote CSV only (install gnuplot-nox for the PNG chart)";
        return true;
    }
    const fs::path gp = base / "rt_bench.gp";
    {
        platform::TextReportFile g(gp.string(), error);
        g << "set terminal pngcairo size 1400,900\n"
             "set output '"
          << (base / "rt_bench.png").string()
          << "'\n"
             "set datafile separator ','\n"
             "set key autotitle columnhead top left\n"
             "set style data histograms\nset style histogram clustered gap 1\n"
             "set style fill solid 0.8 border -1\nset boxwidth 0.9\n"
             "set logscale y\nset yrange [1:*]\nset grid ytics\n"
             "set xtics rotate by -30 font ',9'\n"
             "set multiplot layout 2,1\n"
             "set title 'Haptic loop wake latency (wake - deadline), per case'\n"
             "set ylabel 'microseconds (log)'\n"
             "plot '"
          << csv.string()
          << "' using 9:xtic(1) title 'p50', '' using 10 title 'p99', '' using 11 title 'p99.9', "
             "'' using 12 title 'max'\n"
             "set title 'Period error |wake_k - wake_{k-1} - period|, per case'\n"
             "plot '"
          << csv.string()
          << "' using 13:xtic(1) title 'p50', '' using 14 title 'p99', '' using 15 title 'p99.9', "
             "'' using 16 title 'max'\n"
             "unset multiplot\n";
        if (!g.close())
            return false;
    }
    const std::string cmd = "gnuplot '" + gp.string() + "' 2>&1";
    if (std::system(cmd.c_str()) != 0)
        note = "gnuplot failed: CSV written, the chart may be missing";
    return true;
}

namespace {

/// Prints each goal's median ratio over the runs (with its range) and whether it is met.
void printGoalMedians(int runs, std::map<std::string, std::vector<double>> &ratios,
                      std::map<std::string, double> &goals)
{
    std::printf("\ngoals, median over %d runs (min .. max):\n", runs);
    for (auto &[label, v] : ratios) {
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        const double median = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
        std::printf("  %-40s %.2f (%.2f .. %.2f; goal <= %.2f): %s\n", label.c_str(), median,
                    v.front(), v.back(), goals[label], median <= goals[label] ? "met" : "NOT met");
    }
}

} // namespace

RtBenchReport runRtBenchmarkRuns(const RtBenchOptions &opt, int runs)
{
    // Each run measures every case once; the goals compare figures of the same run, and over
    // several runs their medians are what counts on a shared, noisy machine.
    RtBenchReport result;
    std::map<std::string, std::vector<double>> ratios;
    std::map<std::string, double> goals;
    for (int run = 0; run < runs; ++run) {
        if (runs > 1)
            std::printf("\n--- run %d of %d ---\n", run + 1, runs);
        RtBenchReport one = runRtBenchmark(opt);
        printRtReport(one);
        for (const RtGoalRatio &g : rtGoalRatios(one)) {
            ratios[g.label].push_back(g.ratio);
            goals[g.label] = g.goal;
        }
        if (run == 0)
            result.taskError = one.taskError;
        for (RtCase &c : one.cases)
            result.cases.push_back(std::move(c));
    }
    if (runs > 1)
        printGoalMedians(runs, ratios, goals);
    return result;
}

} // namespace depthtouch::haptic_task::bench
