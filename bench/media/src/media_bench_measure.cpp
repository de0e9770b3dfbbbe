#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>

#include "depthtouch/platform/percentile.h"
#include "media_bench_steps.h"

// The media benchmark's measurements: throughput per preset and size, and depth rate against
// haptic accuracy.

namespace depthtouch::media::bench {

using platform::percentile;

Result<std::vector<ThroughputRow>> measureThroughput(const Clip &clip,
                                                     const ReceiverBackends &backends,
                                                     const MediaBenchOptions &options)
{
    if (clip.frames() < 2)
        return unexpected(Errc::InvalidArgument, "clip has fewer than 2 frames");
    if (options.decodeRuns < 1)
        return unexpected(Errc::InvalidArgument, "decode runs must be >= 1");
    std::vector<ThroughputRow> rows;
    for (const std::string &preset : options.presets) {
        const std::string path = tempName(
            options, "throughput-" + sizeText(clip.width, clip.height) + "-" + preset + ".mkv");
        EncodeSetting es;
        es.preset = preset;
        es.colorCrf = options.colorCrf;
        es.depthCrf = options.depthCrf;
        es.threads = options.encodeThreads;
        auto enc = encodeClip(clip, path, es);
        if (!enc)
            return unexpected(enc.error());
        ThroughputRow row;
        row.width = clip.width;
        row.height = clip.height;
        row.preset = preset;
        row.frames = clip.frames();
        row.colorKbps = kbps(enc->colorBytes, clip.frames(), clip.fps);
        row.depthKbps = kbps(enc->depthBytes, clip.frames(), clip.fps);
        row.encodeSeconds = enc->seconds;
        row.encodeFps =
            enc->seconds > 0.0 ? static_cast<double>(clip.frames()) / enc->seconds : 0.0;
        row.encodeCpuFps =
            enc->cpuSeconds > 0.0 ? static_cast<double>(clip.frames()) / enc->cpuSeconds : 0.0;
        std::vector<double> perFrame;
        std::vector<double> cpuFps;
        for (int run = 0; run < options.decodeRuns; ++run) {
            auto dec = decodeFile(path, backends, false, false, clip.width, clip.height);
            if (!dec) {
                removeUnlessKept(options, path);
                return unexpected(dec.error());
            }
            if (dec->frameSeconds.size() != clip.frames()) {
                removeUnlessKept(options, path);
                return unexpected(Errc::InvalidArgument,
                                  "paired frame count differs from the frames encoded");
            }
            row.decodeRunFps.push_back(static_cast<double>(dec->frameSeconds.size()) /
                                       dec->seconds);
            cpuFps.push_back(dec->cpuSeconds > 0.0
                                 ? static_cast<double>(dec->frameSeconds.size()) / dec->cpuSeconds
                                 : 0.0);
            perFrame.insert(perFrame.end(), dec->frameSeconds.begin(), dec->frameSeconds.end());
            row.depthDuplicated = dec->stats.depthDuplicated;
            row.depthMissing = dec->stats.depthMissing;
        }
        removeUnlessKept(options, path);
        row.decodeFps = percentile(row.decodeRunFps, 0.5);
        row.decodeMedianMs = 1000.0 * percentile(perFrame, 0.5);
        row.decodeP99Ms = 1000.0 * percentile(perFrame, 0.99);
        row.decodeRealtime = row.decodeFps / clip.fps;
        row.decodeCpuFps = percentile(cpuFps, 0.5);
        row.decodeCpuRealtime = row.decodeCpuFps / clip.fps;
        rows.push_back(std::move(row));
    }
    return rows;
}

namespace {

/// Force logs of every stroke on one depth video, for both renderer settings.
struct StrokeForces {
    std::vector<std::vector<haptics::ForceLogRow>> safety;   ///< Per stroke, fixes a–c on.
    std::vector<std::vector<haptics::ForceLogRow>> noSafety; ///< Per stroke, fix (c) off.
};

Result<StrokeForces>
replayStrokes(const std::vector<std::uint8_t> &video, const Clip &clip,
              const std::vector<std::vector<haptics::TrajectorySample>> &strokes,
              const haptics::ReplayOptions &withSafety)
{
    haptics::ReplayOptions withoutSafety = withSafety;
    withoutSafety.config.safety = false;
    StrokeForces out;
    for (const auto &stroke : strokes) {
        auto a = replayOn(video, clip.width, clip.height, clip.fps, stroke, withSafety);
        if (!a)
            return unexpected(a.error());
        auto b = replayOn(video, clip.width, clip.height, clip.fps, stroke, withoutSafety);
        if (!b)
            return unexpected(b.error());
        out.safety.push_back(std::move(*a));
        out.noSafety.push_back(std::move(*b));
    }
    return out;
}

/// Pooled force error of logs \a test against \a reference, stroke by stroke.
ForceError pooledError(const std::vector<std::vector<haptics::ForceLogRow>> &reference,
                       const std::vector<std::vector<haptics::ForceLogRow>> &test)
{
    double sq = 0.0;
    std::size_t n = 0;
    ForceError e;
    for (std::size_t k = 0; k < reference.size() && k < test.size(); ++k) {
        const ForceError one = compareForces(reference[k], test[k]);
        const std::size_t rows = std::min(reference[k].size(), test[k].size());
        sq += one.rmsN * one.rmsN * static_cast<double>(rows);
        n += rows;
        e.maxN = std::max(e.maxN, one.maxN);
    }
    e.rmsN = n > 0 ? std::sqrt(sq / static_cast<double>(n)) : 0.0;
    return e;
}

} // namespace

Result<RateAccuracy> measureRateAccuracy(const Clip &clip, const ReceiverBackends &backends,
                                         const MediaBenchOptions &options)
{
    if (clip.frames() < 2)
        return unexpected(Errc::InvalidArgument, "clip has fewer than 2 frames");
    std::vector<std::uint8_t> source;
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const Image &im = clip.nearness(i);
        for (int y = 0; y < im.height; ++y)
            source.insert(source.end(), im.row(y), im.row(y) + im.width);
    }

    const scene::SceneBox box{};
    const haptics::ReplayOptions ro = paperReplay(options, box);

    // Each setting: encode depth only, decode it through the receiver, compare with lossless.
    struct Setting {
        bool lossless;
        int crf;
    };
    std::vector<Setting> settings{{true, 0}};
    for (const int crf : options.depthCrfs) {
        if (crf < 0)
            continue; // lossless is always measured first
        if (crf > 51)
            return unexpected(Errc::InvalidArgument, "depth CRF must be in 0..51");
        settings.push_back({false, crf});
    }
    RateAccuracy result;
    std::vector<std::uint8_t> reference;
    std::vector<std::vector<haptics::TrajectorySample>> strokes;
    std::vector<std::vector<haptics::TrajectorySample>> presses;
    StrokeForces referenceForces;
    StrokeForces referencePresses;
    for (const Setting &s : settings) {
        const std::string path = tempName(
            options, "rate-" + sizeText(clip.width, clip.height) + "-" +
                         (s.lossless ? std::string("lossless") : "crf" + std::to_string(s.crf)) +
                         ".mkv");
        auto enc = encodeDepthOnly(clip, path, options.ratePreset, VideoCodec::H264Gray, s.crf,
                                   s.lossless, options.encodeThreads);
        if (!enc)
            return unexpected(enc.error());
        auto dec = decodeFile(path, backends, true, true, clip.width, clip.height);
        removeUnlessKept(options, path);
        if (!dec)
            return unexpected(dec.error());
        if (dec->depth.size() != source.size())
            return unexpected(Errc::InvalidArgument,
                              "decoded depth frame count differs from the frames encoded");
        RateRow row;
        row.lossless = s.lossless;
        row.crf = s.crf;
        row.depthKbps = kbps(enc->depthBytes, clip.frames(), clip.fps);
        if (s.lossless) {
            result.losslessExact = dec->depth == source;
            reference = std::move(dec->depth);
            const auto views = viewsOf(reference, clip.width, clip.height, clip.fps);
            const std::vector<double> lanes = strokeLanes(clip.width, clip.height, box);
            for (const double lane : lanes) {
                strokes.push_back(makeStroke(views, box, lane));
                for (const double x : {-0.3, -0.15, 0.0, 0.15, 0.3})
                    presses.push_back(makePress(views, box, x * box.width, lane));
            }
            char text[300];
            std::snprintf(text, sizeof text,
                          "%zu strokes (lanes y = %.1f..%+.1f mm), each %.0f mm left to right in "
                          "%.2f s, 2 mm below the lossless surface; %zu presses (5 per lane) 2 mm "
                          "into it; replayed at %.0f Hz",
                          lanes.size(), 1000.0 * *std::min_element(lanes.begin(), lanes.end()),
                          1000.0 * *std::max_element(lanes.begin(), lanes.end()), 800.0 * box.width,
                          strokes.front().back().t, presses.size(), options.hapticRate);
            result.stroke = text;
        }
        const std::vector<std::uint8_t> &video = s.lossless ? reference : dec->depth;
        auto replayed = replayStrokes(video, clip, strokes, ro);
        if (!replayed)
            return unexpected(replayed.error());
        auto pressed = replayStrokes(video, clip, presses, ro);
        if (!pressed)
            return unexpected(pressed.error());
        if (s.lossless) {
            // The lossless row compares them with themselves: zero error.
            referenceForces = *replayed;
            referencePresses = *pressed;
        }
        const StrokeForces *forces = &*replayed;
        const ForceError press = pooledError(referencePresses.safety, pressed->safety);
        row.pressRmsN = press.rmsN;
        row.pressMaxN = press.maxN;
        row.psnrDb = psnr8(reference, video);
        const ForceError withSafety = pooledError(referenceForces.safety, forces->safety);
        const ForceError noSafety = pooledError(referenceForces.noSafety, forces->noSafety);
        row.forceRmsN = withSafety.rmsN;
        row.forceMaxN = withSafety.maxN;
        row.forceRmsNoSafetyN = noSafety.rmsN;
        row.forceMaxNoSafetyN = noSafety.maxN;
        const auto views = viewsOf(video, clip.width, clip.height, clip.fps);
        double sq = 0.0;
        for (std::size_t k = 0; k < forces->safety.size(); ++k) {
            for (const haptics::ForceLogRow &r : forces->safety[k])
                row.releases += r.out.released ? 1 : 0;
            row.popThroughs += countPopThroughs(views, forces->safety[k], box);
            row.updates += forces->safety[k].size();
            for (const haptics::ForceLogRow &r : referenceForces.safety[k])
                sq += glm::dot(r.out.force, r.out.force);
        }
        row.forceRefRmsN = row.updates > 0 ? std::sqrt(sq / static_cast<double>(row.updates)) : 0.0;
        result.rows.push_back(row);
    }
    return result;
}

double psnr8(const std::vector<std::uint8_t> &reference, const std::vector<std::uint8_t> &test)
{
    if (reference.size() != test.size() || reference.empty())
        return std::numeric_limits<double>::quiet_NaN();
    double sq = 0.0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        const double d = static_cast<double>(reference[i]) - static_cast<double>(test[i]);
        sq += d * d;
    }
    if (sq == 0.0)
        return std::numeric_limits<double>::infinity();
    const double mse = sq / static_cast<double>(reference.size());
    return 10.0 * std::log10(255.0 * 255.0 / mse);
}

ForceError compareForces(const std::vector<haptics::ForceLogRow> &a,
                         const std::vector<haptics::ForceLogRow> &b)
{
    ForceError e;
    const std::size_t n = std::min(a.size(), b.size());
    if (n == 0)
        return e;
    double sq = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = glm::length(a[i].out.force - b[i].out.force);
        sq += d * d;
        e.maxN = std::max(e.maxN, d);
    }
    e.rmsN = std::sqrt(sq / static_cast<double>(n));
    return e;
}

} // namespace depthtouch::media::bench
