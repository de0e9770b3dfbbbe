#pragma once
/// \file
/// \brief The one priority table: scheduling policy, priority and stack size of every thread of the
/// product (PX4 wq_configurations, ArduPilot APM_LINUX_*_PRIORITY).
///
/// Priorities are relative to sched_get_priority_max(SCHED_FIFO): 0 is the maximum, -1 one below,
/// and so on, so the table does not depend on the kernel's range. Only the haptic thread is
/// SCHED_FIFO (docs/architecture.md §5, docs/style.md §4.8). It sits at max − 9 (90 on Linux),
/// above threaded IRQ handlers (50) and below the kernel's own priority-99 threads (watchdog,
/// migration helpers), which must not be starved by a runaway user thread.
///
/// Every thread of the product is started from its row (platform::RealtimeThread; the threads that
/// are not real-time with platform::kPlainThreadOptions), except two: the process's main thread,
/// which runs the control loop (kControlThread documents it), and the player's asynchronous opener
/// (app/playback/src/async_opener.*), a detached std::thread per opened clip that must outlive a
/// player that abandons it, so it is not in the table.
///
/// Thread-safety: constant data and reentrant functions. The header is C++17-clean.

#include <cstddef>
#include <cstdint>

namespace depthtouch::platform {

/// \brief Scheduling class of a thread.
enum class SchedPolicy : std::uint8_t {
    Other, ///< SCHED_OTHER: time-shared, the default for every non-real-time thread.
    Fifo ///< SCHED_FIFO: fixed priority, runs until it blocks. Needs CAP_SYS_NICE or RLIMIT_RTPRIO.
};

/// \return "SCHED_OTHER" or "SCHED_FIFO" (static string). Reentrant, real-time safe.
const char *schedPolicyName(SchedPolicy policy) noexcept;

/// \brief How one thread of the product is started.
struct ThreadConfig {
    /// Thread name shown by ps/top, at most 15 characters (pthread_setname_np limit). Static
    /// string.
    const char *name;
    /// Scheduling policy.
    SchedPolicy policy;
    /// SCHED_FIFO only: priority relative to sched_get_priority_max(SCHED_FIFO); 0 = maximum,
    /// -1 = one below, ... Ignored (must be 0) for SchedPolicy::Other.
    int relativePriority;
    /// Stack size in bytes (rounded up to a multiple of the page size when the thread is created).
    std::size_t stackBytes;
};

/// Longest thread name accepted by pthread_setname_np, without the terminating NUL.
inline constexpr std::size_t kMaxThreadNameLength = 15;

/// \return true when \a name is non-null, non-empty and at most kMaxThreadNameLength characters.
constexpr bool isValidThreadName(const char *name) noexcept
{
    if (name == nullptr || name[0] == '\0')
        return false;
    std::size_t length = 0;
    while (name[length] != '\0')
        ++length;
    return length <= kMaxThreadNameLength;
}

/// \return true when \a config has a valid name, a non-positive priority (0 for Other) and a stack
/// of at least 64 KiB.
constexpr bool isValidThreadConfig(const ThreadConfig &config) noexcept
{
    return isValidThreadName(config.name) && config.relativePriority <= 0 &&
           (config.policy == SchedPolicy::Fifo || config.relativePriority == 0) &&
           config.stackBytes >= 64 * 1024;
}

/// Haptic task: 1 kHz (up to 4 kHz) proxy update and device I/O. The only SCHED_FIFO thread.
inline constexpr ThreadConfig kHapticThread{"dt-haptic", SchedPolicy::Fifo, -9, 256 * 1024};
/// Demux, decode and pairing of color and depth frames.
inline constexpr ThreadConfig kDecodeThread{"dt-decode", SchedPolicy::Other, 0, 1024 * 1024};
/// Decodes the sound, turns it by the volume and keeps the audio output's queue filled; its clock
/// is the one the picture and the haptic time follow (playback/audio_player.h).
inline constexpr ThreadConfig kAudioThread{"dt-audio", SchedPolicy::Other, 0, 1024 * 1024};
/// Texture upload, stereo drawing and presentation, paced by vsync; publishes the depth pairs. The
/// GL driver compiles its shaders on it (llvmpipe: LLVM), so it gets a default thread's stack.
inline constexpr ThreadConfig kRenderThread{"dt-render", SchedPolicy::Other, 0, 8 * 1024 * 1024};
/// Builds the meshes and colour conversions of upcoming frames while the render thread draws.
inline constexpr ThreadConfig kPrepThread{"dt-prep", SchedPolicy::Other, 0, 1024 * 1024};
/// Encodes the output recording (x264) off the render thread.
inline constexpr ThreadConfig kRecordThread{"dt-record", SchedPolicy::Other, 0, 2 * 1024 * 1024};
/// Encodes the snapshots (PNG through FFmpeg's encoder) off the render thread. libavcodec's
/// encoders want more stack than a small worker's: 4 MiB.
inline constexpr ThreadConfig kSnapshotThread{"dt-snapshot", SchedPolicy::Other, 0,
                                              4 * 1024 * 1024};
/// State machine, remote input and control socket: the process's main thread (not started from the
/// table; the row documents it and its stack is the process's).
inline constexpr ThreadConfig kControlThread{"dt-control", SchedPolicy::Other, 0, 512 * 1024};
/// Drains the haptic telemetry ring, writes the force log and reopens a lost device.
inline constexpr ThreadConfig kTelemetryThread{"dt-telemetry", SchedPolicy::Other, 0, 256 * 1024};

/// Every thread of the product, highest priority first.
inline constexpr ThreadConfig kThreadTable[] = {
    kHapticThread, kDecodeThread,   kAudioThread,   kRenderThread,    kPrepThread,
    kRecordThread, kSnapshotThread, kControlThread, kTelemetryThread,
};

namespace detail {
constexpr bool allThreadConfigsValid() noexcept
{
    for (const ThreadConfig &config : kThreadTable) {
        if (!isValidThreadConfig(config))
            return false;
    }
    return true;
}
} // namespace detail

static_assert(detail::allThreadConfigsValid(),
              "every ThreadConfig needs a name of 1..15 characters, a priority <= 0 (0 for Other) "
              "and a stack of at least 64 KiB");

/// \brief Absolute priority for sched_setscheduler/pthread_attr_setschedparam.
/// \return for SchedPolicy::Fifo, sched_get_priority_max(SCHED_FIFO) + relativePriority clamped to
/// [sched_get_priority_min, sched_get_priority_max]; for SchedPolicy::Other, 0.
/// Reentrant, real-time safe (two syscalls without side effects).
int absolutePriority(const ThreadConfig &config) noexcept;

/// \return the SCHED_* constant for \a policy. Reentrant, real-time safe.
int toSchedPolicy(SchedPolicy policy) noexcept;

} // namespace depthtouch::platform
