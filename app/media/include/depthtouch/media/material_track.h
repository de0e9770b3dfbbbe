#pragma once
/// \file
/// \brief The sender's side of the material track (depthtouch/scene/material.h,
/// docs/materials.md): material frames on the depth frame's grid, resized nearest-neighbour (a
/// code is a material, never a mix of two), the third stream's encoder settings, a still source
/// for a material map made in memory, and what `probe` reports of a material stream.
///
/// Resizing, layout conversion, decoding and encoding are libswscale, libavcodec and
/// libavformat; no image format is handled by hand. Errors carry static messages.
/// Thread-safety: MaterialScaler, MaterialTrack and the still source are thread-bound; the free
/// functions are reentrant.

#include <memory>
#include <optional>
#include <string>

#include "depthtouch/media/encoder.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \return the material stream's settings: \a base's size, rate, preset, threads and key-frame
/// interval with VideoCodec::H264Rgb (lossless), title scene::kMaterialTitle and the
/// scene::kMaterialPlanesTag / kMaterialScalesTag stream tags.
VideoEncoderConfig materialStreamConfig(const VideoEncoderConfig &base);

/// \brief Nearest-neighbour resizing of RGB24 material codes with libswscale (SWS_POINT with
/// full-resolution chroma in and out, bit-exact): every output pixel is one input pixel's three
/// codes, whatever the ratio. Caches its libswscale context.
class MaterialScaler {
public:
    MaterialScaler();
    ~MaterialScaler();
    DT_DISABLE_COPY(MaterialScaler)

    /// \brief \a src (Rgb24) resized to \a width × \a height pixels; the same size is a copy.
    /// \return the image, tightly packed; Errc::InvalidArgument for an empty or non-Rgb24 \a src
    /// or a size < 1; Errc::NotSupported when libswscale refuses the conversion.
    Result<Image> resize(const Image &src, int width, int height);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// \brief The material frames of an encode: frame k of \a source pairs with depth frame k; after
/// the source's last frame the last one holds (a still image is used for every depth frame).
class MaterialTrack {
public:
    /// \param[in] source read as Rgb24 at its own size; must outlive the track.
    explicit MaterialTrack(FrameSource &source) : source_(source) {}

    /// \brief The material of the next depth frame, resized to \a width × \a height.
    /// \return the image; Errc::InvalidArgument when the source has no frame at all or a frame
    /// is corrupt, the source's other errors (Errc::Io, Errc::Timeout) as they are.
    Result<Image> next(int width, int height);

    /// \brief next() encoded by \a encoder (a materialStreamConfig() stream) at \a ptsSeconds.
    /// \return the errors of next() and VideoEncoder::encode().
    Result<void> encodeNext(VideoEncoder &encoder, int width, int height, double ptsSeconds);

    /// \return frames read from the source (the rest of the depth frames held the last one).
    [[nodiscard]] long long framesRead() const noexcept { return framesRead_; }

private:
    FrameSource &source_;
    MaterialScaler scaler_;
    Image last_;
    bool ended_ = false;
    long long framesRead_ = 0;
};

/// \brief A source of one picture, given in memory (a material map made from labels), delivered
/// for ever at \a fps frames/s (PTS k / fps). next() converts it with ImageConverter's rules
/// (a different size is bicubic: MaterialTrack asks for the picture's own size).
/// \pre image not empty, fps > 0.
std::unique_ptr<FrameSource> makeStillFrameSource(Image image, double fps, std::string description);

/// \brief What `probe` shows of a material stream.
struct MaterialStreamInfo {
    int index = -1;           ///< Stream index in the file.
    int width = 0;            ///< Pixels.
    int height = 0;           ///< Pixels.
    std::string codec;        ///< libavcodec's name, e.g. "h264".
    std::string pixelFormat;  ///< Declared, e.g. "gbrp".
    std::string titleFrom;    ///< "title", "MP4 handler name" or "MPEG-TS order".
    bool tagsPresent = false; ///< The planes and scales tags are on the stream.
    /// Lossless: x264's settings (its SEI) say `qp=0` with constant QP; nullopt when the stream
    /// does not say (no x264 SEI, or the first frame did not decode).
    std::optional<bool> lossless;
    bool decoded = false; ///< The first frame decoded; the ranges below are valid.
    /// Smallest and largest value in the first frame of the stiffness scale, μs and μd.
    double minValue[3] = {0, 0, 0};
    double maxValue[3] = {0, 0, 0};
};

/// \brief Finds the material stream of the file \a path (title or MP4 handler name `material`;
/// in MPEG-TS, which has no titles, the third video stream when it is gbrp) and decodes its first
/// frame. \return the stream, nullopt when the file has none; Errc::Io / InvalidArgument when the
/// file cannot be read. The file is read once more (not for FIFOs or URLs: callers skip those).
Result<std::optional<MaterialStreamInfo>> probeMaterialStream(const std::string &path);

} // namespace depthtouch::media
