/// \file
/// \brief `depthtouch bench av`: picture and sound in sync. The built-in head scene with its
/// soundtrack (a click at each loop start, a tone as the head turns) is played in a loop for
/// --duration s on each sound output asked (`null` and `wav` by default: both keep time as a
/// sound card does), on the mock display (paced at 60 Hz, nothing drawn) or another; every frame
/// presented while sound plays gives its A/V offset (`play --av-log`: the media time heard when
/// it was presented minus its PTS). Printed per output: median, 99th percentile and largest
/// |offset| against the ±20 ms goal, and the underruns; written: av-OUTPUT.csv, stats-OUTPUT.json
/// and av.png (the offset over play time, one line per output, the goal and ITU-R BT.1359's
/// detectability thresholds drawn).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_options.h"
#include "commands.h"
#include "depthtouch/demo/demo_clip.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/percentile.h"
#include "depthtouch/platform/report_file.h"
#include "option_cli.h"
#include "output_paths.h"
#include "play.h"
#include "source_providers.h"

namespace depthtouch::cli {

namespace {

constexpr double kGoalMs = 20.0; ///< |A/V offset| at p99 (the sound's issue's goal).

struct BenchAvOptions {
    std::string out = "bench-av-out";
    double duration = 60.0;
    std::vector<std::string> outputs{"null", "wav"};
    std::string display = "mock";
    std::string size = "320x216";
    int frames = 120;
};

constexpr const char *kAbout =
    "Picture and sound in sync: the A/V offset of every presented frame of the looping head "
    "scene with its soundtrack, per sound output, against the 20 ms goal";

const OptionRow<BenchAvOptions> kBenchAvRows[] = {
    benchOutRow<BenchAvOptions>(),
    {"duration", &BenchAvOptions::duration, "Seconds played on each sound output"},
    {"output",
     &BenchAvOptions::outputs,
     "Sound outputs (comma-separated): null, wav, alsa, mock",
     {},
     kCommaList},
    {"display", &BenchAvOptions::display, "Display backend: mock (60 Hz, nothing drawn), headless"},
    {"size", &BenchAvOptions::size, "Size of the scene's clip, WxH"},
    {"frames", &BenchAvOptions::frames, "Length of the scene's clip, frames at 30 fps (looped)"},
};

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch bench av: %s\n", message.c_str());
    return code;
}

/// What one output measured.
struct AvRun {
    std::string output;
    std::string log;                        ///< Its --av-log CSV.
    std::vector<double> offset;             ///< ms, one per presented frame with sound.
    double p50 = 0.0, p99 = 0.0, max = 0.0; ///< Median offset; p99 and largest |offset|, ms.
    long long underruns = 0;
};

/// Reads the offsets of an --av-log CSV (time_s,pts_s,offset_ms). \return false when unreadable.
bool readAvLog(const std::string &path, std::vector<double> &offsets)
{
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line))
        return false;
    while (std::getline(in, line)) {
        double t = 0.0;
        double pts = 0.0;
        double ms = 0.0;
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &pts, &ms) == 3)
            offsets.push_back(ms);
    }
    return true;
}

/// Plays the clip on \a run.output and reads what it measured. \return an error text, or empty.
std::string playOn(const BenchAvOptions &o, const std::string &clip, AvRun &run)
{
    PlayOptions p;
    p.url = clip;
    p.display = o.display;
    p.haptic = "none";
    p.audioDevice = run.output;
    if (run.output == "wav")
        p.audioDeviceOptions = "path=" + o.out + "/av.wav";
    p.loop = true;
    p.duration = o.duration;
    p.avLog = run.log;
    p.stats = o.out + "/stats-" + run.output + ".json";
    p.quiet = true;
    const PlayResult r = runPlay(p);
    if (r.exitCode != kExitOk)
        return "play on '" + run.output + "' ended with exit code " + std::to_string(r.exitCode);
    if (r.stats.value("audio", std::string()).empty())
        return "play on '" + run.output + "' played no sound";
    run.underruns = r.stats.value("audio_underruns", 0LL);
    if (!readAvLog(run.log, run.offset) || run.offset.empty())
        return "no A/V offsets in " + run.log;
    std::vector<double> magnitude(run.offset);
    for (double &v : magnitude)
        v = std::abs(v);
    run.p50 = platform::percentile(run.offset, 0.50);
    run.p99 = platform::percentile(magnitude, 0.99);
    run.max = *std::max_element(magnitude.begin(), magnitude.end());
    return {};
}

/// Writes av.gp and draws av.png. \return the chart's path, or why there is none.
std::string drawChart(const BenchAvOptions &o, const std::vector<AvRun> &runs)
{
    const std::string script = o.out + "/av.gp";
    std::string lost;
    {
        platform::TextReportFile g(script, lost);
        g << "set terminal pngcairo size 1000,520 font ',10'\n"
          << "set output '" << o.out << "/av.png'\n"
          << "set datafile separator ','\n"
          << "set title 'DepthTouch bench av: A/V offset of each presented frame (head scene with "
             "its soundtrack, looping)'\n"
          << "set grid\nset key outside right top vertical\nset rmargin 34\n"
          << "set xlabel 'play time (s)'\nset ylabel 'sound heard minus picture shown (ms)'\n"
          << "set yrange [-60:60]\n"
          << "plot " << kGoalMs
          << " with lines dt 2 lw 2 lc rgb '#2a9d2a' title 'goal +-20 ms (p99)', " << -kGoalMs
          << " with lines dt 2 lw 2 lc rgb '#2a9d2a' notitle, "
          << "45 with lines dt 3 lc rgb '#c03030' title 'BT.1359 detectable: sound 45 ms early'";
        const char *colors[] = {"#1f5fbf", "#d07000", "#7a3fb0", "#333333"};
        for (std::size_t i = 0; i < runs.size(); ++i)
            g << ", '" << runs[i].log << "' every ::1 using 1:3 with lines lw 1 lc rgb '"
              << colors[i % 4] << "' title '" << runs[i].output << " output'";
        g << "\n";
    }
    if (!lost.empty())
        return "not drawn: " + lost;
    const platform::PlotStatus st = platform::runGnuplot(script, o.out + "/gnuplot.log");
    return st == platform::PlotStatus::Drawn ? o.out + "/av.png" : platform::plotStatusNote(st);
}

int runBenchAv(const BenchAvOptions &o)
{
    if (!(o.duration >= 1.0 && o.duration <= 3600.0))
        return fail(kExitBadInput, "--duration must be 1 to 3600 s");
    if (o.frames < 30 || o.frames > 100000)
        return fail(kExitBadInput, "--frames must be 30 to 100000");
    if (const int rc = checkOutFolder("bench av", o.out); rc != kExitOk)
        return rc;
    std::error_code ec;
    std::filesystem::create_directories(o.out, ec);
    if (ec)
        return fail(kExitFailure, "cannot create --out " + o.out + ": " + ec.message());
    platform::setLogLevel(platform::LogLevel::Error);
    const std::string clip =
        o.out + "/head-" + o.size + "-" + std::to_string(o.frames) + "-sound.mkv";
    if (!std::filesystem::exists(clip)) {
        bool interrupted = false;
        if (std::string err = demo::encodeScene("head", o.size, o.frames, clip,
                                                makeSourceProviders(), interrupted);
            !err.empty() || interrupted)
            return fail(kExitFailure, interrupted ? "interrupted" : err);
    }
    std::vector<AvRun> runs;
    std::printf("%-8s %8s %10s %10s %10s %10s  %s\n", "output", "frames", "median ms", "p99 |ms|",
                "max |ms|", "underruns", "goal (p99 <= 20 ms)");
    for (const std::string &output : o.outputs) {
        AvRun run;
        run.output = output;
        run.log = o.out + "/av-" + output + ".csv";
        if (std::string err = playOn(o, clip, run); !err.empty())
            return fail(kExitFailure, err);
        std::printf("%-8s %8zu %+10.1f %10.1f %10.1f %10lld  %s\n", output.c_str(),
                    run.offset.size(), run.p50, run.p99, run.max, run.underruns,
                    run.p99 <= kGoalMs ? "met" : "NOT met");
        runs.push_back(std::move(run));
    }
    std::printf("chart: %s\n", drawChart(o, runs).c_str());
    return kExitOk;
}

} // namespace

void registerBenchAvCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchAvOptions>(bench, "av", kAbout, kBenchAvRows, runBenchAv, exitCode);
}

} // namespace depthtouch::cli
