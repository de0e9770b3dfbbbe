/// \file
/// \brief The depth codec comparison's measurements (see depth_codec_bench.h).

#include "depthtouch/media/depth_codec_bench.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "depthtouch/media/media_bench.h"
#include "depthtouch/platform/percentile.h"
#include "media_bench_steps.h"

namespace depthtouch::media::bench {

namespace {

/// The clip's 16-bit nearness frames back to back (the reference).
std::vector<std::uint8_t> sourceFrames(const Clip &clip)
{
    std::vector<std::uint8_t> out;
    const std::size_t rowBytes = static_cast<std::size_t>(clip.width) * 2u;
    out.reserve(rowBytes * static_cast<std::size_t>(clip.height) * clip.frames());
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const Image &im = clip.fineNearness(i);
        for (int y = 0; y < im.height; ++y)
            out.insert(out.end(), im.row(y), im.row(y) + rowBytes);
    }
    return out;
}

/// The rate sweep's strokes and presses on the source.
std::vector<std::vector<haptics::TrajectorySample>>
pathsOn(const std::vector<scene::DepthFrameView> &views, const Clip &clip,
        const scene::SceneBox &box)
{
    std::vector<std::vector<haptics::TrajectorySample>> paths;
    for (const double lane : strokeLanes(clip.width, clip.height, box)) {
        paths.push_back(makeStroke(views, box, lane));
        for (const double x : {-0.3, -0.15, 0.0, 0.15, 0.3})
            paths.push_back(makePress(views, box, x * box.width, lane));
    }
    return paths;
}

/// Force logs of every path on \a video.
Result<std::vector<std::vector<haptics::ForceLogRow>>>
replayAll(const std::vector<std::uint8_t> &video, scene::SampleFormat format, const Clip &clip,
          const std::vector<std::vector<haptics::TrajectorySample>> &paths,
          const haptics::ReplayOptions &ro)
{
    std::vector<std::vector<haptics::ForceLogRow>> out;
    for (const auto &path : paths) {
        auto log = replayOn(video, clip.width, clip.height, clip.fps, path, ro, format);
        if (!log)
            return unexpected(log.error());
        out.push_back(std::move(*log));
    }
    return out;
}

/// RMS (and largest) of |F_test − F_reference| over every update of every path.
void forceError(const std::vector<std::vector<haptics::ForceLogRow>> &reference,
                const std::vector<std::vector<haptics::ForceLogRow>> &test, CodecRow &row)
{
    double sq = 0.0;
    std::size_t n = 0;
    for (std::size_t k = 0; k < reference.size() && k < test.size(); ++k) {
        const std::size_t rows = std::min(reference[k].size(), test[k].size());
        for (std::size_t i = 0; i < rows; ++i) {
            const double d = glm::length(reference[k][i].out.force - test[k][i].out.force);
            sq += d * d;
            row.forceMaxN = std::max(row.forceMaxN, d);
        }
        n += rows;
    }
    row.forceRmsN = n > 0 ? std::sqrt(sq / static_cast<double>(n)) : 0.0;
}

/// RMS height error (mm in \a box) of decoded \a video against the 16-bit \a source.
double heightErrorMm(const std::vector<std::uint8_t> &source,
                     const std::vector<std::uint8_t> &video, scene::SampleFormat format,
                     const scene::SceneBox &box)
{
    const std::size_t n = source.size() / 2;
    if (n == 0 || video.size() != n * scene::bytesPerSample(format))
        return std::nan("");
    const double vmax = scene::maxSampleValue(format);
    double sq = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint16_t s = 0;
        std::memcpy(&s, source.data() + 2 * i, 2);
        double v = 0.0;
        if (format == scene::SampleFormat::Gray8) {
            v = video[i];
        } else {
            std::uint16_t w = 0;
            std::memcpy(&w, video.data() + 2 * i, 2);
            v = w;
        }
        const double d = v / vmax - s / 65535.0;
        sq += d * d;
    }
    return 1000.0 * box.depth * std::sqrt(sq / static_cast<double>(n));
}

/// Median decode + pairing rate (frames/s, wall clock) of \a runs depth-only passes over \a path.
Result<double> decodeRate(const std::string &path, const ReceiverBackends &backends,
                          const Clip &clip, int runs)
{
    std::vector<double> fps;
    for (int run = 0; run < runs; ++run) {
        auto dec = decodeFile(path, backends, true, false, clip.width, clip.height);
        if (!dec)
            return unexpected(dec.error());
        if (dec->frameSeconds.size() != clip.frames() || !(dec->seconds > 0.0))
            return unexpected(Errc::InvalidArgument,
                              "decoded depth frame count differs from the frames encoded");
        fps.push_back(static_cast<double>(clip.frames()) / dec->seconds);
    }
    return platform::percentile(fps, 0.5);
}

struct Setting {
    const char *name;
    VideoCodec id;
    bool lossless;
};

constexpr Setting kSettings[] = {
    {"h264-8", VideoCodec::H264Gray, false},
    {"h264-10", VideoCodec::H264Gray10, false},
    {"hevc-10", VideoCodec::HevcMain10, false},
    {"ffv1-16", VideoCodec::Ffv1Gray16, true},
};

} // namespace

Result<std::vector<CodecRow>> measureCodecs(const Clip &clip, const ReceiverBackends &oneThread,
                                            const ReceiverBackends &allThreads,
                                            const CodecPlan &plan, const MediaBenchOptions &options)
{
    if (clip.frames() < 2 || clip.fineNearnesses.empty())
        return unexpected(Errc::InvalidArgument, "clip has fewer than 2 frames or no 16-bit depth");
    const scene::SceneBox box{};
    const haptics::ReplayOptions ro = paperReplay(options, box);
    const std::vector<std::uint8_t> source = sourceFrames(clip);
    const auto views =
        viewsOf(source, clip.width, clip.height, clip.fps, scene::SampleFormat::Gray16);
    const auto paths = pathsOn(views, clip, box);
    auto reference = replayAll(source, scene::SampleFormat::Gray16, clip, paths, ro);
    if (!reference)
        return unexpected(reference.error());

    std::vector<CodecRow> rows;
    for (const Setting &s : kSettings) {
        for (std::size_t k = 0; k < (s.lossless ? 1u : plan.crfs.size()); ++k) {
            CodecRow row;
            row.codec = s.name;
            row.id = s.id;
            row.width = clip.width;
            row.height = clip.height;
            row.lossless = s.lossless;
            row.crf = s.lossless ? 0 : plan.crfs[k];
            const std::string path =
                tempName(options, "codec-" + sizeText(clip.width, clip.height) + "-" + s.name +
                                      "-" + std::to_string(row.crf) + ".mkv");
            auto enc = encodeDepthOnly(clip, path, plan.preset, s.id, row.crf, false,
                                       options.encodeThreads);
            if (!enc)
                return unexpected(enc.error());
            row.depthKbps = kbps(enc->depthBytes, clip.frames(), clip.fps);
            auto one = decodeRate(path, oneThread, clip, options.decodeRuns);
            auto all = one ? decodeRate(path, allThreads, clip, options.decodeRuns) : one;
            auto dec = all ? decodeFile(path, oneThread, true, true, clip.width, clip.height)
                           : Result<Decoded>(unexpected(all.error()));
            removeUnlessKept(options, path);
            if (!dec)
                return unexpected(dec.error());
            row.decodeFps1 = *one;
            row.decodeFpsAll = *all;
            row.depthErrorMm = heightErrorMm(source, dec->depth, dec->depthFormat, box);
            auto forces = replayAll(dec->depth, dec->depthFormat, clip, paths, ro);
            if (!forces)
                return unexpected(forces.error());
            forceError(*reference, *forces, row);
            rows.push_back(row);
        }
    }
    return rows;
}

} // namespace depthtouch::media::bench
