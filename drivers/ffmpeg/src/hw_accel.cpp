/// \file
/// \brief Hardware decoding devices and frames (see hw_accel.h).

#include "hw_accel.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include <dirent.h>
#include <link.h>

extern "C" {
#include <libavutil/hwcontext.h>
}

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers::ffmpeg {

namespace {

struct Device {
    HwAccelMode mode;
    AVHWDeviceType type;
    const char *name;
};

/// Auto's order: the set-top and desktop API first.
constexpr Device kDevices[] = {
    {HwAccelMode::Vaapi, AV_HWDEVICE_TYPE_VAAPI, "vaapi"},
    {HwAccelMode::Cuda, AV_HWDEVICE_TYPE_CUDA, "cuda"},
    {HwAccelMode::Vdpau, AV_HWDEVICE_TYPE_VDPAU, "vdpau"},
};

/// The folder libvdpau loads its drivers from: $VDPAU_DRIVER_PATH, else the `vdpau` folder beside
/// the libvdpau.so.1 this process loaded (libavutil links it); empty when neither is known.
std::string vdpauModuleDir()
{
    if (const char *path = std::getenv("VDPAU_DRIVER_PATH"); path != nullptr && *path != '\0')
        return path;
    std::string dir;
    dl_iterate_phdr(
        [](dl_phdr_info *info, std::size_t, void *out) {
            const char *name = info->dlpi_name;
            const char *slash = name != nullptr ? std::strrchr(name, '/') : nullptr;
            if (slash == nullptr || std::strncmp(slash + 1, "libvdpau.so", 11) != 0)
                return 0;
            *static_cast<std::string *>(out) = std::string(name, slash) + "/vdpau";
            return 1;
        },
        &dir);
    return dir;
}

/// \return whether libvdpau has a driver to load (a libvdpau_NAME.so other than its trace
/// wrapper in its module folder), or this cannot be told. Without one, creating a VDPAU device
/// makes libvdpau print "Failed to open VDPAU backend ..." on stderr itself, under --quiet too,
/// and fail: auto then does not try it (a desktop with libvdpau and no NVIDIA or Mesa VDPAU
/// driver).
bool vdpauDriverInstalled()
{
    const std::string dir = vdpauModuleDir();
    if (dir.empty())
        return true;
    DIR *d = ::opendir(dir.c_str());
    if (d == nullptr)
        return false;
    bool found = false;
    while (const dirent *e = ::readdir(d)) {
        const std::string name = e->d_name;
        if (name.rfind("libvdpau_", 0) == 0 && name.find(".so") != std::string::npos &&
            name.rfind("libvdpau_trace", 0) != 0)
            found = true;
    }
    ::closedir(d);
    return found;
}

/// \return the hwaccel pixel format \a codec decodes to on \a type through a device context, or
/// NONE when it has no such hwaccel.
AVPixelFormat hwFormatOf(const AVCodec &codec, AVHWDeviceType type) noexcept
{
    for (int i = 0;; ++i) {
        const AVCodecHWConfig *hw = avcodec_get_hw_config(&codec, i);
        if (hw == nullptr)
            return AV_PIX_FMT_NONE;
        if ((hw->methods & AV_CODEC_HW_CONFIG_METHOD_HW_DEVICE_CTX) != 0 && hw->device_type == type)
            return hw->pix_fmt;
    }
}

/// AVCodecContext::get_format: the device's format while it is offered (it is not for a stream
/// the device cannot decode, e.g. 4:0:0), else libavcodec's own software choice.
AVPixelFormat pickHwFormat(AVCodecContext *ctx, const AVPixelFormat *formats)
{
    const auto wanted = static_cast<AVPixelFormat>(reinterpret_cast<std::intptr_t>(ctx->opaque));
    for (const AVPixelFormat *f = formats; *f != AV_PIX_FMT_NONE; ++f)
        if (*f == wanted)
            return *f;
    return avcodec_default_get_format(ctx, formats);
}

} // namespace

Result<HwAccelMode> parseHwAccel(std::string_view name) noexcept
{
    if (name == "none")
        return HwAccelMode::None;
    if (name == "auto")
        return HwAccelMode::Auto;
    for (const Device &d : kDevices)
        if (name == d.name)
            return d.mode;
    return unexpected(Errc::InvalidArgument,
                      "ffmpeg decoder option hwaccel must be none, auto, vaapi, cuda or vdpau");
}

Result<HwAccel> attachHwAccel(AVCodecContext &ctx, const AVCodec &codec, HwAccelMode mode)
{
    HwAccel out;
    if (mode == HwAccelMode::None)
        return out;
    for (const Device &d : kDevices) {
        if (mode != HwAccelMode::Auto && mode != d.mode)
            continue;
        const AVPixelFormat fmt = hwFormatOf(codec, d.type);
        // Looked up once: the drivers installed do not change while the player runs.
        static const bool vdpauUsable = vdpauDriverInstalled();
        if (mode == HwAccelMode::Auto && d.type == AV_HWDEVICE_TYPE_VDPAU && !vdpauUsable)
            continue;
        AVBufferRef *device = nullptr;
        if (fmt == AV_PIX_FMT_NONE ||
            av_hwdevice_ctx_create(&device, d.type, nullptr, nullptr, 0) < 0)
            continue;
        ctx.hw_device_ctx = device; // owned by ctx from now on
        ctx.opaque = reinterpret_cast<void *>(static_cast<std::intptr_t>(fmt));
        ctx.get_format = pickHwFormat;
        out.pixFmt = fmt;
        out.name = d.name;
        DT_LOG(Ffmpeg, Info, "%s decodes on %s", codec.name, d.name);
        return out;
    }
    if (mode == HwAccelMode::Auto) {
        DT_LOG(Ffmpeg, Info, "hwaccel auto: no hardware device decodes %s here: software",
               codec.name);
        return out;
    }
    for (const Device &d : kDevices)
        if (d.mode == mode)
            DT_LOG(Ffmpeg, Warning, "hwaccel %s: no such device here, or it cannot decode %s",
                   d.name, codec.name);
    return unexpected(Errc::NoDevice, "hwaccel: the device asked for does not open or cannot "
                                      "decode this codec");
}

const AVFrame *inSystemMemory(const AVFrame &frame, const HwAccel &hw, AVFrame *scratch) noexcept
{
    if (!hw.active() || frame.format != hw.pixFmt)
        return &frame;
    if (scratch == nullptr)
        return nullptr;
    av_frame_unref(scratch);
    if (av_hwframe_transfer_data(scratch, &frame, 0) < 0 ||
        av_frame_copy_props(scratch, &frame) < 0)
        return nullptr;
    return scratch;
}

} // namespace depthtouch::drivers::ffmpeg
