/// \file
/// \brief `depthtouch demo`: the main job with no arguments. Encodes the built-in synthetic scene
/// (the turning head, rendered with OpenGL ES: color from the color buffer, depth from the
/// Z-buffer, paper §V.A) into a two-stream file once (kept in the output folder and reused), then
/// plays it with `play` on the headless EGL display with the simulated hand pressing and stroking
/// the face, and leaves side-by-side snapshots, the force log, the stats JSON and a PNG chart of
/// the force over time and its power spectral density (paper Fig. 12) in the output folder.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "depthtouch/haptics/spectrum.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/platform/gnuplot.h"
#include "play.h"
#include "source_providers.h"

namespace depthtouch::cli {

namespace {

struct DemoOptions {
    double duration = 8.0;     ///< Seconds of playback (the clip loops).
    std::string scene = "head";
    std::string size = "480x324"; ///< Clip size WxH.
    int frames = 120;          ///< Clip length, frames at 30 fps.
    std::string outDir = "demo-out";
    std::string display = "headless";
    std::string haptic = "sim";
    std::string hapticOptions = "intent=stroke";
    double stiffness = 800.0;
    double rate = 1000.0;
    bool requireRt = false;
    bool rebuild = false; ///< Encode the clip again even when it exists.
};

/// Encodes the scene into \a clip. \return an error text, or empty.
std::string encodeScene(const DemoOptions &o, const std::string &clip)
{
    media::SourceProviders providers = makeSourceProviders();
    const std::string spec = "synthetic:" + o.scene + ",size=" + o.size +
                             ",frames=" + std::to_string(o.frames);
    media::SourceOptions so;
    so.streamTitle = "color";
    auto color = media::openFrameSource(spec, so, providers);
    if (!color)
        return std::string("cannot render the scene: ") + color.error().what;
    so.streamTitle = "depth";
    auto depth = media::openFrameSource(spec, so, providers);
    if (!depth)
        return std::string("cannot render the scene's depth: ") + depth.error().what;
    media::EncodeOptions eo;
    eo.output = clip;
    eo.preset = "veryfast";
    eo.depthCrf = 12;
    media::EncodeCallbacks cb;
    cb.progress = [](const media::EncodeProgress &p) {
        if (p.totalFrames > 0 && (p.frames % 10 == 0 || p.frames == p.totalFrames)) {
            std::fprintf(stderr, "\r  rendering and encoding frame %lld of %lld (%.1f fps)",
                         p.frames, p.totalFrames,
                         p.elapsed > 0 ? static_cast<double>(p.frames) / p.elapsed : 0.0);
            std::fflush(stderr);
        }
    };
    auto r = media::encodeStreams(**color, **depth, eo, nullptr, cb);
    std::fprintf(stderr, "\n");
    if (!r)
        return std::string("cannot encode the scene: ") + r.error().what;
    return {};
}

/// Reads the force log; writes force-psd.csv and the chart script; runs gnuplot.
/// \return a note for the summary.
std::string chartForce(const std::string &dir, const std::string &forceLog, double rate)
{
    std::ifstream in(forceLog);
    std::string line;
    std::getline(in, line);
    std::vector<double> magnitude;
    while (std::getline(in, line)) {
        double v[12] = {};
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0],
                        &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &v[9], &v[10],
                        &v[11]) == 12)
            magnitude.push_back(std::sqrt(v[7] * v[7] + v[8] * v[8] + v[9] * v[9]));
    }
    if (magnitude.size() < 256)
        return "force log too short for a chart";
    const haptics::Psd psd =
        haptics::averagedPsd(magnitude.data(), magnitude.size(), 8, rate, rate / 2.0);
    const std::string psdCsv = dir + "/force-psd.csv";
    {
        std::ofstream f(psdCsv);
        f << "hz,psd_n2_per_hz\n";
        for (std::size_t k = 1; k < psd.density.size(); ++k)
            f << static_cast<double>(k) * psd.binHz << ',' << psd.density[k] << '\n';
    }
    const std::string script = dir + "/force.gp";
    {
        std::ofstream g(script);
        g << "set terminal pngcairo size 1000,700 font ',10'\n"
          << "set output '" << dir << "/force.png'\n"
          << "set datafile separator ','\n"
          << "set multiplot layout 2,1 title 'DepthTouch demo: force on the simulated hand'\n"
          << "set xlabel 'haptic time (s)'\nset ylabel '|F| (N)'\nset grid\n"
          << "plot '" << forceLog << "' every ::1 using 1:(sqrt($8**2+$9**2+$10**2)) with lines "
          << "lw 1 title '|F|', '' every ::1 using 1:($11*0.2) with steps lc rgb '#aaaaaa' "
          << "title 'contact'\n"
          << "set xlabel 'frequency (Hz)'\nset ylabel 'PSD (N^2/Hz)'\nset logscale y\n"
          << "plot '" << psdCsv << "' every ::1 using 1:2 with lines lw 1 title 'force PSD "
          << "(Welch, 8 segments)'\n"
          << "unset multiplot\n";
    }
    const platform::PlotStatus st = platform::runGnuplot(script);
    return st == platform::PlotStatus::Drawn ? dir + "/force.png"
                                             : platform::plotStatusNote(st);
}

int runDemo(const DemoOptions &o)
{
    int w = 0;
    int h = 0;
    char x = 0;
    if (std::sscanf(o.size.c_str(), "%d%c%d", &w, &x, &h) != 3 || w < 16 || h < 16 ||
        w > 4096 || h > 4096 || o.frames < 2 || o.frames > 100000) {
        std::fprintf(stderr, "depthtouch demo: --size must be WxH (16..4096) and --frames >= 2\n");
        return kExitBadInput;
    }
    std::error_code ec;
    std::filesystem::create_directories(o.outDir + "/snapshots", ec);
    if (ec) {
        std::fprintf(stderr, "depthtouch demo: cannot create '%s': %s\n", o.outDir.c_str(),
                     ec.message().c_str());
        return kExitFailure;
    }
    // The clip: made once per scene, size and length, then reused.
    const std::string clip =
        o.outDir + "/" + o.scene + "-" + o.size + "-" + std::to_string(o.frames) + ".mkv";
    if (o.rebuild || !std::filesystem::exists(clip)) {
        std::printf("Rendering the built-in '%s' scene (%d frames at %s) into %s (once)...\n",
                    o.scene.c_str(), o.frames, o.size.c_str(), clip.c_str());
        std::fflush(stdout);
        if (const std::string err = encodeScene(o, clip); !err.empty()) {
            std::fprintf(stderr, "depthtouch demo: %s\n", err.c_str());
            return kExitFailure;
        }
    }
    for (const auto &entry : std::filesystem::directory_iterator(o.outDir + "/snapshots", ec))
        std::filesystem::remove(entry.path(), ec);

    PlayOptions p;
    p.url = clip;
    p.display = o.display;
    p.haptic = o.haptic;
    p.hapticOptions = o.hapticOptions;
    p.stiffness = o.stiffness;
    p.rate = o.rate;
    p.loop = true;
    p.duration = o.duration;
    p.snapshotDir = o.outDir + "/snapshots";
    p.snapshotEvery = 30;
    p.forceLog = o.outDir + "/force-log.csv";
    p.stats = o.outDir + "/stats.json";
    p.requireRt = o.requireRt;
    p.quiet = true;
    std::printf("Playing it for %.0f s on the '%s' display with the '%s' haptic device "
                "(%s)\n",
                o.duration, o.display.c_str(), o.haptic.c_str(), o.hapticOptions.c_str());
    std::fflush(stdout);
    const PlayResult r = runPlay(p);
    if (r.exitCode != kExitOk)
        return r.exitCode;
    const std::string chart = chartForce(o.outDir, p.forceLog, o.rate);
    std::printf("  chart             %s\n", chart.c_str());
    std::printf("  snapshots         %s/snapshots/ (side-by-side, every 30 frames)\n",
                o.outDir.c_str());
    return kExitOk;
}

} // namespace

void registerDemoCommand(CLI::App &app, int &exitCode)
{
    auto o = std::make_shared<DemoOptions>();
    CLI::App *cmd = app.add_subcommand(
        "demo", "The main job: play the built-in head scene and touch it with the simulated hand");
    cmd->add_option("--duration", o->duration, "Seconds of playback")->capture_default_str();
    cmd->add_option("--out", o->outDir, "Folder for the clip, snapshots, force log, stats, chart")
        ->capture_default_str();
    cmd->add_option("--scene", o->scene, "Built-in scene: head, spheres, cut")
        ->capture_default_str();
    cmd->add_option("--size", o->size, "Clip size WxH")->capture_default_str();
    cmd->add_option("--frames", o->frames, "Clip length in frames (30 fps)")
        ->capture_default_str();
    cmd->add_option("--display", o->display, "Display backend")->capture_default_str();
    cmd->add_option("--haptic", o->haptic, "Haptic device backend: sim, mock, falcon, none")
        ->capture_default_str();
    cmd->add_option("--haptic-options", o->hapticOptions, "Options of the haptic device")
        ->capture_default_str();
    cmd->add_option("--stiffness", o->stiffness, "Surface stiffness, N/m")->capture_default_str();
    cmd->add_option("--rate", o->rate, "Haptic servo rate, Hz")->capture_default_str();
    cmd->add_flag("--require-rt", o->requireRt, "Fail when SCHED_FIFO is refused");
    cmd->add_flag("--rebuild", o->rebuild, "Render and encode the clip again");
    cmd->callback([o, &exitCode] { exitCode = runDemo(*o); });
}

} // namespace depthtouch::cli
