#pragma once
/// \file
/// \brief `depthtouch play`: its options and the run, shared with `depthtouch demo` (which plays
/// the built-in scene with the simulated hand).
/// Thread-safety: main thread only.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "depthtouch/playback/playback.h"
#include "depthtouch/player/key_bindings.h"

namespace depthtouch::cli {

/// \brief The player library's defaults, where `play`'s options that land in its config start.
const playback::PlaybackConfig &playbackDefaults();

/// \brief Options of `play`, one field per row of its option table (play_options.h), which gives
/// each one's option name (also its `--config` TOML key), check, help and where it lands in
/// playback::PlaybackConfig. The initializers are the defaults.
struct PlayOptions {
    std::string url; ///< File path or stream URL.
    /// Display backend(s), comma-separated, tried in order; empty (the default): autoprobe the
    /// ones this build has, a screen when there is one (a DRM card, an X server), else offscreen,
    /// as mpv probes its video outputs.
    std::string display;
    std::string displayOptions;
    std::string haptic = "falcon,none"; ///< Haptic device backend(s).
    std::string hapticOptions;
    std::string decoder = "ffmpeg"; ///< Video decoder backend(s).
    std::string decoderOptions;     ///< Options of the decoder backend(s), e.g. drm-prime.
    std::string source = "ffmpeg";  ///< Media source backend.
    std::string sourceOptions;      ///< Options of the media source, e.g. timeout_ms=30000.
    /// Remote-control backend(s): evdev, tty, none; by default the terminal's keys when play runs
    /// in one (mpv's habit), else none.
    std::string remote = "tty,none";
    std::string remoteOptions;
    /// Sound output backend(s): alsa, wav, null, mock; none: no sound (as --no-audio).
    std::string audioDevice = "alsa,null";
    std::string audioDeviceOptions; ///< e.g. device=hw:0 (alsa), path=out.wav (wav).
    bool noAudio = false;           ///< Play without sound (mpv's --no-audio).
    double volume = playbackDefaults().audio.volume; ///< Percent, 0..130.
    bool mute = playbackDefaults().audio.mute;
    std::string stereo = "sbs"; ///< sbs, tab, anaglyph, mono, interleaved.
    double stiffness = playbackDefaults().haptics.renderer.stiffness;             ///< N/m.
    double staticFriction = playbackDefaults().haptics.renderer.staticFriction;   ///< μs.
    double dynamicFriction = playbackDefaults().haptics.renderer.dynamicFriction; ///< μd.
    double rate = playbackDefaults().haptics.servoRateHz; ///< Haptic servo rate, Hz.
    /// After a force-jump release: ramp (re-seat) or release; touch's default too.
    std::string reengage = haptics::reengageName(haptics::kCommandReengage);
    /// The haptic renderer: a name of the renderer table (haptics/renderer_table.h).
    std::string method = haptics::methodName(playbackDefaults().haptics.method);
    bool loop = false;
    double duration = 0.0; ///< s of wall time, 0: until the end of the stream.
    std::string snapshotDir;
    std::uint64_t snapshotEvery = playbackDefaults().snapshotEvery;
    std::string record; ///< Recording of the output (H.264 file).
    int recordCrf = playbackDefaults().recordCrf;
    std::string forceLog;
    std::string avLog; ///< A/V offset per presented frame with sound (CSV).
    std::string stats;
    std::string control;     ///< Control socket path.
    std::string config;      ///< TOML file read after the default ones (play_config_files.h).
    std::string inputConf;   ///< Key map file read after the default ones (mpv's input.conf).
    bool noConfig = false;   ///< Read neither the system nor the user config file (mpv's name).
    bool showConfig = false; ///< Print the settings in effect and where each came from; no play.
    std::string size;        ///< Output WxH, empty: 2·depth width × depth height.
    int meshStep = playbackDefaults().meshStep;        ///< 0: adaptive level of detail.
    double osdSeconds = playbackDefaults().osdSeconds; ///< On-screen display after a command, s.
    double lodTarget = playbackDefaults().lodTarget;   ///< Share of a refresh period drawing takes.
    double maxLateness = playbackDefaults().maxLateness; ///< Lateness a frame is still drawn with.
    bool requireRt = playbackDefaults().haptics.requireRt;
    bool idle = false;    ///< Stay up after the end / an error (control socket).
    bool quiet = false;   ///< Errors only: no state-change lines, no summary.
    bool verbose = false; ///< State changes and the log on stderr (`play` sets the log).
};

/// \brief What a run of `play` measured: the stats JSON (docs/architecture.md §4) and the exit
/// code.
struct PlayResult {
    int exitCode = 0;
    nlohmann::json stats; ///< Empty when nothing was opened.
};

/// \brief Asks a running runPlay() to quit (as SIGINT does). Thread-safe, async-signal-safe.
void requestPlayStop() noexcept;

/// \brief Runs `play` with \a options (after the config file was applied).
/// \return the result; exit code 0 (ended or quit, also after a failure the player recovered
/// from), 1 (pipeline failure, an output that could not be written, stopped while still opening),
/// 2 (bad input: an option, an input that does not open, a control socket path or an output
/// folder that cannot be used). Each failure is one line on stderr.
PlayResult runPlay(const PlayOptions &options, const player::KeyMap &keys = {});

} // namespace depthtouch::cli
