/// \file
/// \brief The benchmark's RGB-D frames: the 7-Scenes kitchen converted as the sender does it,
/// and the synthetic head rendered at the size asked (render_bench.h).

#include <cstdio>
#include <filesystem>
#include <optional>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render/render_bench.h"
#include "depthtouch/synthetic/synthetic_scene.h"

namespace depthtouch::render::bench {

namespace {

std::string framePath(const std::string &dir, int n, const char *kind)
{
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06d.%s", n, kind);
    return dir + name;
}

/// RGB → yuv420p, BT.601 limited range (what an H.264 sender produces), chroma averaged over 2×2.
void rgbToYuv420(const std::uint8_t *rgb, std::size_t stride, int w, int h, RgbdFrame &out)
{
    const int cw = (w + 1) / 2;
    const int ch = (h + 1) / 2;
    out.colorWidth = w;
    out.colorHeight = h;
    out.y.assign(static_cast<std::size_t>(w * h), 0);
    out.u.assign(static_cast<std::size_t>(cw * ch), 0);
    out.v.assign(static_cast<std::size_t>(cw * ch), 0);
    std::vector<double> su(out.u.size(), 0.0);
    std::vector<double> sv(out.v.size(), 0.0);
    std::vector<int> count(out.u.size(), 0);
    for (int y = 0; y < h; ++y) {
        const std::uint8_t *row = rgb + static_cast<std::size_t>(y) * stride;
        for (int x = 0; x < w; ++x) {
            const double r = row[3 * x] / 255.0;
            const double g = row[3 * x + 1] / 255.0;
            const double b = row[3 * x + 2] / 255.0;
            const double luma = 0.299 * r + 0.587 * g + 0.114 * b;
            out.y[static_cast<std::size_t>(y * w + x)] =
                static_cast<std::uint8_t>(std::lround(16.0 + 219.0 * luma));
            const std::size_t ci = static_cast<std::size_t>((y / 2) * cw + x / 2);
            su[ci] += (b - luma) / 1.772;
            sv[ci] += (r - luma) / 1.402;
            ++count[ci];
        }
    }
    for (std::size_t i = 0; i < su.size(); ++i) {
        out.u[i] = static_cast<std::uint8_t>(std::lround(128.0 + 224.0 * su[i] / count[i]));
        out.v[i] = static_cast<std::uint8_t>(std::lround(128.0 + 224.0 * sv[i] / count[i]));
    }
}

} // namespace

Result<std::vector<RgbdFrame>> loadKitchenFrames(const std::string &sceneDir, int maxFrames,
                                                 int width, int height)
{
    if (width < 2 || height < 2 || maxFrames < 1)
        return unexpected(Errc::InvalidArgument, "frame size must be at least 2x2 and count >= 1");
    if (!std::filesystem::exists(framePath(sceneDir, 0, "depth.png")))
        return unexpected(Errc::Io, "no frame-000000.depth.png in the scene folder");
    std::vector<RgbdFrame> frames;
    std::optional<depth::DepthRange> range;
    for (int n = 0; n < maxFrames; ++n) {
        const std::string dpath = framePath(sceneDir, n, "depth.png");
        if (!std::filesystem::exists(dpath))
            break;
        auto dimg = media::readImage(dpath, media::PixelFormat::Gray16);
        if (!dimg)
            return unexpected(dimg.error());
        // The planes of the first frame for the whole sequence.
        auto levels = depth::metricToLevels8(media::toPlane16(*dimg), range, width, height);
        if (!levels)
            return unexpected(levels.error());
        const depth::Plane<std::uint16_t> &q = *levels;
        RgbdFrame f;
        f.width = width;
        f.height = height;
        f.nearness.resize(q.samples.size());
        for (std::size_t i = 0; i < q.samples.size(); ++i)
            f.nearness[i] = static_cast<std::uint8_t>(q.samples[i]);
        auto cimg =
            media::readImage(framePath(sceneDir, n, "color.jpg"), media::PixelFormat::Rgb24);
        if (!cimg)
            return unexpected(cimg.error());
        rgbToYuv420(cimg->row(0), cimg->stride, cimg->width, cimg->height, f);
        frames.push_back(std::move(f));
    }
    return frames;
}

Result<std::vector<RgbdFrame>> loadHeadFrames(int maxFrames, int width, int height)
{
    if (width < 16 || height < 16 || width > 4096 || height > 4096 || maxFrames < 1)
        return unexpected(Errc::InvalidArgument, "head frames must be 16..4096 a side, count >= 1");
    auto scene = synthetic::SyntheticScene::create("head", width, height, 30.0);
    if (!scene)
        return unexpected(scene.error());
    std::vector<RgbdFrame> frames;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) *
                                  static_cast<std::size_t>(height) * 3);
    for (int n = 0; n < maxFrames; ++n) {
        RgbdFrame f;
        f.width = width;
        f.height = height;
        f.nearness.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
        hal::ImageView color;
        color.width = width;
        color.height = height;
        color.format = hal::PixelFormat::Rgb24;
        color.planes[0] = {rgb.data(), width * 3};
        hal::ImageView near;
        near.width = width;
        near.height = height;
        near.format = hal::PixelFormat::Gray8;
        near.planes[0] = {f.nearness.data(), width};
        // Every third animation frame: a second of motion in the frames kept.
        if (auto r = (*scene)->render(static_cast<std::uint64_t>(n) * 3, color, near); !r)
            return unexpected(r.error());
        rgbToYuv420(rgb.data(), static_cast<std::size_t>(width) * 3, width, height, f);
        frames.push_back(std::move(f));
    }
    return frames;
}

} // namespace depthtouch::render::bench
