/// \file
/// \brief The option table of `depthtouch play`: see play_options.h.

#include "play_options.h"

#include <cctype>
#include <cstdio>
#include <optional>
#include <string>

#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/player/state_machine.h"
#include "depthtouch/options/option_range.h"

namespace depthtouch::cli {

namespace {

using Config = playback::PlaybackConfig;

/// Parses \a text as WxH; \return false unless both are in 16..8192 (empty: 0 × 0).
bool parseOutputSize(std::string_view text, int &w, int &h)
{
    w = h = 0;
    if (text.empty())
        return true;
    const std::string s(text);
    char x = 0;
    char extra = 0;
    return std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) == 3 && (x == 'x' || x == 'X') &&
           w >= 16 && h >= 16 && w <= Config::kMaxOutputSize && h <= Config::kMaxOutputSize;
}

/// FFmpeg stereo3d's names that say whether each eye is squeezed into its half (sbs2l, ab2l, tb2l:
/// frame-compatible) or full size (sbsl, abl, tbl); nullopt for the others (--size decides).
std::optional<bool> stereoHalves(std::string_view name)
{
    std::string n(name);
    for (char &ch : n)
        ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (n == "sbs2l" || n == "ab2l" || n == "tb2l")
        return true;
    if (n == "sbsl" || n == "abl" || n == "tbl")
        return false;
    return std::nullopt;
}

/// The check of an option whose range is its row of depthtouch/options/option_range.h, the one
/// range every entry point reads (the control socket's commands, libdepthtouch).
constexpr OptionCheck inRangeOf(const options::OptionRange &range)
{
    return inRange(range.min, range.max, range.unit);
}

bool isStereoMode(std::string_view text)
{
    return player::stereoModeFromName(text).has_value();
}

/// Every option of `play`, in `--help` order.
const OptionRow<PlayOptions> kPlayRows[] = {
    {"url",
     &PlayOptions::url,
     "File path or stream URL",
     {},
     kPositional | kCommandLineOnly}, // required unless --show-config (cmd_play.cpp)
    {"display", &PlayOptions::display, "Display backend(s): headless, x11, kms, mock"},
    {"display-options", &PlayOptions::displayOptions, "Options of the display backend"},
    {"haptic", &PlayOptions::haptic, "Haptic device backend(s): falcon, sim, mock, none"},
    {"haptic-options", &PlayOptions::hapticOptions,
     "Options of the haptic device, e.g. intent=stroke for sim"},
    {"decoder", &PlayOptions::decoder, "Video decoder backend(s)"},
    {"decoder-options", &PlayOptions::decoderOptions,
     "Options of the decoder backend(s), e.g. drm-prime (zero-copy) or pool=24"},
    {"source", &PlayOptions::source, "Media source backend"},
    {"source-options", &PlayOptions::sourceOptions,
     "Options of the media source, e.g. timeout_ms=30000 (longest blocking open or read)"},
    {"remote", &PlayOptions::remote, "Remote control backend(s): evdev, tty, none"},
    {"remote-options", &PlayOptions::remoteOptions,
     "Options of the remote, e.g. device=/dev/input/event3"},
    {"audio-device", &PlayOptions::audioDevice,
     "Sound output backend(s): alsa, wav, null, mock, none (no sound)"},
    {"audio-device-options", &PlayOptions::audioDeviceOptions,
     "Options of the sound output, e.g. device=hw:0 (alsa) or path=out.wav (wav)"},
    {.name = "no-audio",
     .field = &PlayOptions::noAudio,
     .help = "Play without sound",
     .land = [](const PlayOptions &o, Config &c) { c.audioEnabled = !o.noAudio; }},
    {.name = "volume",
     .field = &PlayOptions::volume,
     .help = "Start volume, percent; the gain is (volume/100)^3, as mpv's",
     .check = inRangeOf(options::kVolume),
     .land = [](const PlayOptions &o, Config &c) { c.audio.volume = o.volume; }},
    {.name = "mute",
     .field = &PlayOptions::mute,
     .help = "Start muted",
     .land = [](const PlayOptions &o, Config &c) { c.audio.mute = o.mute; }},
    {.name = "stereo",
     .field = &PlayOptions::stereo,
     .help = "Stereo layout: sbs, tab, anaglyph, mono, interleaved, or FFmpeg stereo3d's sbsl, "
             "sbs2l, abl, ab2l, arcc, irl",
     .check = textWhere(isStereoMode, "sbs, tab, anaglyph, mono or interleaved"),
     .land =
         [](const PlayOptions &o, Config &c) {
             c.stereoMode = *player::stereoModeFromName(o.stereo);
             if (const auto halves = stereoHalves(o.stereo))
                 c.frameCompatible = *halves;
         }},
    {.name = "stiffness",
     .field = &PlayOptions::stiffness,
     .help = "Surface stiffness",
     .check = inRangeOf(options::kStiffness),
     .land = [](const PlayOptions &o, Config &c) { c.haptics.renderer.stiffness = o.stiffness; }},
    {.name = "static-friction",
     .field = &PlayOptions::staticFriction,
     .help = "Static friction coefficient on the proxy (friction cone: the proxy holds while the "
             "tangential force is within MU times the normal force; 0: frictionless)",
     .check = inRange(0.0, haptics::RendererConfig::kMaxFriction),
     .land = [](const PlayOptions &o,
                Config &c) { c.haptics.renderer.staticFriction = o.staticFriction; }},
    {.name = "dynamic-friction",
     .field = &PlayOptions::dynamicFriction,
     .help = "Dynamic friction coefficient: a sliding proxy keeps the tangential force at MU "
             "times the normal force (usually <= the static one)",
     .check = inRange(0.0, haptics::RendererConfig::kMaxFriction),
     .land = [](const PlayOptions &o,
                Config &c) { c.haptics.renderer.dynamicFriction = o.dynamicFriction; }},
    {.name = "rate",
     .field = &PlayOptions::rate,
     .help = "Haptic servo rate",
     .check = inRangeOf(options::kServoRate),
     .land = [](const PlayOptions &o, Config &c) { c.haptics.servoRateHz = o.rate; }},
    {.name = "reengage",
     .field = &PlayOptions::reengage,
     .help = "After a force jump (scene cut): ramp (re-seat the proxy, ramp the force in) or "
             "release (paper IV.C)",
     .check = oneOf("ramp release"),
     .land =
         [](const PlayOptions &o, Config &c) {
             c.haptics.renderer.reengage =
                 o.reengage == "ramp" ? haptics::Reengage::Ramp : haptics::Reengage::Release;
         }},
    {.name = "method",
     .field = &PlayOptions::method,
     .help = "Haptic renderer, a row of the renderer table (docs/architecture.md); the "
             "baselines run with the paper's fixes off",
     .check = oneOf(haptics::rendererChoiceWords()),
     .land =
         [](const PlayOptions &o, Config &c) {
             const haptics::RendererEntry *e = haptics::findRenderer(o.method);
             if (e == nullptr) // checked before it lands (oneOf)
                 return;
             c.haptics.method = e->method;
             c.haptics.renderer.correction = e->fixes;
             c.haptics.renderer.interpolation = e->fixes;
             c.haptics.renderer.safety = e->fixes;
         }},
    {"loop", &PlayOptions::loop, "Start again at the end"},
    {.name = "duration",
     .field = &PlayOptions::duration,
     .help = "Stop after this many seconds (0: at the end)",
     .check = inRangeSaying(0.0, 7 * 24 * 3600.0, ">= 0 s")},
    {.name = "snapshot-dir",
     .field = &PlayOptions::snapshotDir,
     .help = "Folder for PNG snapshots of the output (with --snapshot-every, or on the snapshot "
             "command: remote yellow key, c)",
     .land = [](const PlayOptions &o, Config &c) { c.snapshotDir = o.snapshotDir; }},
    {.name = "snapshot-every",
     .field = &PlayOptions::snapshotEvery,
     .help = "Snapshot every N presented frames (0: only on the snapshot command)",
     .check = inRange(0, 1e6),
     .land = [](const PlayOptions &o, Config &c) { c.snapshotEvery = o.snapshotEvery; }},
    {.name = "record",
     .field = &PlayOptions::record,
     .help = "Record the output as the viewer sees it (H.264; .mkv, .mp4, .ts)",
     .land = [](const PlayOptions &o, Config &c) { c.recordPath = o.record; }},
    {.name = "record-crf",
     .field = &PlayOptions::recordCrf,
     .help = "x264 CRF of the recording",
     .check = inRange(0, 51),
     .land = [](const PlayOptions &o, Config &c) { c.recordCrf = o.recordCrf; }},
    {.name = "force-log",
     .field = &PlayOptions::forceLog,
     .help = "Force log CSV (one row per haptic update)",
     .land = [](const PlayOptions &o, Config &c) { c.haptics.forceLogPath = o.forceLog; }},
    {.name = "av-log",
     .field = &PlayOptions::avLog,
     .help = "A/V log CSV (one row per presented frame with sound: time, PTS, offset of the sound "
             "heard then, ms)",
     .land = [](const PlayOptions &o, Config &c) { c.avLogPath = o.avLog; }},
    {"stats", &PlayOptions::stats, "Stats JSON written at the end"},
    {"control", &PlayOptions::control, "Control socket path (JSON lines)"},
    {"config",
     &PlayOptions::config,
     "TOML file with any of these options, read after the system and the user file",
     {},
     kCommandLineOnly},
    {"input-conf", &PlayOptions::inputConf,
     "Key map file (mpv's input.conf: KEY command), read after the system and the user one"},
    {"no-config",
     &PlayOptions::noConfig,
     "Read no file of /etc/depthtouch or ~/.config/depthtouch (play.toml, input.conf)",
     {},
     kCommandLineOnly},
    {"show-config",
     &PlayOptions::showConfig,
     "Print the settings in effect as TOML, each with the file it came from, and exit",
     {},
     kCommandLineOnly},
    {.name = "size",
     .field = &PlayOptions::size,
     .help = "Output size WxH (default: the stereo layout's for the depth size: sbs 2WxH, tab "
             "Wx2H, others WxH; at most 3840x2160)",
     .check = textWhere(isOutputSize, "WxH, 16..8192 pixels each"),
     .land =
         [](const PlayOptions &o, Config &c) {
             parseOutputSize(o.size, c.outputWidth, c.outputHeight);
             // A display-sized output is a 3D TV's frame, unless the layout's name says.
             if (!stereoHalves(o.stereo))
                 c.frameCompatible = !o.size.empty();
         }},
    {.name = "mesh-step",
     .field = &PlayOptions::meshStep,
     .help = "Drawn mesh step (0: adaptive level of detail)",
     .land = [](const PlayOptions &o, Config &c) { c.meshStep = o.meshStep; }},
    {.name = "osd-seconds",
     .field = &PlayOptions::osdSeconds,
     .help = "On-screen display time after start and each command (0: always shown)",
     .check = inRange(0.0, 86400.0, "s"),
     .land = [](const PlayOptions &o, Config &c) { c.osdSeconds = o.osdSeconds; }},
    {.name = "lod-target",
     .field = &PlayOptions::lodTarget,
     .help = "Level of detail: share of the display's refresh period (or of the frame period, if "
             "shorter) drawing may take; the mesh is made coarser when it takes longer (0: off, "
             "full detail)",
     .check = inRange(0.0, 4.0, "refresh periods"),
     .land = [](const PlayOptions &o, Config &c) { c.lodTarget = o.lodTarget; }},
    {.name = "max-lateness",
     .field = &PlayOptions::maxLateness,
     .help = "Seconds a frame may be late and still be drawn (the next ones catch up); later ones "
             "are dropped (0: drop as soon as the next frame is due)",
     .check = inRange(0.0, Config::kMaxLateness, "seconds"),
     .land = [](const PlayOptions &o, Config &c) { c.maxLateness = o.maxLateness; }},
    {.name = "require-rt",
     .field = &PlayOptions::requireRt,
     .help = "Fail when SCHED_FIFO is refused",
     .land = [](const PlayOptions &o, Config &c) { c.haptics.requireRt = o.requireRt; }},
    {"idle", &PlayOptions::idle,
     "Stay up after the end or an error; with no file, start idle and wait for a loadfile "
     "(mpv --idle, for --control)"},
    {"quiet", &PlayOptions::quiet,
     "Nothing but errors: no state-change lines, no summary (mpv's --really-quiet)"},
    {"verbose", &PlayOptions::verbose,
     "State changes and the log (INFO and up) on stderr; without it a failure is one line"},
};

} // namespace

const playback::PlaybackConfig &playbackDefaults()
{
    static const playback::PlaybackConfig defaults;
    return defaults;
}

OptionTable<PlayOptions> playOptionTable()
{
    return kPlayRows;
}

bool isOutputSize(std::string_view text)
{
    int w = 0;
    int h = 0;
    return parseOutputSize(text, w, h);
}

std::string checkPlayOptionValues(const PlayOptions &options)
{
    return checkOptions(playOptionTable(), options);
}

playback::PlaybackConfig landPlayOptions(const PlayOptions &options)
{
    playback::PlaybackConfig config = playbackDefaults();
    landOptions(playOptionTable(), options, config);
    return config;
}

} // namespace depthtouch::cli
