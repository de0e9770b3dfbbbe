/// \file
/// \brief `depthtouch bench feel`'s outputs: the table and goals on stdout, CSV and JSON, and
/// the chart of feel_chart.cpp (see feel_bench.h).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "feel_chart_internal.h"

namespace depthtouch::haptics::bench {

namespace {

void printRow(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    std::printf(
        "%-18s %-17s %3zu %7.2f %6.2f %8.1f %8.1f %7.2f %7.1f %7.3f %6.1f %6.2f %6.2f %7.2f\n",
        r.scene.c_str(), r.setting.c_str(), r.strokes, f.falseTripsPerSecond, r.realTripsPerSecond,
        f.popThroughMs, f.phantomMs, f.spikesPerSecond, r.worstSpikesPerSecond, f.rippleRms,
        100.0 * f.rippleRelative, f.maxForce, f.updateP50 * 1e6, f.updateP999 * 1e6);
}

const char *verdict(bool ok)
{
    return ok ? "met" : "NOT met";
}

/// The figures new with the stroke families, per row (table, CSV and JSON share the order).
void printFamilyRow(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    char regain[32] = "-";
    if (f.regainEvents > 0)
        std::snprintf(regain, sizeof regain, "%.0f(%zu/%zu)", f.regainMs, f.regainMissed,
                      f.regainEvents);
    std::printf("%-26s %-17s %-6s %3zu %4zu %8.1f %7.1f %4zu %6.2f %7.2f %7.2f %-12s %6.1f %6.2f "
                "%7.3f %7.3f %6.2f\n",
                r.scene.c_str(), r.setting.c_str(), r.family.c_str(), r.strokes, f.falseTrips,
                f.popThroughMs, f.phantomMs, f.longestAlternation, f.reversalSpikesPerSecond,
                f.pressedSpikesPerSecond, f.idealSpikesPerSecond, regain, f.atMaxMs, f.maxForce,
                f.energyExcessMj, f.energyMj, f.updateP999 * 1e6);
}

nlohmann::json figuresJson(const FeelFigures &f)
{
    const double ratio = f.spikeRatio();
    return {{"pressed_seconds", f.pressedSeconds},
            {"pressed_spikes", f.pressedSpikes},
            {"pressed_spikes_per_s", f.pressedSpikesPerSecond},
            {"ideal_spikes", f.idealSpikes},
            {"ideal_spikes_per_s", f.idealSpikesPerSecond},
            {"spikes_over_ideal", std::isnan(ratio) ? nlohmann::json() : nlohmann::json(ratio)},
            {"sign_reversal_spikes", f.reversalSpikes},
            {"sign_reversal_spikes_per_s", f.reversalSpikesPerSecond},
            {"ideal_sign_reversal_spikes", f.idealReversalSpikes},
            {"ideal_sign_reversal_spikes_per_s", f.idealReversalSpikesPerSecond},
            {"longest_alternating_run", f.longestAlternation},
            {"ideal_longest_alternating_run", f.idealLongestAlternation},
            {"regain_events", f.regainEvents},
            {"regain_missed", f.regainMissed},
            {"regain_ms", f.regainMs},
            {"at_max_ms", f.atMaxMs},
            {"pull_down_ms", f.pullDownMs},
            {"arrival_trips", f.arrivalTrips},
            {"covered_ms", f.coveredMs},
            {"energy_mj", f.energyMj},
            {"ideal_energy_mj", f.idealEnergyMj},
            {"energy_excess_mj",
             std::isnan(f.energyExcessMj) ? nlohmann::json() : nlohmann::json(f.energyExcessMj)},
            {"energy_excess_sideways_mj", std::isnan(f.energyExcessSidewaysMj)
                                              ? nlohmann::json()
                                              : nlohmann::json(f.energyExcessSidewaysMj)},
            {"energy_peak_mj", f.energyPeakMj},
            {"max_step_n", f.maxStepN}};
}

/// The CSV columns of figuresJson(), in order.
constexpr const char *kFamilyColumns =
    "pressed_s,pressed_spikes,pressed_spikes_per_s,ideal_spikes,ideal_spikes_per_s,"
    "spikes_over_ideal,sign_reversal_spikes,sign_reversal_spikes_per_s,longest_alternating_run,"
    "ideal_longest_alternating_run,regain_events,regain_missed,regain_ms,at_max_ms,pull_down_ms,"
    "arrival_trips,covered_ms,"
    "energy_mj,ideal_energy_mj,energy_excess_mj,energy_peak_mj,max_step_n,"
    "ideal_sign_reversal_spikes,ideal_sign_reversal_spikes_per_s,energy_excess_sideways_mj";

void writeFamilyCsv(std::ostream &c, const FeelFigures &f)
{
    const double ratio = f.spikeRatio();
    c << f.pressedSeconds << ',' << f.pressedSpikes << ',' << f.pressedSpikesPerSecond << ','
      << f.idealSpikes << ',' << f.idealSpikesPerSecond << ',';
    if (!std::isnan(ratio))
        c << ratio;
    c << ',' << f.reversalSpikes << ',' << f.reversalSpikesPerSecond << ',' << f.longestAlternation
      << ',' << f.idealLongestAlternation << ',' << f.regainEvents << ',' << f.regainMissed << ','
      << f.regainMs << ',' << f.atMaxMs << ',' << f.pullDownMs << ',' << f.arrivalTrips << ','
      << f.coveredMs << ',' << f.energyMj << ',' << f.idealEnergyMj << ',';
    if (!std::isnan(f.energyExcessMj))
        c << f.energyExcessMj;
    c << ',' << f.energyPeakMj << ',' << f.maxStepN << ',' << f.idealReversalSpikes << ','
      << f.idealReversalSpikesPerSecond << ',';
    if (!std::isnan(f.energyExcessSidewaysMj))
        c << f.energyExcessSidewaysMj;
}

nlohmann::json rowJson(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    return {{"scene", r.scene},
            {"setting", r.setting},
            {"strokes", r.strokes},
            {"seconds", f.seconds},
            {"sliding_seconds", f.slidingSeconds},
            {"updates", f.updates},
            {"trips", f.trips},
            {"real_cut_trips", f.realCutTrips},
            {"false_trips", f.falseTrips},
            {"false_trips_per_s", f.falseTripsPerSecond},
            {"real_trips_per_s", r.realTripsPerSecond},
            {"pop_through_ms", f.popThroughMs},
            {"phantom_ms", f.phantomMs},
            {"spikes", f.spikes},
            {"spikes_per_s", f.spikesPerSecond},
            {"worst_stroke_spikes_per_s", r.worstSpikesPerSecond},
            {"worst_stroke", r.worstStroke},
            {"ripple_rms_n", f.rippleRms},
            {"ripple_relative", f.rippleRelative},
            {"max_force_n", f.maxForce},
            {"update_p50_us", f.updateP50 * 1e6},
            {"update_p999_us", f.updateP999 * 1e6}};
}

void writeRowsCsv(std::ostream &c, const std::vector<FeelRow> &rows)
{
    for (const FeelRow &r : rows) {
        const FeelFigures &f = r.total;
        c << r.scene << ',' << r.setting << ',' << r.strokes << ',' << f.seconds << ','
          << f.slidingSeconds << ',' << f.trips << ',' << f.realCutTrips << ',' << f.falseTrips
          << ',' << f.falseTripsPerSecond << ',' << r.realTripsPerSecond << ',' << f.popThroughMs
          << ',' << f.phantomMs << ',' << f.spikes << ',' << f.spikesPerSecond << ','
          << r.worstSpikesPerSecond << ',' << f.rippleRms << ',' << f.rippleRelative << ','
          << f.maxForce << ',' << f.updateP50 * 1e6 << ',' << f.updateP999 * 1e6 << '\n';
    }
}

/// feel.csv, feel_strokes.csv and feel_families.csv in \a base.
bool writeFeelCsvs(const FeelReport &report, const std::filesystem::path &base, std::string &error)
{
    platform::TextReportFile c((base / "feel.csv").string(), error);
    c << "scene,setting,strokes,seconds,sliding_s,trips,real_cut_trips,false_trips,false_trips_"
         "per_s,"
         "real_trips_per_s,pop_through_ms,phantom_ms,spikes,spikes_per_s,worst_stroke_spikes_"
         "per_s,"
         "ripple_rms_n,ripple_relative,max_force_n,update_p50_us,update_p999_us\n";
    writeRowsCsv(c, report.rows);
    writeRowsCsv(c, report.totals);
    platform::TextReportFile k((base / "feel_strokes.csv").string(), error);
    k << "scene,setting,stroke,kind,family,where,trips,real_cut_trips,pop_through_ms,"
         "phantom_ms,spikes,spikes_per_s,ripple_rms_n,max_force_n,update_p999_us,"
      << kFamilyColumns << '\n';
    for (const FeelStrokeResult &r : report.strokes) {
        const FeelFigures &f = r.figures;
        k << r.scene << ',' << r.setting << ",\"" << r.stroke << "\"," << strokeKindName(r.kind)
          << ',' << strokeFamilyName(r.family) << ',' << r.where << ',' << f.trips << ','
          << f.realCutTrips << ',' << f.popThroughMs << ',' << f.phantomMs << ',' << f.spikes << ','
          << f.spikesPerSecond << ',' << f.rippleRms << ',' << f.maxForce << ','
          << f.updateP999 * 1e6 << ',';
        writeFamilyCsv(k, f);
        k << '\n';
    }
    platform::TextReportFile fam((base / "feel_families.csv").string(), error);
    fam << "scene,setting,family,strokes,false_trips,pop_through_ms,phantom_ms,max_force_n,"
           "update_p50_us,update_p999_us,"
        << kFamilyColumns << '\n';
    for (const FeelRow &r : report.familyRows) {
        const FeelFigures &f = r.total;
        fam << r.scene << ',' << r.setting << ',' << r.family << ',' << r.strokes << ','
            << f.falseTrips << ',' << f.popThroughMs << ',' << f.phantomMs << ',' << f.maxForce
            << ',' << f.updateP50 * 1e6 << ',' << f.updateP999 * 1e6 << ',';
        writeFamilyCsv(fam, f);
        fam << '\n';
    }
    const bool written = c.close();
    return k.close() && fam.close() && written;
}

/// feel.json in \a base (the folder \a dir).
bool writeFeelJson(const FeelReport &report, const std::filesystem::path &base, std::string &error)
{
    nlohmann::json rows = nlohmann::json::array();
    nlohmann::json familyRows = nlohmann::json::array();
    nlohmann::json totals = nlohmann::json::array();
    for (const FeelRow &r : report.rows)
        rows.push_back(rowJson(r));
    for (const FeelRow &r : report.familyRows) {
        nlohmann::json j = rowJson(r);
        j["family"] = r.family;
        j.update(figuresJson(r.total));
        familyRows.push_back(j);
    }
    for (const FeelRow &r : report.totals) {
        nlohmann::json j = rowJson(r);
        j.update(figuresJson(r.total));
        nlohmann::json verdicts = nlohmann::json::array();
        bool all = true;
        for (const GoalVerdict &v : judgeGoals(report.familyRows, r.setting, report.goals)) {
            verdicts.push_back(
                {{"goal", v.goal}, {"worst", v.worst}, {"where", v.where}, {"met", v.met}});
            if (!std::isnan(v.ideal))
                verdicts.back()["ideal"] = v.ideal;
            if (!v.aside.empty())
                verdicts.back()["aside"] = v.aside;
            all = all && v.met;
        }
        j["goals"] = verdicts;
        j["all_goals_met"] = all;
        for (const auto &[name, rms] : report.cleanRms)
            if (name == r.setting)
                j["clean_force_rms_n"] = std::isnan(rms) ? nlohmann::json() : nlohmann::json(rms);
        totals.push_back(j);
    }
    const FeelGoals &g = report.goals;
    const nlohmann::json doc = {{"rows", rows},
                                {"family_rows", familyRows},
                                {"totals", totals},
                                {"notes", report.notes},
                                {"replay_seconds", report.seconds},
                                {"goals",
                                 {{"false_trips", 0},
                                  {"pop_through_ms", g.maxPopThroughMs},
                                  {"phantom_ms", g.maxPhantomMs},
                                  {"longest_alternating_run", g.maxAlternation},
                                  {"sign_reversal_spikes_per_s", g.maxReversalsPerSecond},
                                  {"spikes_per_s_over_ideal", 0},
                                  {"spikes_per_s_holds_taps_presses", g.maxStillSpikesPerSecond},
                                  {"regain_ms", g.maxRegainMs},
                                  {"at_max_ms", g.maxAtMaxMs},
                                  {"pull_down_ms", g.maxPullDownMs},
                                  {"energy_excess_mj", g.maxExcessEnergyMj},
                                  {"device_max_force_n", g.deviceMaxForce}}}};
    platform::TextReportFile js((base / "feel.json").string(), error);
    js << doc.dump(2) << '\n';
    return js.close();
}

} // namespace

void printFeelReport(const FeelReport &report)
{
    std::printf("%-18s %-17s %3s %7s %6s %8s %8s %7s %7s %7s %6s %6s %6s %7s\n", "scene", "setting",
                "n", "false/s", "real/s", "pop ms", "phan ms", "spk/s", "worst", "ripl N", "ripl%",
                "max|F|", "p50us", "p99.9us");
    std::string scene;
    for (const FeelRow &r : report.rows) {
        if (!scene.empty() && r.scene != scene)
            std::printf("\n");
        scene = r.scene;
        printRow(r);
    }
    std::printf("\n");
    for (const FeelRow &r : report.totals)
        printRow(r);
    if (!report.familyRows.empty()) {
        std::printf("\nper stroke family (pop, phantom: ms summed; alt: longest alternating run, "
                    "updates; rev/s: sign-reversal spikes; spk/s: spikes pressed; ideal/s: the "
                    "ideal penalty's on the same path; regain: ms (missed/events); atmax: ms at "
                    "%.1f N without a trip; +E mJ: energy put into the hand beyond the ideal "
                    "penalty's, worst stroke; E mJ: energy put into the hand, summed)\n",
                    report.goals.deviceMaxForce);
        std::printf("%-26s %-17s %-6s %3s %4s %8s %7s %4s %6s %7s %7s %-12s %6s %6s %7s %7s %6s\n",
                    "scene", "setting", "family", "n", "fals", "pop ms", "phan ms", "alt", "rev/s",
                    "spk/s", "ideal/s", "regain ms", "atmax", "max|F|", "+E mJ", "E mJ", "p999us");
        scene.clear();
        for (const FeelRow &r : report.familyRows) {
            if (!scene.empty() && r.scene != scene)
                std::printf("\n");
            scene = r.scene;
            printFamilyRow(r);
        }
    }
    for (const std::string &n : report.notes)
        std::printf("note: %s\n", n.c_str());
    if (!report.cleanRms.empty()) {
        std::printf("\nforce RMS error against the ideal god-object on clean synthetic surfaces:");
        for (const auto &[name, rms] : report.cleanRms)
            std::printf(" %s %.3f N;", name.c_str(), rms);
        std::printf("\n");
    }
    std::printf("\ngoals, each on the WORST family x scene row of a setting:\n");
    for (const FeelRow &t : report.totals) {
        const std::vector<GoalVerdict> v = judgeGoals(report.familyRows, t.setting, report.goals);
        std::size_t met = 0;
        for (const GoalVerdict &x : v)
            met += x.met ? 1u : 0u;
        std::printf("  %s: %zu of %zu goals met\n", t.setting.c_str(), met, v.size());
        for (const GoalVerdict &x : v) {
            char ideal[32] = "";
            if (!std::isnan(x.ideal))
                std::snprintf(ideal, sizeof ideal, " (ideal's %.3g)", x.ideal);
            std::printf("    %-40s worst %9.2f at %-36s %s%s%s\n", x.goal.c_str(), x.worst,
                        x.where.c_str(), verdict(x.met), ideal, x.aside.c_str());
        }
    }
}

/// feel_dump/<key>.csv for every stroke with a kept log (see writeFeelOutputs()).
bool writeStrokeLogs(const FeelReport &report, const std::filesystem::path &base,
                     std::string &error)
{
    for (const FeelStrokeResult &r : report.strokes) {
        if (r.log.empty())
            continue;
        std::string name = r.key();
        for (char &ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch)))
                ch = '_';
        std::error_code ec;
        std::filesystem::create_directories(base / "feel_dump", ec);
        platform::TextReportFile f((base / "feel_dump" / (name + ".csv")).string(), error);
        f << "t_s,hip_x_mm,hip_y_mm,hip_z_mm,proxy_x_mm,proxy_y_mm,proxy_z_mm,fx_n,fy_n,fz_n,"
             "surface_z_mm,held_z_mm,surface_rise_mm,ideal_n,tripped,cut,pressed,"
             "reach_surface_z_mm,ideal_fx_n,ideal_fy_n,ideal_fz_n,state,ball_ideal_fx_n,"
             "ball_ideal_fy_n,ball_ideal_fz_n\n";
        for (const FeelSample &w : r.log)
            f << w.t << ',' << w.hip.x * 1e3 << ',' << w.hip.y * 1e3 << ',' << w.hip.z * 1e3 << ','
              << w.proxy.x * 1e3 << ',' << w.proxy.y * 1e3 << ',' << w.proxy.z * 1e3 << ','
              << w.force.x << ',' << w.force.y << ',' << w.force.z << ',' << w.surfaceZ * 1e3 << ','
              << w.heldSurfaceZ * 1e3 << ',' << w.surfaceRise * 1e3 << ',' << w.idealForce << ','
              << w.released << ',' << w.surfaceCut << ',' << w.pressed << ','
              << w.reachSurfaceZ * 1e3 << ',' << w.idealPenalty.x << ',' << w.idealPenalty.y << ','
              << w.idealPenalty.z << ',' << (w.state != nullptr ? w.state : "") << ','
              << w.ballIdealPenalty.x << ',' << w.ballIdealPenalty.y << ',' << w.ballIdealPenalty.z
              << '\n';
        if (!f.close())
            return false;
    }
    return true;
}

bool writeFeelOutputs(const FeelReport &report, const std::string &dir, std::string &error,
                      std::string &note)
{
    namespace fs = std::filesystem;
    const fs::path base(dir);
    if (!platform::createReportFolder(dir, "cannot create " + dir, error))
        return false;
    if (!writeFeelCsvs(report, base, error) || !writeFeelJson(report, base, error) ||
        !writeStrokeLogs(report, base, error))
        return false;
    if (!writeChartScript(report, base, error))
        return false;
    const platform::PlotStatus plot = platform::runGnuplot((base / "feel.gp").string());
    std::filesystem::remove(base / "feel_vs_speed.png");
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV and JSON written";
    return true;
}

} // namespace depthtouch::haptics::bench
