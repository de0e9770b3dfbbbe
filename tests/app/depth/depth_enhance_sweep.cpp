/// \file
/// \brief depth_enhance_sweep: runs the depth enhancement measurement (points kept against error)
/// on 7-Scenes and prints the table. Not a test. Usage:
///   depth_enhance_sweep [FRAMES_DIR [OUTPUT_PREFIX]]
/// FRAMES_DIR defaults to $DT_SHARED_DATA/rgbd-7scenes-redkitchen, OUTPUT_PREFIX to
/// ./depth_enhance_sweep.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "depthtouch/depth/enhance_sweep.h"

int main(int argc, char **argv)
{
    using namespace depthtouch;
    depth::EnhanceSweepOptions o;
    const char *shared = std::getenv("DT_SHARED_DATA");
    o.framesDir = argc > 1 ? argv[1]
                           : std::string(shared != nullptr ? shared : "../shared/data") +
                                 "/rgbd-7scenes-redkitchen";
    if (argc > 2)
        o.outputPrefix = argv[2];
    const auto r = depth::runEnhanceSweep(o);
    if (!r) {
        char buf[160];
        std::fprintf(stderr, "depth_enhance_sweep: %s\n", r.error().format(buf, sizeof buf));
        return 1;
    }
    std::printf("%-12s %6s %9s %8s %8s %8s %8s %8s %8s %8s %8s %8s %8s\n", "criterion", "tol",
                "points", "pts%", "meanErr", "p99Err", "maxErr", "roughIn", "roughMed", "roughOut",
                "edgeIn", "edgeOut", "ms");
    for (const auto &row : r->rows)
        std::printf(
            "%-12s %6.3g %9.0f %8.3f %8.3f %8.3f %8.2f %8.4f %8.4f %8.4f %8.2f %8.2f %8.0f\n",
            depth::criterionName(row.criterion), static_cast<double>(row.tolerance), row.points,
            row.pointsPercent, row.meanAbsError, row.p99AbsError, row.maxAbsError,
            row.roughnessInput, row.roughnessMedian, row.roughnessEnhanced, row.edgeContrastInput,
            row.edgeContrastEnhanced, row.millisPerFrame);
    std::printf("holes filled: %.2f %% of pixels; CSV: %s; chart: %s\n",
                r->rows.front().holesPercent, r->csvPath.c_str(),
                r->chartPath.empty() ? "(none)" : r->chartPath.c_str());
    return 0;
}
