/// \file
/// \brief `depthtouch bench rt`: wake latency and period error of the haptic servo loop (bare loop
/// and the full haptic task with the simulated hand on a moving depth video) at 1 kHz and 4 kHz,
/// SCHED_FIFO against SCHED_OTHER, the owned memory lock (docs/memory.md) against
/// mlockall(MCL_CURRENT) (alternating), idle and optionally loaded; CSV and a PNG chart into --out.

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptic_task/rt_bench.h"
#include "depthtouch/platform/clock.h"
#include "play.h"

namespace depthtouch::cli {

namespace {

struct BenchRtOptions {
    std::string out = "bench-out/rt";
    double duration = 5.0;
    std::vector<double> rates{1000.0, 4000.0};
    std::string policies = "fifo,other";
    std::string locks = "owned,all";
    bool load = false;
    int loadThreads = 2;
    std::string loadClip; ///< Load = the player playing this clip in this process.
    int runs = 1;         ///< Repetitions of the whole set; goal ratios as medians over them.
    std::string haptic = "sim";
    std::string hapticOptions = "intent=stroke,force=1.5,z=0.01,speed=0.05";
};

/// What `bench rt` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout = "Haptic loop timing: wake latency and period error, bare loop vs "
                               "haptic task, SCHED_FIFO vs SCHED_OTHER, memory locks; CSV/PNG";

/// The options of `bench rt`, in `--help` order.
const OptionRow<BenchRtOptions> kBenchRtRows[] = {
    benchOutRow<BenchRtOptions>(),
    {"duration", &BenchRtOptions::duration, "Seconds per case"},
    {"rates", &BenchRtOptions::rates, "Servo rates, Hz"},
    {"policies", &BenchRtOptions::policies, "fifo, other or fifo,other"},
    {"locks", &BenchRtOptions::locks,
     "Memory locks compared, alternating: owned (mlock of what the haptic thread owns, the "
     "default), all (mlockall(MCL_CURRENT), the earlier lock), onfault "
     "(mlockall(MCL_CURRENT|MCL_FUTURE|MCL_ONFAULT)), none"},
    {"load", &BenchRtOptions::load, "Also run every case while other threads load the CPUs"},
    {"load-threads", &BenchRtOptions::loadThreads, "Threads of the load"},
    {"runs", &BenchRtOptions::runs, "Repetitions; goal ratios as medians over them"},
    {"load-clip", &BenchRtOptions::loadClip,
     "Load = the player playing this color + depth file (headless, looping) in this process, "
     "instead of the decode-like threads"},
    {"haptic", &BenchRtOptions::haptic, "Haptic device of the task cases"},
    {"haptic-options", &BenchRtOptions::hapticOptions, "Its options"},
};

/// The player as the load: `play CLIP --loop` on the headless display, without haptics, on a
/// thread of this process (decode, pairing and stereo rendering, as on the box).
class PlayerLoad {
public:
    explicit PlayerLoad(const std::string &clip)
    {
        PlayOptions p;
        p.url = clip;
        p.haptic = "none";
        p.loop = true;
        p.quiet = true;
        thread_ = std::thread([p] {
            const PlayResult r = runPlay(p);
            if (r.exitCode != kExitOk)
                std::fprintf(stderr, "depthtouch bench rt: the player load ended with %d\n",
                             r.exitCode);
        });
    }
    ~PlayerLoad()
    {
        requestPlayStop();
        thread_.join();
    }
    PlayerLoad(const PlayerLoad &) = delete;
    PlayerLoad &operator=(const PlayerLoad &) = delete;

private:
    std::thread thread_;
};

using namespace depthtouch::haptic_task::bench;

/// Checks --duration, --rates and --load-threads; prints the one error line when they are off.
bool checkRates(const BenchRtOptions &o)
{
    if (!(o.duration > 0.0 && o.duration <= 600.0) || o.rates.empty() || o.loadThreads < 1 ||
        o.loadThreads > 64) {
        std::fprintf(stderr, "depthtouch bench rt: --duration must be in (0, 600] s, --rates not "
                             "empty, --load-threads in 1..64\n");
        return false;
    }
    for (const double r : o.rates) {
        if (!(r >= 100.0 && r <= 10000.0)) {
            std::fprintf(stderr, "depthtouch bench rt: --rates must be in [100, 10000] Hz\n");
            return false;
        }
    }
    return true;
}

/// The scheduling policies of --policies; prints the one error line when it names none.
bool setPolicies(const BenchRtOptions &o, RtBenchOptions &opt)
{
    opt.policies.clear();
    if (o.policies.find("fifo") != std::string::npos)
        opt.policies.push_back(platform::SchedPolicy::Fifo);
    if (o.policies.find("other") != std::string::npos)
        opt.policies.push_back(platform::SchedPolicy::Other);
    if (opt.policies.empty()) {
        std::fprintf(stderr, "depthtouch bench rt: --policies takes fifo, other or fifo,other\n");
        return false;
    }
    return true;
}

/// The memory locks of --locks, in the order given; prints the one error line when it names none.
bool setLocks(const BenchRtOptions &o, RtBenchOptions &opt)
{
    opt.lockModes.clear();
    std::size_t begin = 0;
    while (begin <= o.locks.size()) {
        std::size_t end = o.locks.find(',', begin);
        if (end == std::string::npos)
            end = o.locks.size();
        const std::string name = o.locks.substr(begin, end - begin);
        bool known = false;
        for (const platform::MemoryLockMode m :
             {platform::MemoryLockMode::Owned, platform::MemoryLockMode::All,
              platform::MemoryLockMode::OnFault, platform::MemoryLockMode::None}) {
            if (name == platform::memoryLockModeName(m)) {
                opt.lockModes.push_back(m);
                known = true;
            }
        }
        if (!known) {
            std::fprintf(stderr, "depthtouch bench rt: --locks takes owned, all, onfault or none, "
                                 "comma-separated\n");
            return false;
        }
        begin = end + 1;
    }
    return !opt.lockModes.empty();
}

/// With --load-clip, the load is the player playing that clip; prints the one error line when the
/// clip does not exist.
bool setLoadClip(const BenchRtOptions &o, RtBenchOptions &opt)
{
    if (!o.loadClip.empty()) {
        if (!std::filesystem::exists(o.loadClip)) {
            std::fprintf(stderr, "depthtouch bench rt: no clip '%s' for --load-clip\n",
                         o.loadClip.c_str());
            return false;
        }
        opt.load = true;
        const std::string clip = o.loadClip;
        opt.makeLoad = [clip]() -> std::shared_ptr<void> {
            auto load = std::make_shared<PlayerLoad>(clip);
            std::this_thread::sleep_for(std::chrono::seconds(1)); // past opening
            return load;
        };
    }
    return true;
}

/// Checks the device options once, before minutes of measuring, and sets how each case makes its
/// device; prints the one error line when the device cannot be made.
bool setDevice(const BenchRtOptions &o, RtBenchOptions &opt)
{
    hal::BackendConfig cfg;
    cfg.clock = &platform::SteadyClock::instance();
    cfg.options = hal::OptionList(o.hapticOptions);
    hal::SelectionReport report;
    if (auto probe = drivers::createHapticDevice(o.haptic, cfg, &report); !probe) {
        std::fprintf(stderr, "depthtouch bench rt: %s\n", report.message.c_str());
        return false;
    }
    opt.makeDevice = [o]() {
        hal::BackendConfig c;
        c.clock = &platform::SteadyClock::instance();
        c.options = hal::OptionList(o.hapticOptions);
        return drivers::createHapticDevice(o.haptic, c);
    };
    return true;
}

int runBenchRt(const BenchRtOptions &o)
{
    // An --out where nothing can be written fails now, not after the whole run.
    if (const int rc = checkOutFolder("bench rt", o.out); rc != kExitOk)
        return rc;
    RtBenchOptions opt;
    if (!checkRates(o) || !setPolicies(o, opt) || !setLocks(o, opt))
        return kExitBadInput;
    opt.secondsPerCase = o.duration;
    opt.ratesHz = o.rates;
    opt.load = o.load;
    opt.loadThreads = o.loadThreads;
    if (!setLoadClip(o, opt) || !setDevice(o, opt))
        return kExitBadInput;
    const std::size_t cases =
        o.rates.size() * opt.policies.size() * opt.lockModes.size() * 2 * (opt.load ? 2 : 1);
    // Progress on a terminal only, one line rewritten per case (its name); the table is printed
    // once, at the end.
    if (::isatty(STDERR_FILENO) == 1)
        opt.progress = [cases, done = std::size_t{0}](const std::string &line) mutable {
            done = done % cases + 1;
            std::fprintf(stderr, "\r\033[Kcase %zu/%zu done: %.22s%s", done, cases, line.c_str(),
                         done == cases ? "\n" : "");
        };
    std::printf("depthtouch bench rt: %zu cases of %.1f s (haptic device %s)\n", cases, o.duration,
                o.haptic.c_str());
    if (o.runs < 1 || o.runs > 50) {
        std::fprintf(stderr, "depthtouch bench rt: --runs must be in 1..50\n");
        return kExitBadInput;
    }
    RtBenchReport result = runRtBenchmarkRuns(opt, o.runs);
    std::string error;
    std::string note;
    if (!writeRtBenchOutputs(result, o.out, error, note)) {
        std::fprintf(stderr, "depthtouch bench rt: %s\n", error.c_str());
        return kExitFailure;
    }
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s/{rt_bench.csv,rt_bench.png}\n", o.out.c_str());
    return result.cases.empty() ? kExitFailure : kExitOk;
}

} // namespace

void registerBenchRtCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchRtOptions>(bench, "rt", kAbout, kBenchRtRows, runBenchRt, exitCode);
}

} // namespace depthtouch::cli
