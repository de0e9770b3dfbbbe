#pragma once
/// \file
/// \brief Measurement of the depth enhancement (paper §V.B) on real RGB-D frames: for each sampling
/// criterion and error tolerance, points kept against error, roughness and edge contrast, averaged
/// over frames; writes a CSV and a gnuplot chart "points kept against error".
///
/// Input: a folder of `frame-NNNNNN.depth.png` (16-bit, metric units, 0/65535 invalid) such as
/// `../shared/data/rgbd-7scenes-redkitchen`. Each frame is converted (conversion.h), filled
/// (fill.h) and enhanced (enhance.h) at every tolerance. Thread-safety: reentrant; runs gnuplot as
/// a child process.

#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/enhance.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::depth {

/// \brief Options of runEnhanceSweep().
struct EnhanceSweepOptions {
    std::string framesDir; ///< Folder holding frame-NNNNNN.depth.png.
    std::vector<int> frames{0,  10, 20, 30,
                            40, 50}; ///< Frame numbers NNNNNN to use (missing ones are an error).
    std::vector<float> tolerances{0.125f, 0.25f, 0.5f,  1.0f, 2.0f,
                                  4.0f,   8.0f,  16.0f, 32.0f}; ///< Levels.
    std::vector<SamplingCriterion> criteria{SamplingCriterion::LinearError,
                                            SamplingCriterion::Gradient};
    ConvertOptions conversion{}; ///< mm input, 1/Z mapping, planes from the data, v_max = 255.
    EnhanceOptions enhance{};    ///< Base options; sampling tolerance/criterion are swept.
    std::string outputPrefix =
        "depth_enhance_sweep"; ///< Writes PREFIX.csv, PREFIX.gp and PREFIX.png.
    bool plot = true;          ///< Run gnuplot (skipped with a warning when it is missing).
};

/// \brief One (criterion, tolerance) point of the sweep, averaged over the frames.
struct EnhanceSweepRow {
    SamplingCriterion criterion = SamplingCriterion::LinearError;
    float tolerance = 0.0f; ///< Nearness levels.
    std::size_t frames = 0;
    double pixels = 0.0;        ///< Per frame.
    double points = 0.0;        ///< Mean points kept per frame.
    double pointsPercent = 0.0; ///< 100 · points / pixels.
    double meanAbsError = 0.0;  ///< Levels, vs the median-filtered input (EnhanceReport).
    double rmsError = 0.0;
    double p99AbsError = 0.0;
    double maxAbsError = 0.0;
    double roughnessInput = 0.0; ///< RMS Laplacian on flat regions (levels).
    double roughnessMedian = 0.0;
    double roughnessEnhanced = 0.0;
    double edgeContrastInput = 0.0; ///< Mean local range at strong edges (levels).
    double edgeContrastEnhanced = 0.0;
    double holesPercent = 0.0;   ///< Invalid samples filled before enhancement, % of pixels.
    double millisPerFrame = 0.0; ///< Wall time of enhance() per frame.
};

/// \brief The sweep's rows and the files written.
struct EnhanceSweepResult {
    std::vector<EnhanceSweepRow> rows;
    std::string csvPath;
    std::string chartPath; ///< Empty when no chart was made.
};

/// \brief Runs the sweep and writes PREFIX.csv (one row per criterion and tolerance) and, with
/// gnuplot, PREFIX.png: x = points kept (% of pixels, log scale), y = mean |error| (levels), one
/// curve per criterion, each point labelled with its tolerance. \return the rows;
/// Errc::InvalidArgument for empty lists, Errc::Io when a frame cannot be read or the CSV
///         cannot be written, any error of conversion/fill/enhance.
Result<EnhanceSweepResult> runEnhanceSweep(const EnhanceSweepOptions &options);

/// \return "linear_error" or "gradient".
const char *criterionName(SamplingCriterion criterion) noexcept;

} // namespace depthtouch::depth
