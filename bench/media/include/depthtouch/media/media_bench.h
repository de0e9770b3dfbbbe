#pragma once
/// \file
/// \brief The media pipeline benchmark (`depthtouch bench media`), issue "Benchmark: depthtouch
/// bench media":
///  - throughput: encode frames per second of the color + depth pair per x264 preset and frame
///    size (the sender's encoders and muxer, encoder.h), and decode + pairing frames per second of
///    the files written, through the receiver (receiver.h) on the backends the caller passes
///    (the executable: ffmpeg, one decoder thread per stream), with the median and 99th percentile
///    of the time per paired frame and the multiple of real time;
///  - rate against haptic accuracy: the depth stream encoded at several x264 CRFs and lossless;
///    per setting the depth bitrate, the PSNR of the decoded 8-bit nearness against the lossless
///    one, and the force error of one scripted stroke replayed (haptics/replay.h, as `depthtouch
///    touch` does) on the decoded depth against the same stroke on the lossless depth.
///
/// Content: real RGB-D frames (7-Scenes "redkitchen": 640×480 JPEG color, 16-bit depth in mm)
/// converted as the sender does it (metric depth → 8-bit nearness in the 1/Z mapping with the
/// planes of the first frame's robust range, holes filled, depth/conversion.h, depth/fill.h),
/// then stretched to each benchmark size (color bicubic through libswscale, depth edge-aware,
/// depth/resample.h); or a synthetic clip. Units: seconds, pixels, kbit/s, dB, newtons.
///
/// Thread-safety: reentrant functions; the ReceiverBackends factories are called on the calling
/// thread. Timing uses platform::SteadyClock on the calling thread (one core).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/media/depth_codec_bench.h"
#include "depthtouch/media/image.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::media::bench {

/// \brief A color + depth clip in memory: Rgb24 color and Gray8 nearness (0 = far plane, 255 =
/// near plane, docs/architecture.md §3) of one size, \a fps frames per second.
///
/// Frame i of the clip is picture order[i] of the stored pictures, so a short sequence can be
/// played forward and backward without copies.
struct Clip {
    int width = 0;  ///< Pixels.
    int height = 0; ///< Pixels.
    double fps = 30.0;
    std::vector<Image> colors;     ///< Stored pictures: Rgb24, width × height.
    std::vector<Image> nearnesses; ///< Stored pictures: Gray8, width × height, same count.
    /// The same nearness at 16 bits (Gray16, 0..65535, the source's own precision before the
    /// 8-bit rounding), same count: the reference of the depth codec comparison.
    std::vector<Image> fineNearnesses;
    std::vector<std::size_t> order; ///< Frame i → stored picture; each entry < colors.size().
    std::string description; ///< E.g. "7-Scenes redkitchen: 60 frames 640x480 stretched to …".

    /// \return the number of frames.
    [[nodiscard]] std::size_t frames() const noexcept { return order.size(); }
    /// \return the color of frame \a i. \pre i < frames().
    [[nodiscard]] const Image &color(std::size_t i) const noexcept { return colors[order[i]]; }
    /// \return the nearness of frame \a i. \pre i < frames().
    [[nodiscard]] const Image &nearness(std::size_t i) const noexcept
    {
        return nearnesses[order[i]];
    }
    /// \return the 16-bit nearness of frame \a i. \pre i < frames().
    [[nodiscard]] const Image &fineNearness(std::size_t i) const noexcept
    {
        return fineNearnesses[order[i]];
    }
};

/// \brief Loads \a frames frames of a 7-Scenes scene folder (frame-NNNNNN.color.jpg and
/// frame-NNNNNN.depth.png from 000000), converted as in the file comment and stretched to
/// \a width × \a height. When the folder holds fewer frames, the sequence is played forward and
/// backward (no cut) up to \a frames; the description says so.
/// \return the clip; Errc::Io when the folder has no frame-000000.depth.png or .color.jpg,
/// Errc::InvalidArgument for corrupt images, a depth frame without any valid sample, an odd or
/// non-positive size or \a frames < 2.
Result<Clip> loadKitchenClip(const std::string &sceneDir, int frames, int width, int height);

/// \brief A synthetic clip: a tilted plane with two moving spheres in nearness and a moving color
/// texture with edges; deterministic. \pre width, height even and ≥ 16; frames ≥ 2.
Clip makeSyntheticClip(int width, int height, int frames, double fps = 30.0);

/// \brief Where the receiver gets its HAL objects (the executable's backend choice).
struct ReceiverBackends {
    /// Makes a Closed media source for one file.
    std::function<Result<std::unique_ptr<hal::MediaSource>>()> makeSource;
    /// Makes the decoder of one stream (e.g. ffmpeg with `threads=1`).
    receiver::DecoderFactory makeDecoder;
    std::string description; ///< For the report, e.g. "ffmpeg, threads=1".
};

/// \brief Benchmark settings.
struct MediaBenchOptions {
    std::vector<std::string> presets{"ultrafast", "veryfast", "medium"}; ///< x264 presets timed.
    int colorCrf = 23;     ///< Color CRF of the throughput files (`depthtouch encode` default).
    int depthCrf = 18;     ///< Depth CRF of the throughput files (`depthtouch encode` default).
    int encodeThreads = 1; ///< x264 threads per stream (1: one core; 0: automatic).
    int decodeRuns = 3;    ///< Decode + pairing runs per file (median run reported).
    /// Depth CRFs of the rate/accuracy sweep; a negative value stands for lossless (x264 qp 0, as
    /// `--depth-lossless`), which is also the reference and is always measured first.
    std::vector<int> depthCrfs{10, 18, 24, 30, 36, 42};
    std::string ratePreset = "medium"; ///< x264 preset of the rate/accuracy sweep.
    double hapticRate = 1000.0;        ///< Replay updates per second.
    std::string workDir;               ///< Folder for the encoded files (must exist).
    bool keepFiles = false;            ///< Keep the encoded files in workDir.
};

/// \brief Encode and decode figures of one file (one size, one preset).
struct ThroughputRow {
    int width = 0;
    int height = 0;
    std::string preset;
    std::size_t frames = 0;
    double colorKbps = 0.0;    ///< Color bitrate at the clip's frame rate, kbit/s.
    double depthKbps = 0.0;    ///< Depth bitrate, kbit/s.
    double encodeFps = 0.0; ///< Pairs per wall-clock second, both encoders + muxer, flush included.
    double encodeCpuFps = 0.0; ///< Pairs per second of process CPU time (one core's worth).
    double encodeSeconds = 0.0; ///< Wall-clock seconds.
    double decodeFps = 0.0;    ///< Paired frames per wall-clock second, median run.
    double decodeCpuFps = 0.0; ///< Paired frames per second of process CPU time, median run.
    double decodeMedianMs = 0.0; ///< Median wall-clock time per paired frame over all runs, ms.
    double decodeP99Ms = 0.0;    ///< 99th percentile of the same, ms.
    double decodeRealtime = 0.0; ///< decodeFps / clip fps.
    double decodeCpuRealtime = 0.0;   ///< decodeCpuFps / clip fps.
    std::vector<double> decodeRunFps; ///< Each run, wall clock.
    std::uint64_t depthDuplicated = 0; ///< Receiver pairing counters of the last run (0 expected).
    std::uint64_t depthMissing = 0;
};

/// \brief One depth setting of the rate/accuracy sweep. Force figures pool every stroke of
/// strokeLanes(), each replayed on the decoded depth and on the lossless depth.
struct RateRow {
    bool lossless = false;
    int crf = 0;              ///< x264 CRF (unused when lossless).
    double depthKbps = 0.0;   ///< Depth bitrate, kbit/s.
    double psnrDb = 0.0;      ///< Decoded vs lossless nearness (8-bit), dB; +inf when identical.
    /// The renderer as `depthtouch touch` runs it (modified proxy graph, fixes a–c on):
    double forceRmsN = 0.0;   ///< RMS of |F_decoded − F_lossless| over the updates, N.
    double forceMaxN = 0.0;   ///< Largest |F_decoded − F_lossless|, N.
    long releases = 0;        ///< Force-jump safety trips (paper IV.C) on the decoded depth.
    long popThroughs = 0;     ///< Updates ending with the proxy below the decoded surface.
    /// The same with force-jump safety off (`touch --no-safety`): the proxy is never released, so
    /// the difference is the surface's alone.
    double forceRmsNoSafetyN = 0.0;
    double forceMaxNoSafetyN = 0.0;
    /// Presses (makePress(), renderer as `touch` runs it): the HIP stays at one (x, y) while the
    /// video plays, so the difference follows the depth error under it without sliding effects.
    double pressRmsN = 0.0;
    double pressMaxN = 0.0;
    double forceRefRmsN = 0.0; ///< RMS of |F_lossless| over the strokes (scale of the errors), N.
    std::size_t updates = 0;   ///< Haptic updates replayed per renderer setting (all strokes).
};

/// \brief Results of the whole benchmark.
struct MediaBenchReport {
    std::string content;        ///< Clip descriptions, one per size.
    std::string backends;       ///< ReceiverBackends::description.
    double fps = 30.0;          ///< Clip frame rate (real time).
    std::vector<ThroughputRow> throughput;
    int rateWidth = 0;          ///< Size of the rate/accuracy clip.
    int rateHeight = 0;
    std::vector<RateRow> rate;  ///< Lossless first.
    bool losslessExact = false; ///< Lossless depth decoded bit-exact to the encoder's input.
    std::string stroke;         ///< The strokes replayed (RateAccuracy::stroke).
    double loadBefore = -1.0;   ///< 1-minute load average before and after the run (-1: unknown).
    double loadAfter = -1.0;
    std::vector<CodecRow> codecs; ///< The depth codec comparison (depth_codec_bench.h).
    int codecThreads = 1;         ///< Decoder threads of CodecRow::decodeFpsAll.
};

/// \brief Encodes \a clip once per preset and times decode + pairing of each file.
/// \return one row per preset; errors of the encoder (InvalidArgument for a bad preset,
/// NotSupported without libx264), of the receiver, or Errc::InvalidArgument "paired frame count
/// differs" when the receiver did not pair every frame.
Result<std::vector<ThroughputRow>> measureThroughput(const Clip &clip,
                                                     const ReceiverBackends &backends,
                                                     const MediaBenchOptions &options);

/// \brief Result of the rate/accuracy sweep.
struct RateAccuracy {
    std::vector<RateRow> rows;  ///< Lossless first, then one per MediaBenchOptions::depthCrfs.
    bool losslessExact = false; ///< The lossless depth decoded equal to the clip's nearness.
    std::string stroke;         ///< The strokes replayed, in words.
};

/// \brief The rate/accuracy sweep on \a clip (see the file comment and RateRow).
/// \return the sweep; errors of the encoder, the receiver, or the replay.
Result<RateAccuracy> measureRateAccuracy(const Clip &clip, const ReceiverBackends &backends,
                                         const MediaBenchOptions &options);

/// \brief PSNR of 8-bit samples \a test against \a reference: 10·log10(255² / MSE), MSE over every
/// sample. \return +infinity when identical; NaN when the sizes differ or both are empty.
double psnr8(const std::vector<std::uint8_t> &reference, const std::vector<std::uint8_t> &test);

/// \brief Force difference of two force logs of the same stroke (same update times).
struct ForceError {
    double rmsN = 0.0; ///< RMS of |F_a − F_b|, N.
    double maxN = 0.0; ///< Largest |F_a − F_b|, N.
};
/// \return the difference over the common rows; zeros for empty logs.
ForceError compareForces(const std::vector<haptics::ForceLogRow> &a,
                         const std::vector<haptics::ForceLogRow> &b);

/// \brief The scripted stroke: the HIP starts 8 mm above the surface at the left end of the lane
/// y = \a laneY, sinks to 2 mm below it in the first quarter second (or quarter of the clip),
/// then strokes to the right across 80 % of the box width with a ±1 mm sway in y, 2 mm below the
/// surface of \a frames (interpolated in time, paper Eq. 1), one row every \a rowPeriod seconds
/// until the last frame's PTS.
/// \param frames the reference depth frames (PTS in s, increasing). \pre at least 2 frames.
/// \param laneY the lane's y in the scene-box frame, m. \param rowPeriod s, > 0.
std::vector<haptics::TrajectorySample> makeStroke(const std::vector<scene::DepthFrameView> &frames,
                                                  const scene::SceneBox &box, double laneY,
                                                  double rowPeriod = 0.001);

/// \brief A press: the HIP at (\a x, \a y) (m) approaches as in makeStroke() and then stays 2 mm
/// below the surface of \a frames while they play, one row every \a rowPeriod seconds.
std::vector<haptics::TrajectorySample> makePress(const std::vector<scene::DepthFrameView> &frames,
                                                 const scene::SceneBox &box, double x, double y,
                                                 double rowPeriod = 0.001);

/// \return the stroke lanes (y, m) for \a width × \a height frames in \a box: the middle row,
/// then alternately above and below it in steps of a tenth of the half height, up to 0.8 of it
/// (17 lanes).
std::vector<double> strokeLanes(int width, int height, const scene::SceneBox &box);

/// \brief What measureSizes() measures.
struct MediaSizesPlan {
    std::vector<std::pair<int, int>> sizes; ///< Frame sizes (width, height), pixels; the first
                                            ///< also gets the rate/accuracy sweep.
    int frames = 60;                        ///< Frames per clip at 30 fps.
    bool synthetic = false;                 ///< A synthetic clip instead of the 7-Scenes frames.
    std::string scene;                      ///< The 7-Scenes kitchen folder (unless synthetic).
    /// Sizes of the depth codec comparison (measureCodecs()); the first gets every CRF of
    /// codecCrfs, the others the one nearest 18. Empty: no comparison.
    std::vector<std::pair<int, int>> codecSizes;
    std::vector<int> codecCrfs{18};
    ReceiverBackends allThreads; ///< Decoders with `codecThreads` threads each.
    int codecThreads = 1;
};

/// \brief Why measureSizes() stopped: the one-line message, and whether the input was bad (frames
/// that cannot be read, an option the encoder refuses) rather than the run failing.
struct MediaBenchError {
    bool badInput = false;
    std::string message;
};

/// \brief For each size of \a plan: loads its clip and measures its throughput
/// (measureThroughput()) and, on the first size, rate against accuracy (measureRateAccuracy()),
/// then for each of its codec sizes the depth codecs (measureCodecs()), into \a report (its
/// content, fps, throughput, rate and codec rows); progress lines on stderr. \return
/// nothing, or why not.
std::optional<MediaBenchError> measureSizes(const MediaSizesPlan &plan,
                                            const ReceiverBackends &backends,
                                            const MediaBenchOptions &mo, MediaBenchReport &report);

/// \brief A private scratch folder for the encoded files (`dt-bench-media-PID` in the system's
/// temporary folder), removed with what it holds on destruction unless kept.
class ScratchFolder {
public:
    /// \brief Creates the folder. \return it, or null with \a error set to the one error line.
    static std::unique_ptr<ScratchFolder> make(bool keep, std::string &error);
    ~ScratchFolder();
    ScratchFolder(const ScratchFolder &) = delete;
    ScratchFolder &operator=(const ScratchFolder &) = delete;
    [[nodiscard]] const std::filesystem::path &path() const noexcept { return dir_; }

private:
    ScratchFolder(std::filesystem::path dir, bool keep) : dir_(std::move(dir)), keep_(keep) {}
    std::filesystem::path dir_;
    bool keep_;
};

/// \brief Prints \a report (printReport()), writes its files into \a out (writeReport()) and says
/// what was written (and, with \a keptIn not empty, where the encoded files were kept) on stdout.
/// \return false with \a error set when a file cannot be written.
bool finishReport(const MediaBenchReport &report, const std::string &out, const std::string &keptIn,
                  std::string &error);

/// \brief Prints the tables and the goals (720×486 decode + pairing ≥ 10× real time, 1920×1080 ≥
/// 2×) to stdout.
void printReport(const MediaBenchReport &report);

/// \brief The goal for a size: 10 for 720×486, 2 for 1920×1080, 0 for other sizes (no goal).
double realtimeGoal(int width, int height) noexcept;

/// \brief Writes media_throughput.csv, rate_accuracy.csv and (with gnuplot)
/// rate_vs_accuracy.png into \a dir (created when missing).
/// \param[out] note a remark for the user (gnuplot missing or failed), empty otherwise.
/// \return false with \a error set when the folder or a CSV cannot be written.
bool writeReport(const MediaBenchReport &report, const std::string &dir, std::string &error,
                 std::string &note);

} // namespace depthtouch::media::bench
