/// \file
/// \brief Depth enhancement sweep on real frames (see enhance_sweep.h).

#include "depthtouch/depth/enhance_sweep.h"

#include <cstdio>
#include <memory>

#include "depthtouch/depth/fill.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(DepthBench)

namespace depthtouch::depth {

namespace {

struct FileCloser {
    void operator()(std::FILE *f) const noexcept { std::fclose(f); }
};
struct PipeCloser {
    void operator()(std::FILE *f) const noexcept { pclose(f); }
};

/// A converted, filled frame.
struct Frame {
    Plane<float> nearness;
    double holesPercent = 0.0;
};

Result<Frame> loadFrame(const EnhanceSweepOptions &o, int number)
{
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06d.depth.png", number);
    const std::string path = o.framesDir + name;
    auto image = media::readImage(path, media::PixelFormat::Gray16);
    if (!image) {
        DT_LOG(DepthBench, Error, "Failed to read depth frame %s", path.c_str());
        return unexpected(image.error());
    }
    auto converted = metricToNearness(media::toPlane16(*image), o.conversion);
    if (!converted)
        return unexpected(converted.error());
    auto filled = fillInvalid(converted->nearness, converted->valid);
    if (!filled)
        return unexpected(filled.error());
    return Frame{std::move(converted->nearness), 100.0 * static_cast<double>(*filled) /
                                                     static_cast<double>(converted->valid.size())};
}

void writeGnuplotScript(std::FILE *gp, const std::string &csv, const std::string &png)
{
    std::fprintf(
        gp,
        "set terminal pngcairo size 900,600 noenhanced\n"
        "set output '%s'\n"
        "set datafile separator ','\n"
        "set title 'Depth enhancement (paper V.B) on 7-Scenes: points kept against error'\n"
        "set xlabel 'points kept (%% of pixels)'\n"
        "set ylabel 'mean |enhanced - median-filtered| (8-bit nearness levels)'\n"
        "set logscale x\n"
        "set grid\n"
        "set key top right\n"
        "plot '%s' using ($1==0?$5:1/0):7 with linespoints pt 7 title 'linear-error criterion', "
        "\\\n"
        "     '' using ($1==0?$5:1/0):7:(sprintf('%%g',$2)) with labels offset 1.2,0.6 notitle, "
        "\\\n"
        "     '' using ($1==1?$5:1/0):7 with linespoints pt 5 title 'gradient criterion (paper)', "
        "\\\n"
        "     '' using ($1==1?$5:1/0):7:(sprintf('%%g',$2)) with labels offset 1.2,-0.6 notitle\n",
        png.c_str(), csv.c_str());
}

} // namespace

const char *criterionName(SamplingCriterion criterion) noexcept
{
    return criterion == SamplingCriterion::Gradient ? "gradient" : "linear_error";
}

Result<EnhanceSweepResult> runEnhanceSweep(const EnhanceSweepOptions &o)
{
    if (o.frames.empty() || o.tolerances.empty() || o.criteria.empty())
        return unexpected(Errc::InvalidArgument, "Sweep needs frames, tolerances and criteria");

    std::vector<Frame> frames;
    for (const int n : o.frames) {
        auto f = loadFrame(o, n);
        if (!f)
            return unexpected(f.error());
        frames.push_back(std::move(*f));
    }

    platform::SteadyClock &clock = platform::SteadyClock::instance();
    EnhanceSweepResult result;
    for (const SamplingCriterion criterion : o.criteria) {
        for (const float tolerance : o.tolerances) {
            EnhanceOptions eo = o.enhance;
            eo.sampling.criterion = criterion;
            eo.sampling.tolerance = tolerance;
            EnhanceSweepRow row;
            row.criterion = criterion;
            row.tolerance = tolerance;
            double seconds = 0.0;
            for (const Frame &f : frames) {
                const auto t0 = clock.now();
                auto r = enhance(f.nearness, eo);
                seconds += platform::toSeconds(clock.now() - t0);
                if (!r)
                    return unexpected(r.error());
                const EnhanceReport &rep = r->report;
                row.pixels += static_cast<double>(rep.pixels);
                row.points += static_cast<double>(rep.points);
                row.meanAbsError += rep.meanAbsError;
                row.rmsError += rep.rmsError;
                row.p99AbsError += rep.p99AbsError;
                row.maxAbsError += rep.maxAbsError;
                row.roughnessInput += rep.input.roughness;
                row.roughnessMedian += rep.median.roughness;
                row.roughnessEnhanced += rep.enhanced.roughness;
                row.edgeContrastInput += rep.input.edgeContrast;
                row.edgeContrastEnhanced += rep.enhanced.edgeContrast;
                row.holesPercent += f.holesPercent;
            }
            const auto n = static_cast<double>(frames.size());
            row.frames = frames.size();
            for (double *v : {&row.pixels, &row.points, &row.meanAbsError, &row.rmsError,
                              &row.p99AbsError, &row.maxAbsError, &row.roughnessInput,
                              &row.roughnessMedian, &row.roughnessEnhanced, &row.edgeContrastInput,
                              &row.edgeContrastEnhanced, &row.holesPercent})
                *v /= n;
            row.pointsPercent = 100.0 * row.points / row.pixels;
            row.millisPerFrame = 1000.0 * seconds / n;
            DT_LOG(DepthBench, Info,
                   "%s tol %.3g: points %.0f (%.2f %%), mean err %.3f, rough %.3f -> %.3f, edge "
                   "%.2f -> %.2f",
                   criterionName(criterion), static_cast<double>(tolerance), row.points,
                   row.pointsPercent, row.meanAbsError, row.roughnessInput, row.roughnessEnhanced,
                   row.edgeContrastInput, row.edgeContrastEnhanced);
            result.rows.push_back(row);
        }
    }

    result.csvPath = o.outputPrefix + ".csv";
    {
        std::unique_ptr<std::FILE, FileCloser> csv(std::fopen(result.csvPath.c_str(), "w"));
        if (!csv) {
            DT_LOG(DepthBench, Error, "Failed to create %s", result.csvPath.c_str());
            return unexpected(Errc::Io, "Failed to create the sweep CSV");
        }
        // criterion_id first so gnuplot can select a curve numerically.
        std::fprintf(
            csv.get(),
            "criterion_id,tolerance,criterion,frames,points_percent,points,mean_abs_error,rms_"
            "error,"
            "p99_abs_error,max_abs_error,roughness_input,roughness_median,roughness_enhanced,"
            "edge_contrast_input,edge_contrast_enhanced,holes_percent,ms_per_frame,pixels\n");
        for (const EnhanceSweepRow &r : result.rows)
            std::fprintf(csv.get(),
                         "%d,%g,%s,%zu,%.4f,%.1f,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,"
                         "%.1f,%.0f\n",
                         r.criterion == SamplingCriterion::Gradient ? 1 : 0,
                         static_cast<double>(r.tolerance), criterionName(r.criterion), r.frames,
                         r.pointsPercent, r.points, r.meanAbsError, r.rmsError, r.p99AbsError,
                         r.maxAbsError, r.roughnessInput, r.roughnessMedian, r.roughnessEnhanced,
                         r.edgeContrastInput, r.edgeContrastEnhanced, r.holesPercent,
                         r.millisPerFrame, r.pixels);
        if (std::fflush(csv.get()) != 0 || std::ferror(csv.get()) != 0)
            return unexpected(Errc::Io, "Failed to write the sweep CSV");
    }

    if (o.plot) {
        const std::string script = o.outputPrefix + ".gp";
        const std::string png = o.outputPrefix + ".png";
        {
            std::unique_ptr<std::FILE, FileCloser> gp(std::fopen(script.c_str(), "w"));
            if (!gp)
                return unexpected(Errc::Io, "Failed to create the gnuplot script");
            writeGnuplotScript(gp.get(), result.csvPath, png);
        }
        const std::string command = "gnuplot '" + script + "' 2>&1";
        std::unique_ptr<std::FILE, PipeCloser> pipe(popen(command.c_str(), "r"));
        char line[256];
        while (pipe && std::fgets(line, sizeof line, pipe.get()) != nullptr)
            DT_LOG(DepthBench, Warning, "gnuplot: %s", line);
        const int status = pipe ? pclose(pipe.release()) : -1;
        if (status == 0)
            result.chartPath = png;
        else
            DT_LOG(DepthBench, Warning, "gnuplot failed (status %d): no chart, CSV at %s", status,
                   result.csvPath.c_str());
    }
    return result;
}

} // namespace depthtouch::depth
