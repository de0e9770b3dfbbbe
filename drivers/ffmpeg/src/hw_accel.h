#pragma once
/// \file
/// \brief Hardware decoding through libavcodec's hwaccels (ffmpeg's `-hwaccel`): the device a
/// decoder context decodes on (VAAPI on set-top SoCs and Intel/AMD GPUs, CUDA/NVDEC on NVIDIA,
/// VDPAU), chosen when the decoder is configured, with the software decoder as the fallback; and
/// the copy of a hardware frame back to system memory. Private to drivers/ffmpeg.
///
/// Reference: libavcodec's hw_decode example and `fftools/ffmpeg_hw.c` (hw_device_ctx, get_format,
/// av_hwframe_transfer_data). Thread-safety: attach() on the configuring thread; a HwAccel is used
/// by the decoder's thread only.

extern "C" {
#include <libavcodec/avcodec.h>
}

#include <string_view>

#include "depthtouch/platform/result.h"

namespace depthtouch::drivers::ffmpeg {

/// \brief What the ffmpeg decoder option `hwaccel` asks for.
enum class HwAccelMode : unsigned char {
    None, ///< Software (ffmpeg's default).
    /// The first device that opens, in the order VAAPI, CUDA, VDPAU (only where libvdpau has a
    /// driver installed: it prints its failure on stderr itself); else software.
    Auto,
    Vaapi, ///< VAAPI or fail.
    Cuda,  ///< CUDA (NVDEC) or fail.
    Vdpau, ///< VDPAU or fail.
};

/// \return the mode of \a name (`none`, `auto`, `vaapi`, `cuda`, `vdpau`), or nothing.
Result<HwAccelMode> parseHwAccel(std::string_view name) noexcept;

/// \brief The hardware device a decoder context decodes on.
struct HwAccel {
    AVPixelFormat pixFmt = AV_PIX_FMT_NONE; ///< Its frames' format; NONE: software.
    const char *name = "software";          ///< "vaapi", "cuda", "vdpau" or "software".
    [[nodiscard]] bool active() const noexcept { return pixFmt != AV_PIX_FMT_NONE; }
};

/// \brief Opens a device of \a mode for \a codec and attaches it to \a ctx (hw_device_ctx and a
/// get_format that picks the device's format while libavcodec offers it, software otherwise),
/// before avcodec_open2(). Auto tries each device type \a codec has a hwaccel for and falls back to
/// software quietly; a named type that does not open is Errc::NoDevice ("hwaccel vaapi: no
/// device"). \a ctx->opaque is taken (the chosen format).
/// \return the accelerator (inactive for software).
Result<HwAccel> attachHwAccel(AVCodecContext &ctx, const AVCodec &codec, HwAccelMode mode);

/// \brief \a frame in system memory: itself when it is not a frame of \a hw, else copied into
/// \a scratch (av_hwframe_transfer_data; NV12 or P010 for 8- and 10-bit 4:2:0), with its
/// timestamps and flags. \a scratch may be null while \a hw is inactive.
/// \return the frame to read, or nullptr when the copy failed.
const AVFrame *inSystemMemory(const AVFrame &frame, const HwAccel &hw, AVFrame *scratch) noexcept;

} // namespace depthtouch::drivers::ffmpeg
