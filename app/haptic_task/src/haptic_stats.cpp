// HapticStats::toJson: the haptic part of the stats JSON (docs/architecture.md §4).
#include "depthtouch/haptic_task/haptic_stats.h"

#include <nlohmann/json.hpp>

namespace depthtouch::haptic_task {

namespace {

nlohmann::json summaryJson(const LatencySummary &s)
{
    return {{"p50", s.p50Us},   {"p90", s.p90Us}, {"p99", s.p99Us},
            {"p999", s.p999Us}, {"max", s.maxUs}, {"mean", s.meanUs}};
}

} // namespace

std::string HapticStats::toJson(int indent) const
{
    const nlohmann::json j = {
        {"haptic_updates", updates},
        {"haptic_run_s", runSeconds},
        {"haptic_rate_hz", servoRateHz},
        {"rendered_updates", renderedUpdates},
        {"contact_updates", contactUpdates},
        {"overruns", overruns},
        {"missed_periods", missedPeriods},
        {"wake_latency_us", summaryJson(wakeLatency)},
        {"update_time_us", summaryJson(updateTime)},
        {"period_error_us", summaryJson(periodError)},
        {"safety_releases", safetyReleases},
        {"watchdog_trips", watchdogTrips},
        {"device_losses", deviceLosses},
        {"reconnects", reconnects},
        {"device_connected", deviceConnected},
        {"telemetry_dropped", telemetryDropped},
        {"max_force_n", maxForce},
        {"max_force_step_n", maxForceStep},
        {"energy_into_hand_mj", 1e3 * energy},
        {"energy_peak_mj", 1e3 * energyPeak},
        {"device_max_force_n", deviceMaxForce},
        {"device_call_max_us", deviceCallMaxUs},
        {"force_log_lost", forceLogLost},
        {"haptic_thread", thread},
        {"haptic_page_faults",
         {{"minor", pageFaultsMinor}, {"major", pageFaultsMajor}, {"warmup", pageFaultsWarmup}}},
        {"haptic_locked_mib", lockedMiB},
    };
    return j.dump(indent);
}

} // namespace depthtouch::haptic_task
