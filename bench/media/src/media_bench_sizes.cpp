/// \file
/// \brief `depthtouch bench media` over its frame sizes, its scratch folder and its last output:
/// see measureSizes(), ScratchFolder and finishReport() in media_bench.h.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <system_error>
#include <string>
#include <utility>

#include "depthtouch/media/media_bench.h"
#include "media_bench_steps.h"

namespace depthtouch::media::bench {

namespace {

/// The clip of one size: synthetic, or the 7-Scenes frames.
std::optional<MediaBenchError> loadClip(const MediaSizesPlan &plan, int w, int h, Clip &clip)
{
    if (plan.synthetic) {
        clip = makeSyntheticClip(w, h, plan.frames);
    } else {
        auto loaded = loadKitchenClip(plan.scene, plan.frames, w, h);
        if (!loaded)
            return MediaBenchError{loaded.error().code == Errc::Io,
                                   std::string("cannot read the 7-Scenes frames: ") +
                                       loaded.error().what};
        clip = std::move(*loaded);
    }
    return std::nullopt;
}

/// Appends the rows of the measurement \a what at size \a w × \a h to \a into. \return its error,
/// "WHAT at WxH: REASON" (a usage error when an argument was invalid), when it failed.
template <class Row>
std::optional<MediaBenchError> appendRows(const Result<std::vector<Row>> &rows, const char *what,
                                          int w, int h, std::vector<Row> &into)
{
    if (!rows)
        return MediaBenchError{rows.error().code == Errc::InvalidArgument,
                               std::string(what) + " at " + sizeText(w, h) + ": " +
                                   rows.error().what};
    into.insert(into.end(), rows->begin(), rows->end());
    return std::nullopt;
}

/// One measureSizes() run: what every step measures with, and the report the steps fill.
struct SizesRun {
    const MediaSizesPlan &plan;
    const ReceiverBackends &backends;
    const MediaBenchOptions &mo;
    MediaBenchReport &report;

    /// Rate against accuracy on one clip of size \a w × \a h.
    std::optional<MediaBenchError> measureRate(const Clip &clip, int w, int h);
    /// Loads the clip of size `k` and measures its throughput, and on the first size also rate
    /// against accuracy.
    std::optional<MediaBenchError> measureSize(std::size_t k);
    /// Loads the clip of codec size `k` and compares the depth codecs on it.
    std::optional<MediaBenchError> measureCodecSize(std::size_t k);
};

std::optional<MediaBenchError> SizesRun::measureRate(const Clip &clip, int w, int h)
{
    std::fprintf(stderr, "bench media: %dx%d depth rate vs accuracy (%zu settings) ...\n", w, h,
                 mo.depthCrfs.size() + 1);
    auto rate = measureRateAccuracy(clip, backends, mo);
    if (!rate)
        return MediaBenchError{rate.error().code == Errc::InvalidArgument,
                               std::string("rate vs accuracy: ") + rate.error().what};
    report.rate = std::move(rate->rows);
    report.rateWidth = w;
    report.rateHeight = h;
    report.losslessExact = rate->losslessExact;
    report.stroke = rate->stroke;
    return std::nullopt;
}

std::optional<MediaBenchError> SizesRun::measureSize(std::size_t k)
{
    const auto [w, h] = plan.sizes[k];
    std::fprintf(stderr, "bench media: loading %dx%d ...\n", w, h);
    Clip clip;
    if (auto e = loadClip(plan, w, h, clip))
        return e;
    report.content += (report.content.empty() ? "" : "; ") + clip.description;
    report.fps = clip.fps;
    std::fprintf(stderr, "bench media: %dx%d encode per preset, decode + pairing x%d ...\n", w, h,
                 mo.decodeRuns);
    if (auto e = appendRows(measureThroughput(clip, backends, mo), "throughput", w, h,
                            report.throughput))
        return e;
    // Rate against accuracy on the first size (720×486 by default: the paper's frame size).
    if (k == 0)
        return measureRate(clip, w, h);
    return std::nullopt;
}

std::optional<MediaBenchError> SizesRun::measureCodecSize(std::size_t k)
{
    const auto [w, h] = plan.codecSizes[k];
    CodecPlan cp;
    cp.allThreads = plan.codecThreads;
    cp.preset = mo.ratePreset;
    cp.crfs = plan.codecCrfs;
    if (k > 0 && !cp.crfs.empty()) {
        int nearest = cp.crfs.front();
        for (const int c : cp.crfs)
            if (std::abs(c - 18) < std::abs(nearest - 18))
                nearest = c;
        cp.crfs = {nearest};
    }
    std::fprintf(stderr, "bench media: %dx%d depth codecs (%zu CRFs each, FFV1) ...\n", w, h,
                 cp.crfs.size());
    Clip clip;
    if (auto e = loadClip(plan, w, h, clip))
        return e;
    return appendRows(measureCodecs(clip, backends, plan.allThreads, cp, mo), "depth codecs", w, h,
                      report.codecs);
}

} // namespace

std::optional<MediaBenchError> measureSizes(const MediaSizesPlan &plan,
                                            const ReceiverBackends &backends,
                                            const MediaBenchOptions &mo, MediaBenchReport &report)
{
    SizesRun run{plan, backends, mo, report};
    for (std::size_t k = 0; k < plan.sizes.size(); ++k)
        if (auto e = run.measureSize(k))
            return e;
    report.codecThreads = plan.codecThreads;
    for (std::size_t k = 0; k < plan.codecSizes.size(); ++k)
        if (auto e = run.measureCodecSize(k))
            return e;
    return std::nullopt;
}

std::unique_ptr<ScratchFolder> ScratchFolder::make(bool keep, std::string &error)
{
    std::error_code ec;
    std::filesystem::path dir =
        std::filesystem::temp_directory_path(ec) / ("dt-bench-media-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        error = "cannot create a scratch folder: " + ec.message();
        return nullptr;
    }
    return std::unique_ptr<ScratchFolder>(new ScratchFolder(std::move(dir), keep));
}

ScratchFolder::~ScratchFolder()
{
    std::error_code e;
    if (!keep_)
        std::filesystem::remove_all(dir_, e);
}

bool finishReport(const MediaBenchReport &report, const std::string &out, const std::string &keptIn,
                  std::string &error)
{
    std::printf("\n");
    printReport(report);
    printCodecs(report.codecs, report.codecThreads);
    std::string note;
    if (!writeReport(report, out, error, note))
        return false;
    std::string codecNote;
    if (!writeCodecs(report.codecs, report.codecThreads, out, error, codecNote))
        return false;
    if (!note.empty() || !codecNote.empty())
        std::printf("note: %s\n", note.empty() ? codecNote.c_str() : note.c_str());
    std::printf("wrote "
                "%s/{media_throughput.csv,rate_accuracy.csv,rate_vs_accuracy.png,media_throughput."
                "png,depth_codecs.csv%s}\n",
                out.c_str(), report.codecs.empty() ? "" : ",depth_codecs.png");
    if (!keptIn.empty())
        std::printf("encoded files kept in %s\n", keptIn.c_str());
    return true;
}

} // namespace depthtouch::media::bench
