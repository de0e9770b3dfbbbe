/// \file
/// \brief `depthtouch bench rt`: wake latency and period error of the haptic servo loop (bare loop
/// and the full haptic task with the simulated hand on a moving depth video) at 1 kHz and 4 kHz,
/// SCHED_FIFO against SCHED_OTHER, idle and optionally loaded; CSV and a PNG chart into --out.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptic_task/rt_bench.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::cli {

namespace {

struct BenchRtOptions {
    std::string out = "bench-out/rt";
    double duration = 5.0;
    std::vector<double> rates{1000.0, 4000.0};
    std::string policies = "fifo,other";
    bool load = false;
    int loadThreads = 2;
    std::string haptic = "sim";
    std::string hapticOptions = "intent=stroke,force=1.5,z=0.01,speed=0.05";
};

int runBenchRt(const BenchRtOptions &o)
{
    using namespace depthtouch::haptic_task::bench;
    RtBenchOptions opt;
    if (!(o.duration > 0.0 && o.duration <= 600.0) || o.rates.empty() || o.loadThreads < 1 ||
        o.loadThreads > 64) {
        std::fprintf(stderr, "depthtouch bench rt: --duration must be in (0, 600] s, --rates not "
                             "empty, --load-threads in 1..64\n");
        return kExitBadInput;
    }
    for (const double r : o.rates) {
        if (!(r >= 100.0 && r <= 10000.0)) {
            std::fprintf(stderr, "depthtouch bench rt: --rates must be in [100, 10000] Hz\n");
            return kExitBadInput;
        }
    }
    opt.policies.clear();
    if (o.policies.find("fifo") != std::string::npos)
        opt.policies.push_back(platform::SchedPolicy::Fifo);
    if (o.policies.find("other") != std::string::npos)
        opt.policies.push_back(platform::SchedPolicy::Other);
    if (opt.policies.empty()) {
        std::fprintf(stderr, "depthtouch bench rt: --policies takes fifo, other or fifo,other\n");
        return kExitBadInput;
    }
    opt.secondsPerCase = o.duration;
    opt.ratesHz = o.rates;
    opt.load = o.load;
    opt.loadThreads = o.loadThreads;
    // Check the device options once, before minutes of measuring.
    hal::BackendConfig cfg;
    cfg.clock = &platform::SteadyClock::instance();
    cfg.options = hal::OptionList(o.hapticOptions);
    hal::SelectionReport report;
    if (auto probe = drivers::createHapticDevice(o.haptic, cfg, &report); !probe) {
        std::fprintf(stderr, "depthtouch bench rt: %s\n", report.message.c_str());
        return kExitBadInput;
    }
    opt.makeDevice = [o]() {
        hal::BackendConfig c;
        c.clock = &platform::SteadyClock::instance();
        c.options = hal::OptionList(o.hapticOptions);
        return drivers::createHapticDevice(o.haptic, c);
    };
    opt.progress = [](const std::string &line) {
        std::printf("%s\n", line.c_str());
        std::fflush(stdout);
    };
    const std::size_t cases = o.rates.size() * opt.policies.size() * 2 * (o.load ? 2 : 1);
    std::printf("depthtouch bench rt: %zu cases of %.1f s (haptic device %s)\n", cases, o.duration,
                o.haptic.c_str());
    const RtBenchReport result = runRtBenchmark(opt);
    printRtReport(result);
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
    auto o = std::make_shared<BenchRtOptions>();
    CLI::App *cmd = bench.add_subcommand(
        "rt", "Haptic loop timing: wake latency and period error, bare loop vs haptic task, "
              "SCHED_FIFO vs SCHED_OTHER; CSV/PNG");
    cmd->add_option("--out", o->out, "Output directory")->capture_default_str();
    cmd->add_option("--duration", o->duration, "Seconds per case")->capture_default_str();
    cmd->add_option("--rates", o->rates, "Servo rates, Hz")->capture_default_str();
    cmd->add_option("--policies", o->policies, "fifo, other or fifo,other")->capture_default_str();
    cmd->add_flag("--load", o->load, "Also run every case while other threads load the CPUs");
    cmd->add_option("--load-threads", o->loadThreads, "Threads of the load")->capture_default_str();
    cmd->add_option("--haptic", o->haptic, "Haptic device of the task cases")
        ->capture_default_str();
    cmd->add_option("--haptic-options", o->hapticOptions, "Its options")->capture_default_str();
    cmd->callback([o, &exitCode]() { exitCode = runBenchRt(*o); });
}

} // namespace depthtouch::cli
