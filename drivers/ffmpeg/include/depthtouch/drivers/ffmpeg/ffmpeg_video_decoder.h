#pragma once
/// \file
/// \brief FfmpegVideoDecoder: libavcodec decoder lending frames from a preallocated pool. Backend
/// names `ffmpeg` (software: H.264, HEVC, FFV1, raw video, MJPEG) and `v4l2m2m` (H.264 through
/// h264_v4l2m2m; creation fails with NoDevice when libavcodec lacks it or no /dev/video* exists).
///
/// Options: `pool=N` output frames (1..64, default 4; 24 with `drm-prime`), `queue=N` input
/// packets (1..256, default 8), `threads=N` slice threads (1..16, default 2), `drm-prime` (boolean,
/// default off; colour streams only) zero-copy output, see below. Slice threads only, no frame
/// threads: frame
/// threading holds `threads` packets back, which would break "one queued intra packet gives one
/// frame" and the drain accounting.
///
/// Decoding runs inside dequeueFrame(): queuePacket() copies the packet into a fixed ring and never
/// blocks; dequeueFrame() feeds queued packets to libavcodec until a frame comes out, then copies
/// its planes into a free pool frame (tightly packed, format StreamConfig::format). Pool frames
/// are copies, not AVFrame references, so a held FrameRef never pins libavcodec's buffers. Gray
/// output of a YUV stream is its luma plane unchanged (gray H.264 is yuv420p with neutral chroma);
/// gray16be becomes host order. A frame libavcodec flags as damaged is lent with Frame::corrupt
/// (counted concealed); a packet libavcodec refuses is counted dropped (dequeueFrame() returns Io
/// for it), and so is every packet that produced no frame at drain or flush.
///
/// Damaged input decodes on as in ffmpeg: what libavcodec decodes is lent, concealed errors
/// included (Frame::corrupt), and the pictures it cannot vouch for are withheld, never asked for
/// (AV_CODEC_FLAG_OUTPUT_CORRUPT and AV_CODEC_FLAG2_SHOW_ALL stay off): after configure() or
/// flush(), every picture before a key frame or a recovery point, and after a loss the pictures it
/// cannot place in order. The first are predicted from pictures this decoder never had: as depth, a
/// made-up surface under the finger, not a patch concealed in a real one (the haptic side bounds
/// the steps a concealed patch makes). So flush() costs every frame up to the next key frame
/// (seconds in a file): the receiver flushes a stream for a seek, or to resume one whose packets
/// had stopped, not one whose frames only lag (receiver.h). With slice threads (`threads` > 1)
/// libavcodec leaves H.264 error concealment off (unsafe with them): damaged macroblocks are not
/// concealed (about twice the concealed pictures' error on cli_damaged_ts_end_to_end's clip).
/// When nothing is queued and no frame is ready, dequeueFrame() sleeps on the backend clock until
/// the deadline.
///
/// `drm-prime` (zero-copy, DRM PRIME / dma-buf): when the libavcodec decoder can export
/// AV_PIX_FMT_DRM_PRIME frames (h264_v4l2m2m of vendor FFmpeg builds; upstream h264_v4l2m2m
/// cannot), get_format asks for them and each frame is lent with Frame::dmabuf filled
/// (dmaBufFromDrmDescriptor()) and an image without planes (size and format only); the AVFrame
/// stays referenced while the FrameRef is held, so its fds stay valid, and is unreferenced on the
/// decode thread by the next dequeueFrame(), configure() or close() after the FrameRef came back
/// (the release itself stays lock-free). The pool then has no CPU pixels until a frame needs them,
/// and the V4L2 capture queue gets pool + 8 buffers. Fallback, logged once as a warning, never an
/// error: when the decoder cannot export DRM PRIME (or a frame comes out in a software format), the
/// frames are CPU copies exactly as without the option. DecoderStats::framesDmaBuf counts the
/// frames lent as dma-bufs. Thread-safety: as hal::VideoDecoder.

#include <memory>
#include <string>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/video_decoder_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief Sizes of FfmpegVideoDecoder (from the backend options).
struct FfmpegDecoderSettings {
    int poolFrames = 4;
    int queuePackets = 8;
    int threads = 2;
    bool drmPrime = false; ///< `drm-prime`: lend DRM PRIME frames when the decoder can.
    /// `hwaccel` (ffmpeg's `-hwaccel`): none | auto | vaapi | cuda | vdpau. auto (the default)
    /// decodes on the first of VAAPI, CUDA (NVDEC), VDPAU that opens and decodes the stream, else
    /// in software; a named one that does not open fails configure() (Errc::NoDevice). Frames are
    /// copied back to system memory (DecoderStats::framesHardware counts them). Not with
    /// `drm-prime` or the v4l2m2m backend, which are hardware paths of their own.
    std::string hwaccel = "auto";

    static Result<FfmpegDecoderSettings> parse(hal::OptionList options);
};

class FfmpegVideoDecoder final : public hal::VideoDecoderBase {
public:
    /// Backend factory of `ffmpeg` (software decoding).
    static Result<std::unique_ptr<hal::VideoDecoder>> create(const hal::BackendConfig &cfg);
    /// Backend factory of `v4l2m2m` (H.264 on a V4L2 memory-to-memory device).
    static Result<std::unique_ptr<hal::VideoDecoder>> createV4l2m2m(const hal::BackendConfig &cfg);

    ~FfmpegVideoDecoder() override;

    [[nodiscard]] hal::DecoderStats stats() const noexcept override;

    /// \return frames lent and not yet returned. Thread-safe.
    [[nodiscard]] int framesLent() const noexcept;

    struct Impl;

protected:
    // hal::VideoDecoderBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> configureDevice(const hal::StreamConfig &cfg) override;
    [[nodiscard]] Result<void> queuePacketDevice(const hal::Packet &pkt) override;
    [[nodiscard]] Result<hal::FrameRef> dequeueFrameDevice(hal::Deadline until) override;
    void flushDevice() noexcept override;
    void closeDevice() noexcept override;

private:
    explicit FfmpegVideoDecoder(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::drivers
