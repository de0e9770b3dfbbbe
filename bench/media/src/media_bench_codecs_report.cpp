/// \file
/// \brief The depth codec comparison's report: the console table, depth_codecs.csv and the chart
/// (see depth_codec_bench.h).

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "depthtouch/media/depth_codec_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "media_bench_steps.h"

namespace depthtouch::media::bench {

namespace {

/// The goal of the default depth codec: 1920×1080 depth decoded at 60 fps on one thread.
constexpr double kGoalFps = 60.0;

const char *const kCodecs[] = {"h264-8", "h264-10", "hevc-10", "ffv1-16"};

/// \return the setting text of \a r: "crf18" or "lossless".
std::string crfText(const CodecRow &r)
{
    return r.lossless ? std::string("lossless") : "crf" + std::to_string(r.crf);
}

/// The row of \a codec at \a w × \a h whose CRF is nearest 18 (`encode`'s depth default), or null.
const CodecRow *decodeRow(const std::vector<CodecRow> &rows, const std::string &codec, int w, int h)
{
    const CodecRow *best = nullptr;
    for (const CodecRow &r : rows)
        if (r.codec == codec && r.width == w && r.height == h &&
            (best == nullptr || std::abs(r.crf - 18) < std::abs(best->crf - 18)))
            best = &r;
    return best;
}

/// The frame sizes of \a rows in their order.
std::vector<std::pair<int, int>> sizesOf(const std::vector<CodecRow> &rows)
{
    std::vector<std::pair<int, int>> sizes;
    for (const CodecRow &r : rows)
        if (sizes.empty() || sizes.back() != std::make_pair(r.width, r.height))
            sizes.emplace_back(r.width, r.height);
    return sizes;
}

/// depth_codecs_rate.csv: the first size's rows, one block per codec (gnuplot `index`).
bool writeRateBlocks(const std::vector<CodecRow> &rows, const std::string &path)
{
    platform::ReportFile f(path);
    const auto sizes = sizesOf(rows);
    for (const char *codec : kCodecs) {
        f.print("# %s\n", codec);
        for (const CodecRow &r : rows)
            if (r.codec == codec && std::make_pair(r.width, r.height) == sizes.front())
                f.print("%.2f,%.6f,%s,%.5f\n", r.depthKbps, r.forceRmsN, crfText(r).c_str(),
                        r.depthErrorMm);
        f.print("\n\n");
    }
    return f.close();
}

/// depth_codecs_decode.csv: per size, each codec's one-thread and all-thread decode rate.
bool writeDecodeTable(const std::vector<CodecRow> &rows, const std::string &path)
{
    platform::ReportFile f(path);
    f.print("size");
    for (const char *codec : kCodecs)
        f.print(",%s 1 thread,%s all", codec, codec);
    f.print("\n");
    for (const auto &[w, h] : sizesOf(rows)) {
        f.print("%s", sizeText(w, h).c_str());
        for (const char *codec : kCodecs) {
            const CodecRow *r = decodeRow(rows, codec, w, h);
            const double nan = std::nan("");
            f.print(",%.2f,%.2f", r ? r->decodeFps1 : nan, r ? r->decodeFpsAll : nan);
        }
        f.print("\n");
    }
    return f.close();
}

} // namespace

void printCodecs(const std::vector<CodecRow> &rows, int allThreads)
{
    if (rows.empty())
        return;
    std::printf("\ndepth codecs: depth only; decode + pairing in software on 1 and %d decoder "
                "threads (frames/s, wall clock, median run); force error = strokes and presses "
                "replayed (modified proxy graph) on the decoded vs the 16-bit source depth\n",
                allThreads);
    std::printf("%-9s %-8s %-9s %9s %9s %9s %10s %10s %9s\n", "size", "codec", "setting", "kbit/s",
                "dec fps", "dec fps", "force RMS", "force max", "height");
    std::printf("%-9s %-8s %-9s %9s %9s %9s %10s %10s %9s\n", "", "", "", "", "1 thread", "all",
                "N", "N", "RMS mm");
    for (const CodecRow &r : rows)
        std::printf("%-9s %-8s %-9s %9.1f %9.1f %9.1f %10.4f %10.3f %9.4f\n",
                    sizeText(r.width, r.height).c_str(), r.codec.c_str(), crfText(r).c_str(),
                    r.depthKbps, r.decodeFps1, r.decodeFpsAll, r.forceRmsN, r.forceMaxN,
                    r.depthErrorMm);
    std::printf("goal (the default depth codec): 1920x1080 decode >= %.0f fps on one thread:",
                kGoalFps);
    bool any = false;
    for (const char *codec : kCodecs)
        if (const CodecRow *r = decodeRow(rows, codec, 1920, 1080)) {
            std::printf(" %s %.0f (%s)", codec, r->decodeFps1,
                        r->decodeFps1 >= kGoalFps ? "met" : "not met");
            any = true;
        }
    std::printf("%s\n", any ? "" : " (1920x1080 not measured)");
}

bool writeCodecs(const std::vector<CodecRow> &rows, int allThreads, const std::string &dir,
                 std::string &error, std::string &note)
{
    namespace fs = std::filesystem;
    const fs::path base(dir);
    const std::string csv = (base / "depth_codecs.csv").string();
    {
        platform::ReportFile f(csv);
        f.print("size,codec,setting,crf,depth_kbps,decode_fps_1_thread,decode_fps_all_threads,"
                "all_threads,force_rms_n,force_max_n,height_rms_mm\n");
        for (const CodecRow &r : rows)
            f.print("%s,%s,%s,%s,%.2f,%.2f,%.2f,%d,%.6f,%.6f,%.5f\n",
                    sizeText(r.width, r.height).c_str(), r.codec.c_str(), crfText(r).c_str(),
                    r.lossless ? "" : std::to_string(r.crf).c_str(), r.depthKbps, r.decodeFps1,
                    r.decodeFpsAll, allThreads, r.forceRmsN, r.forceMaxN, r.depthErrorMm);
        if (!closeReport(f, csv, error))
            return false;
    }
    if (rows.empty())
        return true;
    const std::string rate = (base / "depth_codecs_rate.csv").string();
    const std::string decode = (base / "depth_codecs_decode.csv").string();
    if (!writeRateBlocks(rows, rate) || !writeDecodeTable(rows, decode)) {
        error = "cannot write " + rate + " or " + decode;
        return false;
    }
    const std::string script = (base / "depth_codecs.gp").string();
    platform::ReportFile g(script);
    const auto first = sizesOf(rows).front();
    g.print("set terminal pngcairo size 1900,700 noenhanced\n"
            "set datafile separator ','\n"
            "set output '%s'\n"
            "set multiplot layout 1,3 title 'Depth codecs: pick by haptic force error, bit "
            "rate and decode rate'\n",
            (base / "depth_codecs.png").string().c_str());
    // The force error and the height error against the bit rate: the same series, column 2 or 4.
    const char *panels[][4] = {
        {"Force error", "force RMS error vs 16-bit source (N)", "2", "set key below"},
        {"Surface height error", "height RMS error vs 16-bit source (mm)", "4", "unset key"}};
    for (const auto &p : panels)
        g.print("set title '%s, %s (labels: CRF)'\n"
                "set logscale x\nset grid\n%s\n"
                "set xlabel 'depth bit rate (kbit/s, log scale)'\n"
                "set ylabel '%s'\nset yrange [0:*]\n"
                "plot '%s' index 0 using 1:%s with linespoints pt 7 lw 2 lc rgb '#1f77b4' title "
                "'H.264 4:0:0 8-bit', \\\n"
                "  '' index 1 using 1:%s with linespoints pt 5 lw 2 lc rgb '#ff7f0e' title "
                "'H.264 4:0:0 10-bit', \\\n"
                "  '' index 2 using 1:%s with linespoints pt 9 lw 2 lc rgb '#2ca02c' title "
                "'HEVC Main10 4:2:0', \\\n"
                "  '' index 3 using 1:%s with points pt 13 ps 2 lc rgb '#d62728' title "
                "'FFV1 16-bit lossless', \\\n"
                "  '' index 2 using 1:%s:3 with labels offset 0,-1 font ',8' textcolor rgb "
                "'#2ca02c' notitle, \\\n"
                "  '' index 0 using 1:%s:3 with labels offset 0,1 font ',8' textcolor rgb "
                "'#1f77b4' notitle\n",
                p[0], sizeText(first.first, first.second).c_str(), p[3], p[1], rate.c_str(), p[2],
                p[2], p[2], p[2], p[2], p[2]);
    g.print("unset logscale x\nunset xlabel\nunset yrange\n"
            "set title 'Software decode (CRF 18; hatched: %d threads)'\n"
            "set style data histograms\nset style histogram clustered gap 1\n"
            "set style fill solid 0.85 border -1\nset boxwidth 0.9\n"
            "set logscale y\nset grid ytics\nset ylabel 'frames/s (log scale)'\n"
            "set key top right\n"
            "set key below horizontal maxrows 3 font ',9' samplen 2\n"
            "plot '%s' skip 1 using 2:xtic(1) fs solid lc rgb '#1f77b4' title 'H.264 8-bit, 1 "
            "thread', '' skip 1 using 3 fs pattern 4 lc rgb '#1f77b4' title 'H.264 8-bit, %d', "
            "'' skip 1 using 4 fs solid lc rgb '#ff7f0e' title 'H.264 10-bit, 1', "
            "'' skip 1 using 5 fs pattern 4 lc rgb '#ff7f0e' title 'H.264 10-bit, %d', "
            "'' skip 1 using 6 fs solid lc rgb '#2ca02c' title 'HEVC Main10, 1', "
            "'' skip 1 using 7 fs pattern 4 lc rgb '#2ca02c' title 'HEVC Main10, %d', "
            "'' skip 1 using 8 fs solid lc rgb '#d62728' title 'FFV1 16-bit, 1', "
            "'' skip 1 using 9 fs pattern 4 lc rgb '#d62728' title 'FFV1 16-bit, %d', "
            "%g with lines dt 2 lw 2 lc rgb 'black' title 'goal: 60 fps at 1920x1080, 1 thread', "
            "30 with lines dt 3 lw 2 lc rgb 'gray40' title 'real time (30 fps)'\n"
            "unset multiplot\n",
            allThreads, decode.c_str(), allThreads, allThreads, allThreads, allThreads, kGoalFps);
    return closeAndPlot(g, script, error, note);
}

} // namespace depthtouch::media::bench
