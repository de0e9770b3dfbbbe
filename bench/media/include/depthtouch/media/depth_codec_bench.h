#pragma once
/// \file
/// \brief `depthtouch bench media`'s depth codec comparison: for each depth codec `encode` offers
/// (`--depth-codec h264|hevc|ffv1`, `--depth-bits`) and frame size, the depth bit rate, the decode
/// rate in software on one decoder thread and on all of them, and the haptic force error of the
/// decoded depth against the 16-bit source: the figures a producer picks a depth codec by
/// (docs/making-content.md, "Choosing the depth codec").
///
/// Force error: the rate/accuracy sweep's strokes and presses (strokeLanes(), makeStroke(),
/// makePress(); modified proxy graph, paper section IV, safety on) replayed at the haptic rate on
/// the decoded depth and on the clip's 16-bit nearness (Clip::fineNearness()), RMS over every
/// update of |F_decoded − F_source| (N).
///
/// Thread-safety: stateless functions. Not real-time safe.

#include <string>
#include <vector>

#include "depthtouch/media/encoder.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media::bench {

struct Clip;
struct ReceiverBackends;
struct MediaBenchOptions;

/// \brief One depth codec setting at one frame size.
struct CodecRow {
    std::string codec; ///< "h264-8", "h264-10", "hevc-10" or "ffv1-16" (codec-bits).
    VideoCodec id = VideoCodec::H264Gray;
    int width = 0;             ///< Pixels.
    int height = 0;            ///< Pixels.
    bool lossless = false;     ///< FFV1 (always lossless).
    int crf = 0;               ///< x264 / x265 CRF of a lossy setting.
    double depthKbps = 0.0;    ///< Depth bit rate at the clip's frame rate, kbit/s.
    double decodeFps1 = 0.0;   ///< Depth-only decode + pairing, frames per wall-clock second,
                               ///< one decoder thread (median of the runs).
    double decodeFpsAll = 0.0; ///< The same with CodecPlan::allThreads decoder threads.
    double forceRmsN = 0.0;    ///< Strokes and presses: RMS of |F_decoded − F_source|, N.
    double forceMaxN = 0.0;    ///< Largest |F_decoded − F_source| of any update, N.
    double depthErrorMm = 0.0; ///< RMS of the decoded surface's height error over every sample, mm
                               ///< in the scene box (the renderer's z).
};

/// \brief What measureCodecs() measures at one size.
struct CodecPlan {
    std::vector<int> crfs{18};     ///< CRFs of each lossy codec (x264, x265), each a row.
    int allThreads = 1;            ///< Decoder threads of CodecRow::decodeFpsAll.
    std::string preset = "medium"; ///< x264 / x265 preset.
};

/// \brief Measures every depth codec on \a clip: H.264 4:0:0 8- and 10-bit and HEVC Main10 at each
/// CRF of \a plan, FFV1 16-bit once. \a oneThread and \a allThreads decode (their decoders' thread
/// counts: 1 and CodecPlan::allThreads).
/// \return the rows in that order; errors of the encoder (NotSupported without libx265), the
/// receiver or the replay, or InvalidArgument when the decoded frame count differs.
Result<std::vector<CodecRow>> measureCodecs(const Clip &clip, const ReceiverBackends &oneThread,
                                            const ReceiverBackends &allThreads,
                                            const CodecPlan &plan,
                                            const MediaBenchOptions &options);

/// \brief Prints \a rows as a table (one line per codec and size) to stdout, with the goal of the
/// default codec (1920×1080 decode ≥ 60 fps on one thread).
void printCodecs(const std::vector<CodecRow> &rows, int allThreads);

/// \brief Writes depth_codecs.csv and (with gnuplot) depth_codecs.png into \a dir (which exists).
/// \param[out] note a remark for the user (gnuplot missing or failed), empty otherwise.
/// \return false with \a error set when the CSV cannot be written.
bool writeCodecs(const std::vector<CodecRow> &rows, int allThreads, const std::string &dir,
                 std::string &error, std::string &note);

} // namespace depthtouch::media::bench
