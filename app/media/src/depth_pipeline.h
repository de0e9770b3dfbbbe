#pragma once
/// \file
/// \brief The depth half of the sender's encode pipeline (encode_job.h), private to dt_media: one
/// depth frame in, the nearness levels of the output grid out, ready for the depth encoder.
///
/// Metric (16-bit) depth keeps its holes by default (docs/architecture.md §3 "Holes"): invalid
/// samples are coded 0 and measured nearness n is coded depth::occupiedLevel(n) above the guard
/// band of depth::occupancyFor(bits, lossless); resampling keeps the holes (resampleMasked()) and
/// `--enhance` runs on a push-pull filled copy whose holes are restored after. A frame with no
/// valid sample is written all holes. With EncodeOptions::fillHoles, holes are filled by push-pull
/// as before (a frame with no valid sample repeats the previous one) and no threshold is written.
///
/// A DepthTouch file's depth (EncodeOptions::depthInputHoleBelow) is nearness at any bit depth,
/// read as play reads it (scene::DepthFrameView: a code below its holeBelow is a hole, measured
/// codes farCode()..v_max span nearness 0..v_max); its holes are holes of the output as metric
/// holes are (or filled under fillHoles).
///
/// Thread-safety: one object per encode, on its thread.

#include <optional>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/enhance.h"
#include "depthtouch/depth/occupancy.h"
#include "depthtouch/media/encode_job.h"

namespace depthtouch::media::detail {

/// \return the significant bits of the depth codec \a codec: 8, 10 or 16.
int depthBitsOf(VideoCodec codec) noexcept;

/// Depth frame → nearness levels of the output grid (see the file comment).
class DepthPipeline {
public:
    /// \a o and \a cb must outlive the pipeline. \a metric: the input is 16-bit metric depth
    /// converted with \a range.
    DepthPipeline(const EncodeOptions &o, int width, int height, bool metric,
                  std::optional<depth::DepthRange> range, const EncodeCallbacks &cb);

    [[nodiscard]] int bits() const noexcept { return bits_; }
    /// \return the stream's hole threshold and far-plane code; threshold 0 when it has no holes
    /// (8-bit nearness input, or EncodeOptions::fillHoles).
    [[nodiscard]] const depth::Occupancy &occupancy() const noexcept { return occ_; }

    /// \return the encoder's image (Gray8, or Gray16 holding 0..2^bits − 1) of \a frame, with
    /// \a summary's counts updated. Errors: InvalidArgument for an empty frame, a first frame
    /// without a valid sample under fillHoles; the errors of conversion, resampling and
    /// enhancement.
    Result<Image> process(const Image &frame, EncodeSummary &summary);

private:
    /// The nearness of \a frame into \a nearness and its holes into \a valid (empty: none).
    /// \return false when the frame has no valid sample and the previous one is to be repeated.
    Result<bool> toNearness(const Image &frame, depth::Plane<float> &nearness,
                            depth::Plane<std::uint8_t> &valid, EncodeSummary &summary);
    /// The holes of a converted frame (\a n: nearness, validity, count of holes): kept in
    /// \a valid when the output has holes, else filled. \return as toNearness().
    Result<bool> keepOrFill(depth::NearnessFrame &n, depth::Plane<float> &nearness,
                            depth::Plane<std::uint8_t> &valid, EncodeSummary &summary);
    Result<void> resampleToGrid(depth::Plane<float> &nearness, depth::Plane<std::uint8_t> &valid,
                                EncodeSummary &summary);
    Result<void> enhanceFrame(depth::Plane<float> &nearness,
                              const depth::Plane<std::uint8_t> &valid, EncodeSummary &summary);
    void accumulate(const depth::EnhanceReport &r, EncodeSummary &summary);

    const EncodeOptions &options_;
    const EncodeCallbacks &callbacks_;
    int width_;
    int height_;
    bool metric_;
    /// The input's hole threshold in the units of its frames (EncodeOptions::depthInputHoleBelow);
    /// 0: none.
    std::uint32_t inputHoleBelow_;
    int bits_;
    double vmax_;
    std::optional<depth::DepthRange> range_;
    depth::Occupancy occ_{};
    depth::EnhanceOptions enhance_;
    Image last_;
};

} // namespace depthtouch::media::detail
