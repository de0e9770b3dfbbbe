#pragma once
/// \file
/// \brief The sender's pipeline behind `depthtouch encode`: pull paired color and depth frames
/// from two FrameSources, turn depth into nearness, optionally enhance it (paper §V.B), encode
/// color H.264 4:2:0 and depth 4:0:0 / gray10 / FFV1 gray16 and mux both into one output
/// (docs/architecture.md §4) with identical PTS for each pair.
///
/// Depth conversion (docs/architecture.md §3):
///  - 8-bit depth samples are nearness and pass through (scaled to the output's 2^bits − 1);
///    color-format depth inputs give their luma, likewise. Without given planes, the input's own
///    depth_near/depth_far/depth_mapping tags (a DepthTouch file) are carried over.
///  - A DepthTouch file's depth (EncodeOptions::depthInputHoleBelow) is nearness at any bit depth;
///    its holes (codes under its hole threshold) are written as holes, as metric holes are below,
///    or filled with EncodeOptions::fillHoles.
///  - 16-bit samples are metric depth (EncodeOptions::depthScale metres per unit): converted with
///    near/far planes that are either given or the robust range (1 %..99 % quantiles, a sparse far
///    tail cut: depth::estimateRange()) of the valid
///    samples of the first EncodeOptions::rangeFrames frames, decided once so the mapping is
///    constant over the file, in the 1/Z (MPEG 3DV) or linear mapping. Invalid samples (0 and the
///    saturation value) stay holes (docs/architecture.md §3 "Holes"): coded 0, measured nearness
///    lifted above the guard band of depth::occupancyFor() (depth/occupancy.h), the threshold
///    written as the `depth_occupancy` tag; a frame without any valid sample is all holes. With
///    EncodeOptions::fillHoles they are instead filled by push-pull interpolation from valid
///    neighbours (depth/fill.h), never set to the far plane, no threshold is written, and a frame
///    without any valid sample repeats the previous frame.
///  - Depth of another size than the output grid (the color size or EncodeOptions::width/height)
///    is resampled edge-aware (depth/resample.h; holes by nearest sample, never blended into
///    measured depth), with a warning.
///  - `enhance`: depth::enhance() per frame (median → adaptive points → Delaunay → Gaussian mesh
///    smoothing → re-render), its report accumulated in EncodeSummary; holes are filled for the
///    filter only and stay holes in the output.
///
/// Pairing: frame i of each source forms pair i; its PTS is the color frame's PTS (seconds from
/// the first), forced strictly increasing. Encoding ends at the shorter source, after maxFrames
/// pairs or maxDuration seconds, or when *stop becomes true (then the encoders are flushed and
/// the trailer written: the output stays playable).
///
/// Material track (docs/materials.md): with a material source, a third stream titled `material`
/// (VideoCodec::H264Rgb, lossless) carries the material codes of each depth frame on the output
/// grid, with the depth frame's PTS (MaterialTrack: resized nearest-neighbour, the last frame
/// holds when the source ends).
///
/// Thread-safety: runs on the calling thread; \a stop may be set from any thread or a signal
/// handler (it is only read, lock-free).

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/enhance.h"
#include "depthtouch/media/audio_track.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief Everything `depthtouch encode` can set.
struct EncodeOptions {
    std::string output;                 ///< File name or URL.
    std::optional<Container> container; ///< nullopt: containerForOutput(output).
    int crf = 23;                       ///< Color x264 CRF 0..51.
    std::string preset = "medium";      ///< x264 preset of both H.264 streams.
    VideoCodec depthCodec =
        VideoCodec::H264Gray;   ///< H264Gray, H264Gray10, HevcMain10 or Ffv1Gray16.
    int depthCrf = 18;          ///< Depth x264 CRF 0..51 (lossy).
    bool depthLossless = false; ///< Depth x264 qp 0 (FFV1 is always lossless).
    int threads = 0;            ///< Encoder threads per stream; 0 = automatic.
    /// Frames between key frames, the same in every stream (VideoEncoderConfig::gop: aligned, no
    /// scene-cut key frames); 0: 2 s for a paced output and HLS, x264's default otherwise.
    int gop = 0;
    RateControl colorRate; ///< Color bit rate, maxrate, VBV buffer; default: the CRF alone.
    RateControl depthRate; ///< Depth's likewise (lossy H.264 depth only).
    long long muxRate = 0; ///< MPEG-TS constant mux rate, bits/s (MuxerOptions::muxRate); 0: none.
    /// Sound (AudioTrack): the file whose first audio stream the output carries; empty: none.
    std::string audioSource;
    /// audioSource is the color input: its video stream's start is the picture's (output 0).
    bool audioFromPicture = false;
    /// A source without an audio stream is an error (`--audio` named it), not silence.
    bool audioRequired = false;
    /// An HLS rendition ladder (`--renditions`): the heights (pixels, even, tallest first, at
    /// most the output grid's) of renditions that each carry color, depth, material and sound at
    /// that height and the grid's aspect; the output names their multivariant playlist
    /// (docs/making-content.md "A rendition ladder"). Empty: one output.
    std::vector<int> renditions;
    int width = 0; ///< Output grid (pixels, even); 0 = the color size.
    int height = 0;
    /// Write at the media rate (as `ffmpeg -re`): pair n leaves no earlier than its PTS after the
    /// first. `encode` sets it for URL outputs and --loop unless --realtime says otherwise. A
    /// paced HLS output is a live playlist (MuxerOptions::live).
    bool paced = false;
    long long maxFrames = 0;  ///< Stop after this many pairs; 0 = no limit.
    double maxDuration = 0.0; ///< Stop at this PTS (seconds); 0 = no limit.

    depth::RawDepthFormat raw{}; ///< Metric input: metres per unit, saturation value.
    depth::DepthMapping mapping = depth::DepthMapping::InverseZ;
    std::optional<depth::DepthRange> range; ///< Given near/far (metres); nullopt = robust range.
    int rangeFrames = 5;                    ///< Frames the robust range is taken from (≥ 1).
    /// Metric input: fill invalid samples by push-pull (`--fill-holes`) instead of keeping them as
    /// holes with a `depth_occupancy` threshold.
    bool fillHoles = false;
    /// The depth input is a DepthTouch file (its depth stream carries the depth tags, as play and
    /// probe read them): its samples are nearness codes at any bit depth, never metric depth, and
    /// a sample below this threshold is a hole (scene::DepthFrameView::holeBelow of its frames as
    /// read: 8-bit frames for an 8-bit input, else 16-bit widened by bit replication;
    /// receiver::depthHoleBelow() gives it). Its holes stay holes of the output (the
    /// `depth_occupancy` tag) unless fillHoles. 0: the file has no holes; nullopt: not a
    /// DepthTouch file (16-bit samples are metric depth).
    std::optional<std::uint32_t> depthInputHoleBelow;

    bool enhance = false; ///< Run the §V.B enhancement on every depth frame.
    /// Enhancement options at the 8-bit scale; scaled to the output's bits (forScale()).
    depth::EnhanceOptions enhanceOptions{};

    /// \return Errc::InvalidArgument with a message naming the bad option, or nothing.
    [[nodiscard]] Result<void> validate() const;
};

/// \brief Progress after each encoded pair (for a terminal display).
struct EncodeProgress {
    long long frames = 0;      ///< Pairs encoded.
    long long totalFrames = 0; ///< Expected pairs, 0 when unknown.
    double elapsed = 0.0;      ///< Wall-clock seconds since the start.
    double pts = 0.0;          ///< PTS of the last pair (seconds).
};

/// \brief Accumulated §V.B enhancement figures over the encoded frames.
struct EnhanceTotals {
    long long frames = 0;
    long long pixels = 0;        ///< Σ W·H.
    long long points = 0;        ///< Σ feature points kept.
    double meanAbsError = 0.0;   ///< Mean |enhanced − median-filtered| over all pixels (levels).
    double rmsError = 0.0;       ///< RMS of the same (levels).
    double maxAbsError = 0.0;    ///< Largest over the frames (levels).
    double roughnessInput = 0.0; ///< Mean over frames of the flat-region roughness before (levels).
    double roughnessOutput = 0.0;    ///< … and after.
    double edgeContrastInput = 0.0;  ///< Mean over frames of the strong-edge contrast before.
    double edgeContrastOutput = 0.0; ///< … and after.
    double levelsMax = 255.0;        ///< The scale of the levels above (2^bits − 1).
};

/// \brief One rendition of a ladder, as written in the multivariant playlist.
struct RenditionSummary {
    int width = 0;                ///< Pixels.
    int height = 0;               ///< Pixels.
    std::string playlist;         ///< Its media playlist's path.
    long long peakBitRate = 0;    ///< BANDWIDTH (RFC 8216 §4.3.4.2), bits/s.
    long long averageBitRate = 0; ///< AVERAGE-BANDWIDTH, bits/s.
};

/// \brief What the encode did.
struct EncodeSummary {
    long long frames = 0; ///< Pairs written.
    /// Compressed bytes of each kind, summed over the renditions of a ladder.
    long long colorBytes = 0;     ///< Compressed color bytes.
    long long depthBytes = 0;     ///< Compressed depth bytes.
    long long materialBytes = 0;  ///< Compressed material bytes (0 without a material track).
    long long materialFrames = 0; ///< Material frames read (the rest held the last one).
    std::string audio;            ///< AudioTrack::description(), empty without sound.
    long long audioBytes = 0;     ///< Audio bytes written.
    double elapsed = 0.0;         ///< Wall-clock seconds.
    double duration = 0.0;        ///< PTS span written (seconds).
    bool interrupted = false;     ///< *stop ended it.
    bool metric = false;          ///< Depth was metric and converted with `range`.
    depth::DepthRange range{};    ///< Planes used (metric, given, or from the input's tags).
    /// What a robust range (metric depth, no --near/--far) was taken from; nullopt otherwise.
    std::optional<depth::RangeEstimate> rangeEstimate;
    depth::DepthMapping mapping = depth::DepthMapping::InverseZ; ///< Mapping written.
    int depthBits = 8;                                           ///< 8, 10 or 16.
    long long filledSamples = 0;                                 ///< Invalid depth samples filled.
    long long holeSamples = 0;  ///< Depth samples written as holes (output grid).
    long long depthSamples = 0; ///< Depth samples written (output grid, every frame).
    /// The `depth_occupancy` threshold written (stream sample units); 0: no holes, no tag.
    std::uint32_t depthOccupancy = 0;
    long long repeatedFrames = 0; ///< Depth frames without valid samples (previous repeated).
    bool depthResampled = false;  ///< Depth was resampled to the output grid.
    std::string endedBy;          ///< "color", "depth", "frames", "duration" or "stop".
    std::vector<RenditionSummary> renditions; ///< A ladder's, tallest first; empty without.
    std::optional<EnhanceTotals> enhance;
};

/// \brief Callbacks of encodeStreams(); each may be empty.
struct EncodeCallbacks {
    std::function<void(const EncodeProgress &)> progress; ///< After each pair.
    std::function<void(const std::string &)> warning;     ///< Once per condition (e.g. resampling).
};

/// \brief Runs the whole encode (see the file comment).
/// \param[in] stop may be null; when it becomes true, encoding stops after the current pair.
/// \return the summary; errors: Errc::InvalidArgument for bad options or input data (no frame,
///         odd output size, corrupt frame, depth without any valid sample to start from),
///         Errc::Io when writing fails or the output cannot be created, Errc::NotSupported for an
///         encoder or container FFmpeg lacks. No output file is left behind on error.
Result<EncodeSummary> encodeStreams(FrameSource &color, FrameSource &depth,
                                    const EncodeOptions &options,
                                    const std::atomic<bool> *stop = nullptr,
                                    const EncodeCallbacks &callbacks = {});

/// \brief As above, with the material track from \a material (nullptr: none; read as RGB24
/// codes, see depthtouch/scene/material.h). A material input without any frame is
/// Errc::InvalidArgument; its read errors are returned as they are.
Result<EncodeSummary> encodeStreams(FrameSource &color, FrameSource &depth, FrameSource *material,
                                    const EncodeOptions &options,
                                    const std::atomic<bool> *stop = nullptr,
                                    const EncodeCallbacks &callbacks = {});

/// \brief The metadata tags of docs/architecture.md §4 written on the depth stream and the
/// container: depth_near and depth_far (metres, "%.6g"; "unknown" when \a range is nullopt, as for
/// 8-bit nearness inputs given without planes), depth_mapping ("inverse_z" or "linear"),
/// depth_bits, and depth_occupancy (decimal, stream sample units: a sample below it is a hole,
/// depth/occupancy.h) when \a occupancy is not 0.
std::vector<std::pair<std::string, std::string>>
depthTags(const std::optional<depth::DepthRange> &range, depth::DepthMapping mapping, int bits,
          std::uint32_t occupancy = 0);

} // namespace depthtouch::media
