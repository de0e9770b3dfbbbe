#include "depthtouch/media/media_bench.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "media_bench_steps.h"

// The media benchmark's report: the console tables, the CSV files and the gnuplot charts.

namespace depthtouch::media::bench {

double realtimeGoal(int width, int height) noexcept
{
    if (width == 720 && height == 486)
        return 10.0;
    if (width == 1920 && height == 1080)
        return 2.0;
    return 0.0;
}

void printReport(const MediaBenchReport &r)
{
    std::printf("content: %s\n", r.content.c_str());
    std::printf("decode + pairing: receiver on %s, on the calling thread; x RT = multiple of real "
                "time at %.0f fps\n",
                r.backends.c_str(), r.fps);
    if (r.loadBefore >= 0.0)
        std::printf(
            "machine load (1-min average) before / after: %.2f / %.2f; 'cpu' figures divide "
            "by the process's CPU time (one core's worth of work), 'wall' by elapsed time\n",
            r.loadBefore, r.loadAfter);
    std::printf("\n%-9s %-9s %6s %8s %8s %8s %8s %8s %8s %7s %7s %8s %8s\n", "size", "preset",
                "frames", "color", "depth", "enc fps", "enc fps", "dec fps", "dec fps", "med ms",
                "p99 ms", "dec xRT", "dec xRT");
    std::printf("%-9s %-9s %6s %8s %8s %8s %8s %8s %8s %7s %7s %8s %8s\n", "", "", "", "kbit/s",
                "kbit/s", "wall", "cpu", "wall", "cpu", "wall", "wall", "wall", "cpu");
    for (const ThroughputRow &t : r.throughput)
        std::printf("%-9s %-9s %6zu %8.0f %8.0f %8.1f %8.1f %8.1f %8.1f %7.2f %7.2f %8.1f %8.1f\n",
                    sizeText(t.width, t.height).c_str(), t.preset.c_str(), t.frames, t.colorKbps,
                    t.depthKbps, t.encodeFps, t.encodeCpuFps, t.decodeFps, t.decodeCpuFps,
                    t.decodeMedianMs, t.decodeP99Ms, t.decodeRealtime, t.decodeCpuRealtime);
    if (!r.rate.empty()) {
        std::printf(
            "\nrate vs haptic accuracy at %s: depth only (x264 gray); force error = the same "
            "strokes replayed (modified proxy graph) on the decoded vs the lossless depth\n",
            sizeText(r.rateWidth, r.rateHeight).c_str());
        std::printf("strokes: %s\n", r.stroke.c_str());
        std::printf("lossless depth decoded bit-exact: %s\n", r.losslessExact ? "yes" : "NO");
        std::printf("%-9s %8s %8s | %-19s | %-37s | %-9s\n", "", "", "", "presses",
                    "strokes, as `touch` runs them", "strokes");
        std::printf("%-9s %8s %8s | %-19s | %-37s | %-9s\n", "", "", "", "force error",
                    "force error", "no safety");
        std::printf("%-9s %8s %8s | %9s %9s | %9s %9s %8s %8s | %9s\n", "depth", "kbit/s",
                    "PSNR dB", "RMS N", "max N", "RMS N", "max N", "releases", "pops", "RMS N");
        for (const RateRow &q : r.rate)
            std::printf("%-9s %8.1f %8s | %9.4f %9.3f | %9.4f %9.3f %8ld %8ld | %9.4f\n",
                        settingText(q).c_str(), q.depthKbps, psnrText(q.psnrDb).c_str(),
                        q.pressRmsN, q.pressMaxN, q.forceRmsN, q.forceMaxN, q.releases,
                        q.popThroughs, q.forceRmsNoSafetyN);
        std::printf(
            "(RMS of |F| on the lossless strokes: %.3f N; %zu updates per setting on the strokes; "
            "pops: updates ending with the proxy below the decoded surface, e.g. after a "
            "release)\n",
            r.rate.front().forceRefRmsN, r.rate.front().updates);
    }
    std::printf("\ngoals (decode + pairing of color + depth on one core, x real time at %.0f fps; "
                "worst preset's file):\n",
                r.fps);
    bool any = false;
    for (std::size_t k = 0; k < r.throughput.size(); ++k) {
        const ThroughputRow &t = r.throughput[k];
        const double goal = realtimeGoal(t.width, t.height);
        bool first = true;
        for (std::size_t j = 0; j < k; ++j)
            if (r.throughput[j].width == t.width && r.throughput[j].height == t.height)
                first = false;
        if (goal <= 0.0 || !first)
            continue;
        any = true;
        const ThroughputRow *worst = &t;
        for (const ThroughputRow &u : r.throughput)
            if (u.width == t.width && u.height == t.height &&
                u.decodeCpuRealtime < worst->decodeCpuRealtime)
                worst = &u;
        std::printf("  %s >= %.0fx: %s: %.1fx on CPU time (%s file); %.1fx on the wall clock\n",
                    sizeText(t.width, t.height).c_str(), goal,
                    worst->decodeCpuRealtime >= goal ? "met" : "NOT met", worst->decodeCpuRealtime,
                    worst->preset.c_str(), worst->decodeRealtime);
    }
    if (!any)
        std::printf("  (no goal for the sizes measured: goals are for 720x486 and 1920x1080)\n");
}

bool writeReport(const MediaBenchReport &r, const std::string &dir, std::string &error,
                 std::string &note)
{
    namespace fs = std::filesystem;
    if (!platform::createReportFolder(dir, "cannot create " + dir, error))
        return false;
    const fs::path base(dir);
    const std::string throughputCsv = (base / "media_throughput.csv").string();
    const std::string rateCsv = (base / "rate_accuracy.csv").string();
    {
        platform::ReportFile f(throughputCsv); // close() reports a failed open as well
        f.print("size,preset,frames,color_kbps,depth_kbps,encode_fps,encode_cpu_fps,"
                "decode_fps,decode_cpu_fps,decode_median_ms,decode_p99_ms,decode_realtime_x,"
                "decode_cpu_realtime_x,goal_x,goal_met\n");
        for (const ThroughputRow &t : r.throughput) {
            const double goal = realtimeGoal(t.width, t.height);
            f.print("%s,%s,%zu,%.1f,%.1f,%.2f,%.2f,%.1f,%.1f,%.3f,%.3f,%.2f,%.2f,%g,%s\n",
                    sizeText(t.width, t.height).c_str(), t.preset.c_str(), t.frames, t.colorKbps,
                    t.depthKbps, t.encodeFps, t.encodeCpuFps, t.decodeFps, t.decodeCpuFps,
                    t.decodeMedianMs, t.decodeP99Ms, t.decodeRealtime, t.decodeCpuRealtime, goal,
                    goal <= 0.0 ? "" : (t.decodeCpuRealtime >= goal ? "yes" : "no"));
        }
        if (!closeReport(f, throughputCsv, error))
            return false;
    }
    {
        platform::ReportFile f(rateCsv);
        f.print("depth,crf,depth_kbps,psnr_db,force_rms_n,force_max_n,releases,pop_throughs,"
                "force_rms_no_safety_n,force_max_no_safety_n,press_rms_n,press_max_n,"
                "force_ref_rms_n,updates\n");
        for (const RateRow &q : r.rate)
            f.print("%s,%s,%.2f,%s,%.6f,%.6f,%ld,%ld,%.6f,%.6f,%.6f,%.6f,%.6f,%zu\n",
                    settingText(q).c_str(), q.lossless ? "" : std::to_string(q.crf).c_str(),
                    q.depthKbps, psnrText(q.psnrDb).c_str(), q.forceRmsN, q.forceMaxN, q.releases,
                    q.popThroughs, q.forceRmsNoSafetyN, q.forceMaxNoSafetyN, q.pressRmsN,
                    q.pressMaxN, q.forceRefRmsN, q.updates);
        if (!closeReport(f, rateCsv, error))
            return false;
    }

    const std::string script = (base / "media_bench.gp").string();
    platform::ReportFile g(script);
    g.print("set terminal pngcairo size 1000,680 noenhanced\n"
            "set datafile separator ','\n"
            "set output '%s'\n"
            "set title 'Depth rate vs accuracy, %s, x264 gray: PSNR and haptic force error "
            "vs lossless depth'\n"
            "set logscale x\nset grid\n"
            "set xlabel 'depth bitrate (kbit/s, log scale)'\n"
            "set ylabel 'depth PSNR vs lossless (dB, 8-bit nearness)'\n"
            "set y2label 'force RMS error vs lossless depth (N)'\n"
            "set ytics nomirror\nset y2tics\nset y2range [0:*]\n"
            "set key below\n"
            "plot '%s' skip 1 using 3:(strcol(4) eq 'inf' ? NaN : $4) axes x1y1 with "
            "linespoints pt 7 lw 2 title 'PSNR (dB, left)', \\\n"
            "     '' skip 1 using 3:5 axes x1y2 with linespoints pt 5 lw 2 title 'force RMS "
            "error, strokes as touch runs them (N, right)', \\\n"
            "     '' skip 1 using 3:9 axes x1y2 with linespoints pt 9 lw 2 dt 2 title 'force "
            "RMS error, strokes, safety off (N, right)', \\\n"
            "     '' skip 1 using 3:11 axes x1y2 with linespoints pt 11 lw 2 title 'force "
            "RMS error, presses (N, right)', \\\n"
            "     '' skip 1 using 3:(strcol(4) eq 'inf' ? NaN : $4):1 axes x1y1 with labels "
            "offset 0,1 font ',8' notitle\n",
            (base / "rate_vs_accuracy.png").string().c_str(),
            sizeText(r.rateWidth, r.rateHeight).c_str(), rateCsv.c_str());
    g.print("reset\nset datafile separator ','\n"
            "set terminal pngcairo size 1000,560 noenhanced\n"
            "set output '%s'\n"
            "set title 'Color + depth throughput, one core: x real time at %.0f fps "
            "(goals: decode 10x at 720x486, 2x at 1920x1080)'\n"
            "set style data histograms\nset style histogram clustered gap 1\n"
            "set style fill solid 0.8 border -1\nset boxwidth 0.9\n"
            "set logscale y\nset grid ytics\nset ylabel 'x real time (log scale)'\n"
            "set xtics rotate by -20 font ',9'\nset key below horizontal\n"
            "plot '%s' skip 1 using ($7/%g):xtic(stringcolumn(1).' '.stringcolumn(2)) "
            "title 'encode (cpu)', '' skip 1 using 13 title 'decode + pairing (cpu)', "
            "'' skip 1 using 12 title 'decode + pairing (wall)'\n",
            (base / "media_throughput.png").string().c_str(), r.fps, throughputCsv.c_str(), r.fps);
    return closeAndPlot(g, script, error, note);
}

} // namespace depthtouch::media::bench
