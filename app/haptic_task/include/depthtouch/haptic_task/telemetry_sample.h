#pragma once
/// \file
/// \brief TelemetrySample and TelemetryRing: what the haptic thread hands the telemetry thread, one
/// sample per update, through a lock-free single-producer single-consumer ring
/// (docs/architecture.md §5). The haptic thread is the only producer (ServoLoop), the telemetry
/// thread or a drain under TelemetryService's mutex the only consumer.

#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

#include "depthtouch/platform/spsc_ring.h"

namespace depthtouch::haptic_task {

/// \brief One haptic update as pushed into the telemetry ring (no allocation, trivially copyable).
struct TelemetrySample {
    enum Flags : std::uint16_t {
        Rendered = 1u << 0,      ///< Device read and frames present: t, hip, proxy are meaningful.
        Contact = 1u << 1,       ///< Proxy held on the surface.
        Released = 1u << 2,      ///< Renderer force-jump safety released the proxy (paper IV.C).
        Overrun = 1u << 3,       ///< This cycle started late.
        WatchdogTrip = 1u << 4,  ///< The watchdog zeroed the force on this cycle.
        DeviceLost = 1u << 5,    ///< The device is unplugged or being reconnected.
        DeviceTimeout = 1u << 6, ///< The device did not answer this cycle.
        Clutched = 1u << 7,      ///< The clutch button is held.
        NoFrames = 1u << 8,      ///< No depth frame published yet.
    };
    double t = 0.0;                  ///< Haptic time, s (clock time − media origin).
    glm::dvec3 hip{};                ///< HIP, m, scene box.
    glm::dvec3 proxy{};              ///< Proxy after the update, m.
    glm::dvec3 force{};              ///< Force commanded to the device, N.
    std::int64_t wakeNs = 0;         ///< Clock time of the wake-up, ns since the clock's epoch.
    std::int32_t wakeLatencyNs = 0;  ///< Wake time − deadline, ns.
    std::int32_t updateNs = 0;       ///< Time from the wake-up to the command, ns.
    std::uint64_t cycle = 0;         ///< Cycle number, 1-based (gaps: samples lost to a full ring).
    std::uint32_t missedPeriods = 0; ///< Deadlines skipped by an overrun's re-sync.
    float gain = 0.0f;               ///< Enable/ramp gain in [0, 1].
    std::uint16_t flags = 0;
};

/// Capacity of the telemetry ring: 8 s at 1 kHz, drained every few milliseconds.
inline constexpr std::size_t kTelemetryCapacity = 8192;
/// The telemetry ring: written by the haptic thread (tryPush(), wait-free, a full ring drops the
/// sample and counts it), read by the telemetry side (tryPop()).
using TelemetryRing = platform::SpscRing<TelemetrySample, kTelemetryCapacity>;

} // namespace depthtouch::haptic_task
