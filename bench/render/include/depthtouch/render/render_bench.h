#pragma once
/// \file
/// \brief The stereo renderer benchmark (`depthtouch bench render`): frame rate against geometric
/// error for the full mesh, fixed decimations and the adaptive mesh at several error tolerances,
/// stereo side-by-side on real RGB-D frames (and the synthetic head), with the render thread's CPU
/// time for each frame's depth geometry at several depth sizes; CSV, gnuplot charts and a printed
/// table.
///
/// Real data: Microsoft 7-Scenes "redkitchen" (DT_SHARED_DATA/rgbd-7scenes-redkitchen: 640×480
/// Kinect depth in mm + JPEG colour), converted like the sender does it: metric depth → 8-bit
/// nearness (dt_depth, 1/Z mapping, planes fixed from the first frame's robust range), holes
/// filled, resampled to the benchmark size; colour → yuv420p BT.601 limited range. Thread-safety:
/// thread-bound (the GL thread).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/platform/result.h"
#include "depthtouch/render/adaptive_mesh.h"
#include "depthtouch/render/stereo.h"

namespace depthtouch::render::bench {

/// \brief One RGB-D frame ready for the renderer: 8-bit nearness and yuv420p colour.
struct RgbdFrame {
    int width = 0;  ///< Depth W.
    int height = 0; ///< Depth H.
    std::vector<std::uint8_t> nearness; ///< W×H, row-major, 0 = far plane.
    int colorWidth = 0;
    int colorHeight = 0;
    std::vector<std::uint8_t> y, u, v; ///< yuv420p planes, tightly packed.
};

/// \brief Loads up to \a maxFrames consecutive 7-Scenes frames from \a sceneDir, depth resampled
/// to \a width × \a height. \return Errc::Io when the folder has no frame-000000.depth.png,
/// Errc::InvalidArgument for corrupt images or sizes ≤ 1.
Result<std::vector<RgbdFrame>> loadKitchenFrames(const std::string &sceneDir, int maxFrames,
                                                 int width, int height);

/// \brief Renders \a maxFrames frames of the synthetic `head` scene (app/synthetic: every third
/// frame of its 30 fps animation) at \a width × \a height, depth as 8-bit nearness and colour as
/// yuv420p BT.601 limited range. \pre a current GLES 3 context. \return InvalidArgument for sizes
/// outside 16..4096 or a count < 1; the scene's errors.
Result<std::vector<RgbdFrame>> loadHeadFrames(int maxFrames, int width, int height);

/// \brief Parses a depth size "WxH" (each 2..8192). \return false when malformed.
bool parseDepthSize(const std::string &text, int &width, int &height);

/// \brief One mesh setting measured.
struct BenchConfig {
    std::string name;  ///< e.g. "full", "step4", "adaptive-1.0"
    MeshOptions mesh;
};

/// \brief The stages of one frame as the player runs them, in order: depth texture upload, level of
/// detail and index list (CPU), index upload, colour upload, clear, left eye, right eye, avatar and
/// on-screen display, blit to the display framebuffer.
inline constexpr int kStageCount = 9;
/// \return the short name of stage \a i ("depth", "mesh", "index", "color", "clear", "eye1",
/// "eye2", "overlay", "blit"); static string.
const char *stageName(int i) noexcept;

/// \brief The figures of one setting.
struct BenchRow {
    std::string name;
    std::string family; ///< "fixed", "adaptive", "quadtree" or "budgets" (chart lines).
    std::string source; ///< The frames: "kitchen" or "head".
    int depthWidth = 0; ///< Depth frame size, samples.
    int depthHeight = 0;
    /// Render-thread CPU time of the frame's depth geometry (StereoRenderer::setDepth() with the
    /// mesh made ahead, as the player calls it: level choice left, index selection, depth texture
    /// upload, mapping), median over the frames, ms; thread CPU time (CLOCK_THREAD_CPUTIME_ID).
    double geomCpuMs = 0.0;
    double geomCpuP99Ms = 0.0; ///< Its 99th percentile, ms.
    /// CPU time of the work the player does on its prep thread for that frame (FramePrep::build()
    /// without colour: the quadtree's level choice and triangle list; nothing for a fixed step,
    /// whose grid is static), median, ms; thread CPU time. Here run on the render thread before
    /// the frame, so the frame time includes it.
    double prepCpuMs = 0.0;
    double tolerance = 0.0;     ///< Adaptive tolerance, levels (0 for fixed meshes).
    int step = 0;               ///< Fixed step (0 for adaptive).
    double meanTriangles = 0.0; ///< Triangles per frame (each drawn twice: one per eye).
    double medianMs = 0.0;      ///< Frame time, median, ms (uploads, mesh, both eyes, avatar, OSD,
                                ///< blit, glFinish): what the player spends per frame.
    double p99Ms = 0.0;         ///< Frame time, 99th percentile, ms.
    double fps = 0.0;           ///< 1000 / medianMs.
    double cpuMs = 0.0; ///< Process CPU time per frame (all threads, incl. the rasterizer's), ms:
                        ///< less sensitive than wall time to other load on a shared machine.
    double meshMs = 0.0;        ///< Median time of the level choice and index list (CPU), ms.
    double drawMs = 0.0; ///< Median time in the two eyes' draw calls on the calling thread (vertex
                         ///< processing and binning on llvmpipe; shading runs later), ms.
    /// Stage breakdown: each frame drawn a second time with a glFinish after each stage
    /// (StageTiming::Finished), so each stage carries its own rasterization: median and 99th
    /// percentile per stage (order of stageName()), and of the per-frame sum, ms.
    std::array<double, kStageCount> stageMedianMs{};
    std::array<double, kStageCount> stageP99Ms{};
    double stagedMedianMs = 0.0;
    double stagedP99Ms = 0.0;
    double meanError = 0.0; ///< Mean |surface − sample| over all frames' samples, nearness levels.
    double maxError = 0.0;      ///< Largest |surface − sample| over all frames, nearness levels.
    std::size_t uncovered = 0;  ///< Samples not covered by any triangle (cracks): 0 expected.
};

/// \brief Benchmark options.
struct BenchOptions {
    std::string source = "kitchen";    ///< Name of the frames, for the rows (BenchRow::source).
    int outputWidth = 1440;            ///< Side-by-side frame: two 720-wide eyes.
    int outputHeight = 486;
    StereoMode mode = StereoMode::SideBySide;
    bool frameCompatible = false;      ///< false: each half is a full-aspect 720×486 eye.
    int framesPerConfig = 60;          ///< Frames rendered per setting (cycling through the data).
    int warmup = 5;                    ///< Frames rendered and not timed first.
    bool stageBreakdown = true;        ///< Also run the staged pass (BenchRow::stageMedianMs).
    std::vector<BenchConfig> configs;  ///< Empty: defaultConfigs().
    /// Framebuffer the output is blitted to, as the player does (a display's framebuffer()); unset:
    /// an offscreen RGBA8 target of the output size, like the headless display's.
    std::optional<std::uint32_t> presentFramebuffer;
};

/// \return full mesh, steps 2/4/8, per-tile adaptive (tile 8, mean criterion, cap 16 levels; the
/// default MeshOptions at 1.2) at tolerances 0.3, 0.5, 0.7, 0.9 and 1.2 levels, and the quadtree
/// (root 32, frame mean error budget, cap 16) at budgets 0.3, 0.4, 0.45, 0.5 and 0.6 levels.
std::vector<BenchConfig> defaultConfigs();

/// \return the settings run at the depth sizes after the first of `--depth-sizes` (their full
/// mesh draws millions of triangles on a software rasterizer): full, step4, quadtree-0.50 and
/// budget-6k.
std::vector<BenchConfig> depthSizeConfigs();

/// \brief Runs every setting on \a frames; the settings take turns frame by frame (each frame is
/// drawn by every setting before the next), so a change of load on a shared machine affects them
/// alike. \pre a current GLES 3 context with EXT_color_buffer_float
/// not needed. \return the rows in setting order; errors of the renderer (e.g. NotSupported).
Result<std::vector<BenchRow>> runRenderBenchmark(const std::vector<RgbdFrame> &frames,
                                                 const BenchOptions &options);

/// \brief Renders frame \a index of \a frames side-by-side with \a mesh and writes it as PNG.
Result<void> writeSideBySideSnapshot(const std::vector<RgbdFrame> &frames, std::size_t index,
                                     const MeshOptions &mesh, int width, int height,
                                     const std::string &path);

/// \return the settings of defaultConfigs() whose names are in \a names (comma-separated; empty:
/// all). \return Errc::InvalidArgument naming no known setting.
Result<std::vector<BenchConfig>> selectConfigs(const std::string &names);

/// \brief Prints the tables (frame rate vs error; stage breakdown) to stdout.
void printTable(const std::vector<BenchRow> &rows, const BenchOptions &options);

/// \brief What runDepthSizes() measures.
struct DepthSizesPlan {
    std::string scene;                      ///< The 7-Scenes kitchen folder.
    std::vector<std::pair<int, int>> sizes; ///< Depth sizes (width, height), pixels; the first
                                            ///< is the main one.
    bool withHead = false;   ///< Also the synthetic head at each size (--depth-sizes given).
    bool allConfigs = false; ///< Every size runs \a configs (--only given), not only the first.
    int frames = 0;      ///< Frames per config at the first size (a quarter, at least 5, after).
    bool stages = false; ///< Per-stage breakdown of the first size's kitchen.
    std::vector<BenchConfig> configs; ///< The configs of the first size.
};

/// \brief Why runDepthSizes() stopped: the one-line message, and whether the input was bad (the
/// frames of a size could not be made) rather than the run failing.
struct DepthSizesError {
    bool badInput = false;
    std::string message;
};

/// \brief Runs every depth size of \a plan (the kitchen, and the head when asked; fewer frames of a
/// larger size: about the memory of 60 frames of 720×486) with \a bo (its source, configs, frames,
/// warm-up and breakdown set per run) into \a rows; the first size's kitchen frames into
/// \a firstFrames. Needs the GLES context current. \return nothing, or why not.
std::optional<DepthSizesError> runDepthSizes(const DepthSizesPlan &plan, BenchOptions &bo,
                                             std::vector<BenchRow> &rows,
                                             std::vector<RgbdFrame> &firstFrames);

/// \brief Writes `render_bench.csv` (one row per setting, frame source and depth size; stage
/// medians and p99 included) and, when gnuplot is installed, `fps_vs_error.png` (one line per
/// family, the rows of the first source and size), `stages.png` (stacked stage medians, same rows;
/// only when they had the stage pass, else an earlier run's is removed) and `cpu_vs_depth_size.png`
/// (geometry CPU per frame against the depth size, or the triangles at one size) into \a dir.
/// gnuplot's messages go to `gnuplot.log` there, never to stderr.
/// \param[out] note a remark for the user (e.g. gnuplot missing, or its first message)
/// \return false with \a error set when the directory or CSV cannot be written.
bool writeBenchOutputs(const std::vector<BenchRow> &rows, const std::string &dir,
                       std::string &error, std::string &note);

/// \brief The end of `depthtouch bench render`: prints the tables (printTable() with \a options),
/// writes the files into \a out (writeBenchOutputs()) and the side-by-side snapshot of frame 0 of
/// \a firstFrames (kitchen_sbs.png, at the options' output size; one that cannot be written is a
/// line on stderr, not an error), and says what was written on stdout. Needs the GLES context
/// current. \return false with \a error set when a file of the tables cannot be written.
bool finishRenderBench(const std::vector<BenchRow> &rows, const BenchOptions &options,
                       const std::vector<RgbdFrame> &firstFrames, const std::string &out,
                       std::string &error);

} // namespace depthtouch::render::bench
