#pragma once
/// \file
/// \brief What `depthtouch play` reports at the end of a run: the stats JSON (docs/architecture.md
/// §4) and the summary on stdout. Thread-safety: main thread only.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/playback/playback.h"

namespace depthtouch::playback {

/// \brief What one run of the player gave: the player's figures and the run's own.
struct PlayRunFigures {
    const PlaybackInfo *info = nullptr;             ///< The opened input (never null).
    PlaybackStats stats;                            ///< The player's counters.
    std::optional<haptic_task::HapticStats> haptic; ///< The haptic task's, when it ran.
    std::string display;                            ///< The display backend chosen.
    /// A line for the summary when the display fell back to drawing offscreen, or empty.
    std::string displayNote;
    std::string hapticDevice; ///< The haptic device backend chosen.
    /// The remote's input device at the end: there, waited for (not plugged in, or lost), or no
    /// remote (player::StateMachine::remoteConnected()).
    std::optional<bool> remoteConnected;
    std::string audioDevice;     ///< The sound output backend chosen; empty: none (--no-audio).
    double deviceMaxForce = 0.0; ///< Its maximum force, N.
    double rssStart = -1.0;      ///< Resident memory, MiB (−1: unknown).
    double rssAfterWarmup = -1.0;
    double rssEnd = -1.0;
    /// Locked memory (VmLck of /proc/self/status), MiB: the larger of the samples after 5 s and at
    /// the end (−1: unknown). The haptic thread's own share is HapticStats::lockedMiB.
    double lockedMiB = -1.0;
    std::string finalState; ///< The player's state at the end.
    std::string failure;    ///< Why the player ended in Error (empty: it did not).
    /// What a file sound output (`wav`) lost (hal::AudioOutput::lostOutput()); empty: nothing.
    std::string audioOutputLost;
};

/// \return the stats JSON of a run of \a url.
nlohmann::json playStatsJson(const std::string &url, const PlayRunFigures &run);

/// \brief Prints the summary of a run of \a url on stdout (with its recording, force log and stats
/// files, when given).
void printPlaySummary(const std::string &url, const PlayRunFigures &run, const std::string &record,
                      const std::string &forceLog, const std::string &statsFile);

} // namespace depthtouch::playback
