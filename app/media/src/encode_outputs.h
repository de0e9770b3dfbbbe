#pragma once
/// \file
/// \brief The outputs of an encode (encode_job.h): one muxer with its color, depth, material and
/// sound encoders, or one such output per rendition of an HLS ladder (renditions.h), each fed the
/// same pair at its own size.
/// Thread-safety: the encode's thread only.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/media/audio_track.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/image_convert.h"
#include "depthtouch/media/material_track.h"
#include "depth_pipeline.h"
#include "renditions.h"

namespace depthtouch::media::detail {

/// The size and rate the color is encoded at.
struct ColorShape {
    int width = 0;
    int height = 0;
    double fps = 0.0;
};

/// The muxer and the encoders (material: optional); the encoders refer to the muxer's streams,
/// so they are declared after it and go first.
struct Outputs {
    std::unique_ptr<Muxer> muxer;
    std::unique_ptr<VideoEncoder> color;
    std::unique_ptr<VideoEncoder> depth;
    std::unique_ptr<VideoEncoder> material;
    std::unique_ptr<AudioTrack> audio; ///< Null without sound.
};

/// \return the frames between key frames of every stream: \a options' --gop, else 2 s (a
/// segment, MuxerOptions::kHlsSegmentSeconds) for a paced output and HLS, else 0 (x264's own).
int keyFrameInterval(const EncodeOptions &options, Container container, double fps);

/// Opens the muxer of \a output with \a tags and the color, depth and (\a material) material
/// encoders at \a shape's size and rate (\a options' bit rates scaled by \a rateScale); the
/// header is written.
Result<void> openOutputs(const EncodeOptions &options, const std::string &output,
                         const ColorShape &shape, double rateScale,
                         const std::vector<std::pair<std::string, std::string>> &tags,
                         bool material, Outputs &out);

/// \brief One output of the encode: the whole output, or one rendition of a ladder.
struct Rendition {
    RenditionPlan plan;
    Outputs out;
    /// The depth of a rendition smaller than the encode's grid, from the input's depth frame
    /// (resampled in nearness, holes kept: depth_pipeline.h); null: the encode's own pipeline.
    std::unique_ptr<DepthPipeline> pipeline;
    EncodeSummary scratch; ///< pipeline's counts (the summary counts the encode's grid).
    ImageConverter colorScaler;
    MaterialScaler materialScaler;
};

/// \brief The encode's outputs: without EncodeOptions::renditions the one output at \a shape,
/// else one per rendition (the tallest at \a shape) and the multivariant playlist, written
/// before the first pair with estimated rates and again whenever a segment completes.
/// The smaller renditions' depth pipelines give no warnings (the encode's own gives them).
class EncodeOutputs {
public:
    EncodeOutputs() = default;
    EncodeOutputs(const EncodeOutputs &) = delete;
    EncodeOutputs &operator=(const EncodeOutputs &) = delete;
    /// An encode that did not finish leaves no multivariant playlist (the muxers remove their
    /// own files).
    ~EncodeOutputs();

    /// \brief Opens every output (headers written).
    Result<void> open(const EncodeOptions &options, const ColorShape &shape,
                      const std::vector<std::pair<std::string, std::string>> &tags, bool material,
                      bool metric, const std::optional<depth::DepthRange> &range);

    /// \brief Encodes a pair at \a pts (s): \a color (Rgb24) and \a depthFrame (the input's
    /// depth frame, for the smaller renditions) at \a shape, \a depth the encode's pipeline's
    /// image of it; \a material the material frame at \a shape or nullptr; sound up to
    /// \a until seconds.
    Result<void> encode(const Image &color, const Image &depthFrame, const Image &depth,
                        const Image *material, double pts, double until);

    /// \brief Flushes every encoder, adds their bytes to \a summary and finishes the outputs
    /// (the multivariant playlist with its measured rates last).
    Result<void> finish(EncodeSummary &summary, double duration);

    [[nodiscard]] bool hasAudio() const noexcept
    {
        return !renditions_.empty() && renditions_.front().out.audio != nullptr;
    }

private:
    Result<void> writeMultivariant(double duration, bool final);

    ColorShape shape_{};
    std::vector<Rendition> renditions_;
    std::string master_;               ///< The multivariant playlist; empty without a ladder.
    std::vector<RenditionRate> rates_; ///< As last written.
    long long segmentsSeen_ = 0;       ///< Segments of all renditions when it was last written.
    double segmentSeconds_ = 2.0;      ///< Each complete segment's duration.
    bool finished_ = false;
};

} // namespace depthtouch::media::detail
