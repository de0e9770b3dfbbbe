#pragma once
/// \file
/// \brief FrameSource: where the sender (`depthtouch encode`) pulls its color and depth frames
/// from, one frame at a time, with its PTS.
///
/// A source is named by one text, the *source spec*, parsed in one place (parseSourceSpec()):
///  - `v4l2:/dev/videoN`: a V4L2 camera (see SourceProviders);
///  - `synthetic:NAME`: a synthetic CG scene (see SourceProviders);
///  - anything else: a file, URL or image sequence that FFmpeg reads (openFfmpegFrameSource()):
///    a printf pattern (`d/frame-%06d.png`) or a glob (`d/*.png`, sorted by name) is an image
///    sequence (PNG 8/16-bit, JPEG, any still format) read by libavformat's image2 demuxer at
///    SourceOptions::fps; other names are opened by probing (y4m, mkv, mp4, gray16 FFV1…), or
///    with a forced demuxer and raw-video options (SourceOptions::format, videoSize, pixelFormat).
/// Decoding is libavformat + libavcodec, layout conversion libswscale: no image or container
/// format is parsed here.
///
/// Thread-safety: a FrameSource is thread-bound (use it from one thread); distinct sources are
/// independent.

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/media/image.h"
#include "depthtouch/media/image_convert.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief What a source delivers and how fast.
struct SourceInfo {
    int width = 0;  ///< Pixels.
    int height = 0; ///< Pixels.
    double fps = 0; ///< Nominal frame rate (frames/s): the stream's, or SourceOptions::fps.
    /// The Image layout closest to the source's samples: Gray8 (8-bit gray, e.g. nearness), Gray16
    /// (gray deeper than 8 bits, e.g. metric depth in mm), Rgb24 (any color format).
    PixelFormat nativeFormat = PixelFormat::Rgb24;
    /// Frames the source holds when known (image sequences, most files), 0 when unknown (live).
    long long frameCount = 0;
    std::string description; ///< E.g. "image2 png 640x480 gray16be"; for logs and --help text.
    /// Metadata of the stream and its container, keys lower-case, the stream's first (e.g. the
    /// depth tags of a DepthTouch file: depth_near, depth_far, depth_mapping, depth_bits).
    std::vector<std::pair<std::string, std::string>> tags;

    /// \return the value of tag \a key (lower-case), or nullptr.
    [[nodiscard]] const std::string *tag(std::string_view key) const noexcept
    {
        for (const auto &[k, v] : tags)
            if (k == key)
                return &v;
        return nullptr;
    }
};

/// \brief One decoded frame.
struct SourceFrame {
    Image image;    ///< In the layout asked of next().
    double pts = 0; ///< Seconds from the source's first frame (the first frame has 0).
};

/// \brief A sequence of frames: image sequence, video file, camera, synthetic scene.
class FrameSource {
public:
    virtual ~FrameSource() = default;

    /// \return what the source delivers; constant after opening.
    [[nodiscard]] virtual const SourceInfo &info() const noexcept = 0;

    /// \brief Decodes the next frame and converts it to \a format (libswscale rules of readImage():
    /// 16 → 8 bit keeps the high byte, color → gray takes the luma, gray → RGB replicates). Gray8
    /// from 8-bit planar YUV (a depth video, e.g. gray H.264) copies the luma plane as it is, with
    /// no range conversion.
    /// \param[in] width, height output size in pixels (bicubic scaling); 0 = the frame's own size
    /// \return the frame; Errc::EndOfStream after the last one; Errc::InvalidArgument for a
    ///         corrupt or undecodable frame (the source cannot go on); Errc::Io when reading fails.
    virtual Result<SourceFrame> next(PixelFormat format, int width = 0, int height = 0) = 0;

protected:
    FrameSource() = default;
    FrameSource(const FrameSource &) = delete;
    FrameSource &operator=(const FrameSource &) = delete;
};

/// \brief A FrameSource that makes its frames itself (a camera, a synthetic scene, a still): its
/// constructor fills in info_, and its next() brings each frame to the layout and size asked with
/// converter_.
class ConvertingFrameSource : public FrameSource {
public:
    [[nodiscard]] const SourceInfo &info() const noexcept final { return info_; }

protected:
    ConvertingFrameSource() = default;

    SourceInfo info_;
    ImageConverter converter_;
};

/// \brief Options for opening a source.
struct SourceOptions {
    /// Frame rate (frames/s) of image sequences and raw video, and of any stream whose container
    /// gives none. > 0.
    double fps = 30.0;
    /// Forced libavformat demuxer (`-f`), e.g. "rawvideo", "image2"; empty = by probing.
    std::string format;
    /// Raw video only: "WxH" (`-video_size`) and an FFmpeg pixel format name (`-pixel_format`,
    /// e.g. "gray16le", "rgb24").
    std::string videoSize;
    std::string pixelFormat;
    /// Files with several video streams: take the one with this title (e.g. "depth" to read a
    /// DepthTouch file's depth); absent or empty: FFmpeg's best video stream. `material`
    /// (scene::kMaterialTitle) finds the material track as probe does (title, MP4 handler name,
    /// MPEG-TS order), and an input of several video streams without one is
    /// Errc::InvalidArgument.
    std::string streamTitle;
    /// Files with several video streams: read the one with this container stream number
    /// (libavformat's stream index, e.g. hal::StreamInfo::containerIndex of the stream a player's
    /// identification chose); it takes precedence over streamTitle. -1: by streamTitle. A number
    /// that is no video stream of the input is Errc::InvalidArgument.
    int streamIndex = -1;
    /// Tags known from elsewhere (e.g. a DepthTouch MPEG-TS file's depth tags, carried in its
    /// timed metadata rather than as stream tags), keys lower-case: listed in SourceInfo::tags
    /// before the stream's and the container's own, so they win.
    std::vector<std::pair<std::string, std::string>> tags;
    /// Image sequences only: start over after the last image, forever (a still or a short
    /// sequence as an endless live source; stop it with a frame limit or a signal).
    bool loop = false;
    /// Longest wait of one open or read (ms): a silent URL or a FIFO without a writer fails with
    /// Errc::Timeout after it instead of blocking for ever. > 0.
    int ioTimeoutMs = 10'000;
};

/// \brief The kinds of source spec.
enum class SourceKind : std::uint8_t { Ffmpeg, V4l2, Synthetic };

/// \brief A parsed source spec: its kind and the rest of the text (path, device, scene name).
struct SourceSpec {
    SourceKind kind = SourceKind::Ffmpeg;
    std::string target;
};

/// \brief Splits a source spec into its kind and target (`v4l2:/dev/video0` → V4l2,
/// "/dev/video0"). Everything without a known prefix is an FFmpeg input (URLs like `udp://…`
/// included). \return Errc::InvalidArgument for an empty spec or an empty target after a prefix.
Result<SourceSpec> parseSourceSpec(std::string_view spec);

/// \brief Opens a file, URL or image sequence through FFmpeg (see the file comment). A FIFO is
/// opened without blocking and waits SourceOptions::ioTimeoutMs at most for its writer; every
/// open and read gives up after that long without data (Errc::Timeout).
/// \return the source; Errc::Timeout (no data in time), Errc::Io (missing or unreadable file, no
///         image matches the pattern),
///         Errc::InvalidArgument (not media, no video stream, bad options), Errc::NotSupported
///         (no decoder). FFmpeg's own message is logged (category "Media", Warning).
Result<std::unique_ptr<FrameSource>> openFfmpegFrameSource(const std::string &url,
                                                           const SourceOptions &options);

/// \brief Factories for the sources that live outside dt_media (a V4L2 camera needs a driver,
/// which only executables link; synthetic scenes come from the renderer). An executable that has
/// them fills these in; an empty one means "not built in".
struct SourceProviders {
    using Factory = std::function<Result<std::unique_ptr<FrameSource>>(
        const std::string &target, const SourceOptions &options)>;
    Factory v4l2;      ///< `v4l2:DEVICE`.
    Factory synthetic; ///< `synthetic:NAME`.
};

/// \brief Opens any source spec: FFmpeg inputs here, the others through \a providers.
/// \return the source; Errc::NotSupported with "not built in" for a v4l2:/synthetic: spec whose
///         provider is empty; otherwise the errors of the source opened.
Result<std::unique_ptr<FrameSource>> openFrameSource(std::string_view spec,
                                                     const SourceOptions &options,
                                                     const SourceProviders &providers = {});

} // namespace depthtouch::media
