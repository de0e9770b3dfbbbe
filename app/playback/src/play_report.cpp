/// \file
/// \brief The stats JSON and summary of `depthtouch play`: see play_report.h.

#include "depthtouch/playback/play_report.h"

#include <cstdio>

namespace depthtouch::playback {

namespace {

/// Adds the player's own figures (frames, render, level of detail) to \a j.
void addPlaybackStats(nlohmann::json &j, const PlaybackStats &ps)
{
    j["frames_decoded"] = ps.receiver.colorFrames + ps.receiver.depthFrames;
    j["frames_received"] = ps.framesReceived;
    j["frames_presented"] = ps.framesPresented;
    j["frames_dropped"] = ps.framesDropped;
    j["frames_late"] = ps.framesLate;
    j["late_ms_max"] = ps.lateMsMax;
    j["frames_concealed"] = ps.receiver.framesConcealed;
    j["decode_errors"] = ps.receiver.decodeErrors;
    j["zero_copy"] = ps.zeroCopy;
    j["color_frames_dmabuf"] = ps.receiver.colorFramesZeroCopy;
    j["color_frames_hardware"] = ps.receiver.colorFramesHardware;
    j["depth_frames_hardware"] = ps.receiver.depthFramesHardware;
    j["color_frames_imported"] = ps.colorFramesImported;
    j["color_frames_dmabuf_uploaded"] = ps.colorFramesDmaBufUploaded;
    j["depth_pairs_published"] = ps.depthPairsPublished;
    // The material track (docs/materials.md): frames decoded, depth frames that held an older
    // material frame, depth frames with none at or before them, damaged frames skipped.
    j["material_frames"] = ps.receiver.materialFrames;
    j["material_held"] = ps.receiver.materialHeld;
    j["material_missing"] = ps.receiver.materialMissing;
    j["material_damaged"] = ps.receiver.materialDamaged;
    j["render_ms_p50"] = ps.renderMsP50;
    j["render_ms_p99"] = ps.renderMsP99;
    j["mesh_triangles_p50"] = ps.meshTrianglesP50;
    j["lod_budget_blocks"] = ps.lodBudget;
    j["frames_lod_limited"] = ps.framesLodLimited;
    j["presented_fps"] = ps.presentedFps;
    j["playing_s"] = ps.playingSeconds;
    j["tune_in_s"] = ps.tuneInSeconds;
    j["seeks"] = ps.seeks;
    j["snapshots_written"] = ps.snapshotsWritten;
    j["frames_recorded"] = ps.framesRecorded;
    j["frames_prepared_ahead"] = ps.framesPreparedAhead;
    j["audio_underruns"] = ps.audioUnderruns;
    j["audio_delay_ms"] = ps.audioDelayMs;
    j["av_offset_ms_p50"] = ps.avOffsetMsP50;
    j["av_offset_ms_p99"] = ps.avOffsetMsP99;
    if (!ps.audioLost.empty())
        j["audio_lost"] = ps.audioLost;
}

/// Prints the haptic task's lines of the summary.
void printHapticSummary(const haptic_task::HapticStats &hs, double deviceMaxForce)
{
    std::printf("  haptic thread     %s\n", hs.thread.c_str());
    // The watchdog's share of the releases (a missed deadline, a device time-out) is the
    // machine's or the device's, not the renderer's: said apart, as the GStreamer elements do.
    std::printf("  haptic updates    %llu (%llu in contact), %llu overruns, %llu safety "
                "releases (%llu by the watchdog)\n",
                static_cast<unsigned long long>(hs.updates),
                static_cast<unsigned long long>(hs.contactUpdates),
                static_cast<unsigned long long>(hs.overruns),
                static_cast<unsigned long long>(hs.safetyReleases),
                static_cast<unsigned long long>(hs.watchdogTrips));
    std::printf("  wake latency      p50 %.1f us, p99 %.1f us; update time p50 %.2f us, p99 "
                "%.2f us\n",
                hs.wakeLatency.p50Us, hs.wakeLatency.p99Us, hs.updateTime.p50Us,
                hs.updateTime.p99Us);
    std::printf("  page faults       %llu minor, %llu major on the haptic thread after its "
                "warm-up (%llu in it); %.1f MiB locked for it\n",
                static_cast<unsigned long long>(hs.pageFaultsMinor),
                static_cast<unsigned long long>(hs.pageFaultsMajor),
                static_cast<unsigned long long>(hs.pageFaultsWarmup), hs.lockedMiB);
    std::printf(
        "  max force         %.2f N (device maximum %.2f N), largest step %.2f N per update\n",
        hs.maxForce, deviceMaxForce, hs.maxForceStep);
    std::printf("  energy            %.2f mJ put into the hand at the device, at most %.2f mJ at "
                "any time (passivity observer)\n",
                1e3 * hs.energy, 1e3 * hs.energyPeak);
}

} // namespace

nlohmann::json playStatsJson(const std::string &url, const PlayRunFigures &run)
{
    const PlaybackInfo &info = *run.info;
    nlohmann::json j =
        run.haptic ? nlohmann::json::parse(run.haptic->toJson()) : nlohmann::json::object();
    j["url"] = url;
    j["mode"] = info.mode;
    j["depth_size"] = {info.depthWidth, info.depthHeight};
    j["color_size"] = {info.colorWidth, info.colorHeight};
    j["output_size"] = {info.outputWidth, info.outputHeight};
    j["fps"] = info.fps;
    j["display"] = run.display;
    j["haptic_device"] = run.hapticDevice;
    // null without a remote, as the control socket's remote-connected is unavailable then
    j["remote_connected"] =
        run.remoteConnected ? nlohmann::json(*run.remoteConnected) : nlohmann::json();
    j["audio_device"] = run.audioDevice;
    j["audio"] = info.audio; // the sound played ("48000 Hz 2 ch"); empty: none
    addPlaybackStats(j, run.stats);
    j["rss_mib_start"] = run.rssStart;
    j["rss_mib_after_5s"] = run.rssAfterWarmup;
    j["rss_mib_end"] = run.rssEnd;
    j["locked_mib"] = run.lockedMiB;
    j["notes"] = info.notes;
    j["final_state"] = run.finalState;
    if (!run.failure.empty())
        j["error"] = run.failure;
    return j;
}

void printPlaySummary(const std::string &url, const PlayRunFigures &run, const std::string &record,
                      const std::string &forceLog, const std::string &statsFile)
{
    const PlaybackInfo &info = *run.info;
    const PlaybackStats &ps = run.stats;
    std::printf("DepthTouch play: %s (%s, %dx%d depth at %.3g fps) on %s, haptics %s\n",
                url.c_str(), info.mode.c_str(), info.depthWidth, info.depthHeight, info.fps,
                run.display.c_str(), info.haptics ? run.hapticDevice.c_str() : "off");
    for (const std::string &n : info.notes)
        std::printf("  note              %s\n", n.c_str());
    if (!run.displayNote.empty())
        std::printf("  note              %s\n", run.displayNote.c_str());
    if (ps.receiver.materialDamaged > 0)
        std::printf(
            "  material          %llu damaged frames skipped: the material before each held "
            "(docs/materials.md)\n",
            static_cast<unsigned long long>(ps.receiver.materialDamaged));
    std::printf("  frames            %llu received, %llu presented, %llu dropped, %llu late "
                "(at most %.0f ms; %.1f fps presented; render p50 %.1f ms, p99 %.1f ms)\n",
                static_cast<unsigned long long>(ps.framesReceived),
                static_cast<unsigned long long>(ps.framesPresented),
                static_cast<unsigned long long>(ps.framesDropped),
                static_cast<unsigned long long>(ps.framesLate), ps.lateMsMax, ps.presentedFps,
                ps.renderMsP50, ps.renderMsP99);
    if (ps.framesPresented > 0)
        std::printf("  tune-in           %.2f s from the open to the first frame on screen\n",
                    ps.tuneInSeconds);
    std::printf("  decoding          color %llu of %llu frames in hardware, depth %llu of %llu "
                "(the rest in software; decoder option hwaccel)\n",
                static_cast<unsigned long long>(ps.receiver.colorFramesHardware),
                static_cast<unsigned long long>(ps.receiver.colorFrames),
                static_cast<unsigned long long>(ps.receiver.depthFramesHardware),
                static_cast<unsigned long long>(ps.receiver.depthFrames));
    if (ps.lodBudget > 0)
        std::printf("  level of detail   %.0f triangles a frame (median); %llu of %llu frames made "
                    "coarser to keep time, budget now %zu blocks\n",
                    ps.meshTrianglesP50, static_cast<unsigned long long>(ps.framesLodLimited),
                    static_cast<unsigned long long>(ps.framesPresented), ps.lodBudget);
    if (!info.audio.empty())
        std::printf("  sound             %s on %s: %llu underruns; A/V offset median %+.1f ms, "
                    "p99 %.1f ms; device queue %.0f ms%s%s\n",
                    info.audio.c_str(), run.audioDevice.c_str(),
                    static_cast<unsigned long long>(ps.audioUnderruns), ps.avOffsetMsP50,
                    ps.avOffsetMsP99, ps.audioDelayMs, ps.audioLost.empty() ? "" : "; ",
                    ps.audioLost.c_str());
    if (run.haptic)
        printHapticSummary(*run.haptic, run.deviceMaxForce);
    std::printf("  memory            %.1f MiB resident at start, %.1f MiB at the end; %.1f MiB "
                "locked\n",
                run.rssStart, run.rssEnd, run.lockedMiB);
    if (!record.empty())
        std::printf("  recording         %s (%llu frames)\n", record.c_str(),
                    static_cast<unsigned long long>(ps.framesRecorded));
    if (!forceLog.empty() || !statsFile.empty())
        std::printf("  files             %s%s%s\n", forceLog.c_str(),
                    !forceLog.empty() && !statsFile.empty() ? ", " : "", statsFile.c_str());
}

} // namespace depthtouch::playback
