#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "media_bench_steps.h"

// The media benchmark's content: the clips (the kitchen scene, or a synthetic one) and the strokes
// replayed on them.

namespace depthtouch::media::bench {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string framePath(const std::string &dir, int n, const char *kind)
{
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06d.%s", n, kind);
    return dir + name;
}

} // namespace

Result<Clip> loadKitchenClip(const std::string &sceneDir, int frames, int width, int height)
{
    if (frames < 2 || width < 2 || height < 2 || width % 2 != 0 || height % 2 != 0)
        return unexpected(Errc::InvalidArgument, "clip needs >= 2 frames and an even size >= 2x2");
    std::error_code ec;
    if (!std::filesystem::exists(framePath(sceneDir, 0, "depth.png"), ec) ||
        !std::filesystem::exists(framePath(sceneDir, 0, "color.jpg"), ec))
        return unexpected(Errc::Io, "no frame-000000.depth.png / .color.jpg in the scene folder");
    int stored = 0;
    while (stored < frames &&
           std::filesystem::exists(framePath(sceneDir, stored, "depth.png"), ec) &&
           std::filesystem::exists(framePath(sceneDir, stored, "color.jpg"), ec))
        ++stored;

    Clip clip;
    clip.width = width;
    clip.height = height;
    clip.fps = 30.0;
    SourceOptions so;
    so.fps = clip.fps;
    auto colorSource = openFfmpegFrameSource(sceneDir + "/frame-%06d.color.jpg", so);
    if (!colorSource)
        return unexpected(colorSource.error());
    std::optional<depth::DepthRange> range;
    int nativeW = 0;
    int nativeH = 0;
    for (int n = 0; n < stored; ++n) {
        auto color = (*colorSource)->next(PixelFormat::Rgb24, width, height);
        if (!color)
            return unexpected(color.error());
        nativeW = (*colorSource)->info().width;
        nativeH = (*colorSource)->info().height;
        auto raw = readImage(framePath(sceneDir, n, "depth.png"), PixelFormat::Gray16);
        if (!raw)
            return unexpected(raw.error());
        // The first frame's robust range for the whole clip, as the sender does.
        auto q = depth::metricToLevels8(toPlane16(*raw), range, width, height);
        if (!q)
            return unexpected(q.error());
        auto fine = depth::metricToLevels(toPlane16(*raw), range, width, height, 65535.0);
        if (!fine)
            return unexpected(fine.error());
        Image near = Image::make(width, height, PixelFormat::Gray8);
        Image near16 = Image::make(width, height, PixelFormat::Gray16);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                near.row(y)[x] = static_cast<std::uint8_t>(q->at(x, y));
                near16.setSample16(x, y, fine->at(x, y));
            }
        clip.colors.push_back(std::move(color->image));
        clip.nearnesses.push_back(std::move(near));
        clip.fineNearnesses.push_back(std::move(near16));
    }
    // Forward, then backward, then forward…: a longer clip without a cut.
    const std::size_t period = stored > 1 ? 2u * static_cast<std::size_t>(stored) - 2u : 1u;
    for (int i = 0; i < frames; ++i) {
        const std::size_t k = static_cast<std::size_t>(i) % period;
        clip.order.push_back(k < static_cast<std::size_t>(stored) ? k : period - k);
    }
    char text[256];
    std::snprintf(text, sizeof text,
                  "7-Scenes redkitchen: %d frames%s of %dx%d (JPEG color, mm depth -> 8-bit 1/Z "
                  "nearness %.2f..%.2f m, holes filled) stretched to %dx%d",
                  frames, stored < frames ? " (played forward and back)" : "", nativeW, nativeH,
                  range ? range->nearM : 0.0, range ? range->farM : 0.0, width, height);
    clip.description = text;
    return clip;
}

Clip makeSyntheticClip(int width, int height, int frames, double fps)
{
    Clip clip;
    clip.width = width;
    clip.height = height;
    clip.fps = fps;
    const double r1 = 0.22 * std::min(width, height);
    const double r2 = 0.15 * std::min(width, height);
    for (int n = 0; n < frames; ++n) {
        const double t = static_cast<double>(n) / fps;
        const double c1x = width * (0.35 + 0.10 * std::sin(2.0 * kPi * 0.5 * t));
        const double c1y = height * 0.45;
        const double c2x = width * 0.70;
        const double c2y = height * (0.50 + 0.15 * std::cos(2.0 * kPi * 0.4 * t));
        Image near = Image::make(width, height, PixelFormat::Gray8);
        Image near16 = Image::make(width, height, PixelFormat::Gray16);
        Image color = Image::make(width, height, PixelFormat::Rgb24);
        const int shift = n * 2;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                double v = 40.0 + 70.0 * x / (width - 1) + 30.0 * y / (height - 1);
                const double d1 = std::hypot(x - c1x, y - c1y);
                const double d2 = std::hypot(x - c2x, y - c2y);
                if (d1 < r1)
                    v = std::max(v, 110.0 + 100.0 * std::sqrt(1.0 - (d1 * d1) / (r1 * r1)));
                if (d2 < r2)
                    v = std::max(v, 150.0 + 90.0 * std::sqrt(1.0 - (d2 * d2) / (r2 * r2)));
                const auto level = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
                near.row(y)[x] = level;
                near16.setSample16(x, y,
                                   static_cast<std::uint16_t>(
                                       std::clamp(std::lround(v * 65535.0 / 255.0), 0L, 65535L)));
                const bool check = (((x + shift) / 8) + (y / 8)) % 2 == 0;
                std::uint8_t *px = color.row(y) + 3 * x;
                px[0] = static_cast<std::uint8_t>(255 * x / width);
                px[1] = check ? 190 : 70;
                px[2] = level;
            }
        }
        clip.colors.push_back(std::move(color));
        clip.nearnesses.push_back(std::move(near));
        clip.fineNearnesses.push_back(std::move(near16));
        clip.order.push_back(static_cast<std::size_t>(n));
    }
    clip.description = "synthetic: tilted plane with two moving spheres, " +
                       std::to_string(frames) + " frames " + sizeText(width, height);
    return clip;
}

namespace {

/// HIP path from (x0, y) to (x1, y) (m) with a sway of \a sway m in y, following the surface of
/// \a frames 2 mm below it after an approach from 8 mm above (see makeStroke()).
std::vector<haptics::TrajectorySample>
followSurface(const std::vector<scene::DepthFrameView> &frames, const scene::SceneBox &box,
              double x0, double x1, double y, double sway, double rowPeriod)
{
    std::vector<haptics::TrajectorySample> out;
    if (frames.size() < 2 || !(rowPeriod > 0.0))
        return out;
    const double tEnd = frames.back().pts - frames.front().pts;
    const double approach = std::min(0.25, 0.25 * tEnd);
    haptics::HeightField surface(box);
    std::size_t current = frames.size();
    const auto rows = static_cast<std::size_t>(std::ceil(tEnd / rowPeriod - 1e-9));
    for (std::size_t k = 0; k <= rows; ++k) {
        const double t = std::min(static_cast<double>(k) * rowPeriod, tEnd);
        const std::size_t i = frameAt(frames, t);
        if (i != current) {
            current = i;
            (void)surface.setFrames(frames[i], i + 1 < frames.size() ? &frames[i + 1] : nullptr);
        }
        surface.setTime(frames.front().pts + t, true);
        const double u = t <= approach ? 0.0 : (t - approach) / (tEnd - approach);
        haptics::TrajectorySample s;
        s.t = t;
        s.x = x0 + (x1 - x0) * u;
        s.y = y + sway * std::sin(3.0 * kPi * u);
        const double h = surface.contains(s.x, s.y) ? surface.heightAt(s.x, s.y) : 0.0;
        s.z = t < approach ? h + 0.008 - 0.010 * (t / approach) : h - 0.002;
        out.push_back(s);
    }
    return out;
}

} // namespace

std::vector<haptics::TrajectorySample> makeStroke(const std::vector<scene::DepthFrameView> &frames,
                                                  const scene::SceneBox &box, double laneY,
                                                  double rowPeriod)
{
    return followSurface(frames, box, -0.4 * box.width, 0.4 * box.width, laneY, 0.001, rowPeriod);
}

std::vector<haptics::TrajectorySample> makePress(const std::vector<scene::DepthFrameView> &frames,
                                                 const scene::SceneBox &box, double x, double y,
                                                 double rowPeriod)
{
    return followSurface(frames, box, x, x, y, 0.0, rowPeriod);
}

std::vector<double> strokeLanes(int width, int height, const scene::SceneBox &box)
{
    const double halfHeight = width > 1 ? 0.5 * box.width * (height - 1) / (width - 1) : 0.0;
    std::vector<double> lanes{0.0};
    for (int k = 1; k <= 8; ++k) {
        lanes.push_back(0.1 * k * halfHeight);
        lanes.push_back(-0.1 * k * halfHeight);
    }
    return lanes;
}

} // namespace depthtouch::media::bench
