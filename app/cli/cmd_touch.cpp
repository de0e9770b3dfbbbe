/// \file
/// \brief `depthtouch touch DEPTH --trajectory traj.csv --out forces.csv`: replays a HIP trajectory
/// against a depth video at the haptic rate and writes the force log CSV (DESIGN.md §4),
/// deterministically. Bad input prints one error line and exits 2 without leaving an output file.

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/replay.h"

namespace depthtouch::cli {

namespace {

struct TouchOptions {
    std::string depth;
    std::string trajectory;
    std::string out;
    std::string size;
    double fps = 30.0;
    int bits = 8;
    double rate = 1000.0;
    double stiffness = 800.0;
    double damping = 0.0;
    double maxForce = 8.5;
    double boxWidth = 0.10;
    double boxDepth = 0.04;
    std::string method = "modified";
    bool noCorrection = false;
    bool noInterpolation = false;
    bool noSafety = false;
    double maxForceStep = 2.0;
    std::string reengage = "release";
    double rampTime = 0.25;
};

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch touch: %s\n", message.c_str());
    return code;
}

bool readFile(const std::string &path, std::vector<std::uint8_t> &bytes)
{
    std::FILE *f = std::fopen(path.c_str(), "rb");
    if (f == nullptr)
        return false;
    bytes.clear();
    std::uint8_t buf[65536];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
        bytes.insert(bytes.end(), buf, buf + n);
    const bool ok = std::ferror(f) == 0;
    std::fclose(f);
    return ok;
}

int runTouch(const TouchOptions &o)
{
    using namespace depthtouch::haptics;
    auto method = parseMethod(o.method);
    if (!method)
        return fail(kExitBadInput, "--method must be modified, proxy-graph or mesh-bvh");
    if (o.reengage != "release" && o.reengage != "ramp")
        return fail(kExitBadInput, "--reengage must be release or ramp");
    if (!(o.rate > 0.0))
        return fail(kExitBadInput, "--rate must be positive");
    ReplayOptions opt;
    opt.rate = o.rate;
    opt.method = *method;
    RendererConfig &c = opt.config;
    c.box = SceneBox{o.boxWidth, o.boxDepth};
    c.stiffness = o.stiffness;
    c.damping = o.damping;
    c.maxForce = o.maxForce;
    // The baselines run with every fix off; the --no-* flags turn single fixes off in `modified`.
    const bool fixes = *method == Method::Modified;
    c.correction = fixes && !o.noCorrection;
    c.interpolation = fixes && !o.noInterpolation;
    c.safety = fixes && !o.noSafety;
    c.maxForceStep = o.maxForceStep;
    c.reengage = o.reengage == "ramp" ? Reengage::Ramp : Reengage::Release;
    c.rampTime = o.rampTime;
    if (auto v = c.validate(); !v)
        return fail(kExitBadInput, v.error().what);

    // Depth input: raw gray frames for now; video files need the media layer's decoder.
    if (o.size.empty())
        return fail(kExitBadInput, "unsupported depth input '" + o.depth +
                                       "': video files need the media decoder (not built yet); give a "
                                       "raw gray file with --size WxH --fps N [--bits 8|16]");
    int w = 0;
    int h = 0;
    char x = 0;
    std::istringstream ss(o.size);
    if (!(ss >> w >> x >> h) || x != 'x' || w < 2 || h < 2 || !ss.eof())
        return fail(kExitBadInput, "--size must be WxH with W, H >= 2");
    if (o.bits != 8 && o.bits != 16)
        return fail(kExitBadInput, "--bits must be 8 or 16");
    std::vector<std::uint8_t> bytes;
    if (!readFile(o.depth, bytes))
        return fail(kExitBadInput, "cannot read depth file '" + o.depth + "'");
    RawVideoFrameProvider frames(std::move(bytes), w, h,
                                 o.bits == 8 ? SampleFormat::Gray8 : SampleFormat::Gray16, o.fps);
    if (auto v = frames.validate(); !v)
        return fail(kExitBadInput, std::string(v.error().what) + " ('" + o.depth + "')");

    std::vector<std::uint8_t> trajBytes;
    if (!readFile(o.trajectory, trajBytes))
        return fail(kExitBadInput, "cannot read trajectory '" + o.trajectory + "'");
    std::size_t line = 0;
    const std::string_view text(reinterpret_cast<const char *>(trajBytes.data()), trajBytes.size());
    auto traj = parseTrajectoryCsv(text, &line);
    if (!traj)
        return fail(kExitBadInput, o.trajectory + ":" + std::to_string(line) + ": " + traj.error().what);

    auto rows = replay(frames, *traj, opt);
    if (!rows)
        return fail(rows.error().code == Errc::Io ? kExitFailure : kExitBadInput, rows.error().what);

    // Write to a temporary name in the same directory, then rename: never a partial output file.
    const std::string tmp = o.out + ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        const std::string csv = formatForceLog(*rows);
        out.write(csv.data(), static_cast<std::streamsize>(csv.size()));
        out.close();
        if (!out) {
            std::remove(tmp.c_str());
            return fail(kExitFailure, "Failed to write '" + o.out + "'");
        }
    }
    if (std::rename(tmp.c_str(), o.out.c_str()) != 0) {
        std::remove(tmp.c_str());
        return fail(kExitFailure, "Failed to rename the force log to '" + o.out + "'");
    }
    return kExitOk;
}

} // namespace

void registerTouchCommand(CLI::App &app, int &exitCode)
{
    auto o = std::make_shared<TouchOptions>();
    CLI::App *cmd = app.add_subcommand(
        "touch", "Replay a HIP trajectory against a depth video at the haptic rate; write the force log CSV");
    cmd->add_option("DEPTH", o->depth, "Depth video (raw 8/16-bit gray frames with --size)")->required();
    cmd->add_option("--trajectory", o->trajectory, "HIP trajectory CSV t,x,y,z (s, m)")->required();
    cmd->add_option("--out", o->out, "Force log CSV to write")->required();
    cmd->add_option("--size", o->size, "Raw depth frame size WxH (pixels)");
    cmd->add_option("--fps", o->fps, "Raw depth frame rate (frames/s)")->capture_default_str();
    cmd->add_option("--bits", o->bits, "Raw depth sample size: 8 or 16 (host byte order)")->capture_default_str();
    cmd->add_option("--rate", o->rate, "Haptic update rate (Hz)")->capture_default_str();
    cmd->add_option("--stiffness", o->stiffness, "Spring stiffness k (N/m)")->capture_default_str();
    cmd->add_option("--damping", o->damping, "Damping b (N·s/m)")->capture_default_str();
    cmd->add_option("--max-force", o->maxForce, "Device maximum force (N)")->capture_default_str();
    cmd->add_option("--box-width", o->boxWidth, "Scene box width (m)")->capture_default_str();
    cmd->add_option("--box-depth", o->boxDepth, "Scene box depth (m)")->capture_default_str();
    cmd->add_option("--method", o->method, "modified | proxy-graph | mesh-bvh")->capture_default_str();
    cmd->add_flag("--no-correction", o->noCorrection, "Turn off fix (a), collision correction");
    cmd->add_flag("--no-interpolation", o->noInterpolation, "Turn off fix (b), surface interpolation");
    cmd->add_flag("--no-safety", o->noSafety, "Turn off fix (c), force-jump safety");
    cmd->add_option("--max-force-step", o->maxForceStep,
                    "Force change per update that trips safety (N); the default 2 N never trips while "
                    "stroking smooth surfaces at 1 m/s (k=800: <= 0.8 N/update) and always trips at a "
                    "cut of half the box depth (16 N)")
        ->capture_default_str();
    cmd->add_option("--reengage", o->reengage, "After a trip: release | ramp")->capture_default_str();
    cmd->add_option("--ramp-time", o->rampTime, "Ramp duration for --reengage ramp (s)")->capture_default_str();
    cmd->callback([o, &exitCode]() { exitCode = runTouch(*o); });
}

} // namespace depthtouch::cli
