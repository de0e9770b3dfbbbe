#include "depthtouch/render/snapshot.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include "depthtouch/media/image.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render/render_target.h"

namespace depthtouch::render {

Result<void> writeSnapshot(const RenderTarget &target, const std::string &path)
{
    std::vector<std::uint8_t> rgb;
    if (auto r = target.readRgb(rgb); !r)
        return r;
    media::Image img = media::Image::make(target.width(), target.height(), media::PixelFormat::Rgb24);
    for (int y = 0; y < img.height; ++y)
        std::memcpy(img.row(y), rgb.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) * 3,
                    static_cast<std::size_t>(img.width) * 3);
    return media::writePng(path, img);
}

Snapshotter::Snapshotter(std::string dir, std::uint64_t everyN, std::string prefix)
    : dir_(std::move(dir)), prefix_(std::move(prefix)), everyN_(everyN)
{
}

Result<std::optional<std::string>> Snapshotter::onFrame(const RenderTarget &target)
{
    const std::uint64_t frame = frames_++;
    const bool periodic = everyN_ > 0 && frame % everyN_ == 0;
    const bool requested = requested_.exchange(false, std::memory_order_relaxed);
    if (!periodic && !requested)
        return std::optional<std::string>{};
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
        return unexpected(Errc::Io, "Failed to create the snapshot directory");
    char name[64];
    std::snprintf(name, sizeof name, "-%06llu.png", static_cast<unsigned long long>(frame));
    std::string path = dir_ + "/" + prefix_ + name;
    if (auto r = writeSnapshot(target, path); !r)
        return unexpected(r.error());
    ++written_;
    return std::optional<std::string>{std::move(path)};
}

} // namespace depthtouch::render
