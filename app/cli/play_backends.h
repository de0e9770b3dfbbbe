#pragma once
/// \file
/// \brief How a player of `play`'s options checks its outputs, opens its backends and makes its
/// pipeline: the one path of `depthtouch play` (cmd_play.cpp) and of libdepthtouch's player thread
/// (lib/src/player_thread.cpp). The display, the haptic device, the remote and the sound output
/// come from the backend table (drivers/backends.h), the decoder and the source names are checked,
/// and playback::Playback is made on them. A failure comes back as data (which part, its one line,
/// whether it is bad input), which each caller turns into its own outcome (play's one line and
/// exit code, the library's log line and DT_ERROR_* code): nothing here prints or logs.
///
/// Compiled into dt_cli_play_backends, which calls drivers:: and so is linked only by the
/// executable and the shared library (docs/architecture.md §2).
/// Thread-safety: reentrant; what openPlayer() makes is used on the thread that runs the player.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/output_paths.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"
#include "play.h"

namespace depthtouch::cli {

/// How messages name the sound output's file (the `wav` backend's path=).
inline constexpr const char *kWavOutputOption = "--audio-device-options path";

/// \brief Checks the output paths of \a opt without changing anything: --record, --force-log,
/// --av-log, --stats, the sound output's file, --snapshot-dir (platform/output_paths.h), and with
/// \a distinctFromInputs that no output names the input, --config or another output (by file
/// identity). \return the first check that failed (exitCode 1: an output that would be lost, 2: bad
/// input; its message the one line), else a usable one (exitCode platform::kOutputUsable).
platform::OutputPathCheck checkPlayOutputs(const PlayOptions &opt, bool distinctFromInputs);

/// The part of a player that could not be opened.
enum class PlayPart : std::uint8_t {
    Display,
    HapticDevice,
    RemoteInput,
    AudioOutput,
    VideoDecoder, ///< Its name and options, checked; decoders are made per open.
    MediaSource,  ///< Its name and options, checked; sources are made per open.
    Playback,     ///< playback::Playback::create() on the backends.
    ControlSocket ///< --control's socket (PlayerCore::open()).
};

/// \brief Why openPlayer() failed.
struct PlayOpenFailure {
    PlayPart part = PlayPart::Playback;
    /// The one line: the backend table's report (hal::SelectionReport::message), or the
    /// Playback's error (Error::what).
    std::string message;
    /// Bad input: a name or an option at fault (Errc::InvalidArgument), and any decoder or
    /// source that cannot be made now. Else the device or the system failed.
    bool badInput = false;
    Error error; ///< The error that failed: the backend's, the Playback's or the socket's.
};

/// \brief The backends a player plays on, and which of the names given were chosen.
struct PlayBackends {
    std::unique_ptr<hal::Display> display;
    std::unique_ptr<hal::HapticDevice> device; ///< Also with `none` (a device that is not there).
    /// Null with --remote none, or a list that fell back to `none`.
    std::unique_ptr<hal::RemoteInput> remote;
    std::unique_ptr<hal::AudioOutput> audio; ///< Null with --no-audio or --audio-device none.
    hal::SelectionReport displayReport;
    hal::SelectionReport hapticReport;
    hal::SelectionReport audioReport;

    /// True when the haptic backend chosen is `none`: the player plays without haptics.
    [[nodiscard]] bool noDevice() const { return hapticReport.chosen == "none"; }
};

/// \brief A player with its pipeline: the Playback is destroyed before its backends.
struct OpenedPlayer {
    PlayBackends backends;
    std::unique_ptr<playback::Playback> playback; ///< Set when openPlayer() succeeded.
};

/// \brief One backend openPlayer() has just opened (before it opens the next).
struct OpenedBackend {
    drivers::BackendKind kind; ///< Display, HapticDevice, RemoteInput or AudioOutput.
    std::string_view names;    ///< The option's list of names, e.g. "falcon,none".
    const hal::SelectionReport &report;
    bool awaitingDevice = false; ///< Its device is not plugged in yet and is waited for.
};

/// Called by openPlayer() for each backend it keeps, in the order they open.
using OnBackendOpened = std::function<void(const OpenedBackend &)>;

/// \brief A source the caller feeds itself (the GStreamer element depthtouchsink: its pads):
/// openPlayer() makes each open's media source with makeSource instead of --source's backend, and
/// a pause in the frames is not a live sender that fell silent (a paused pipeline sends none).
/// With masterClock, the media follows the caller's clock (the pipeline's running time: the PTS
/// makeSource's frames carry) instead of the player's own (playback::PlaybackHal::masterClock).
struct PlayerFeed {
    std::function<Result<std::unique_ptr<hal::MediaSource>>()> makeSource;
    std::function<playback::MasterClock()> masterClock;
};

/// \brief Opens the backends of \a opt as `play` does, on \a clock (which must outlive them):
/// the display, the haptic device and the remote (waited for when --idle: hot-plug), the sound
/// output (unless --no-audio or `none`); checks the decoder and the source (made per open); then
/// makes the Playback with the config of \a opt (landPlayOptions()), which plays without haptics
/// on the `none` device. \a opened (may be empty) hears of each backend kept as it opens. A
/// display already in out.backends.display is used instead of --display's (libdepthtouch's render
/// API, lib/src/host_frames.h). With \a feed (may be null), its source replaces --source's
/// (PlayerFeed).
/// \return nullopt with the player in \a out, or the first failure (\a out holds what opened).
std::optional<PlayOpenFailure> openPlayer(const PlayOptions &opt, platform::Clock &clock,
                                          OpenedPlayer &out, const OnBackendOpened &opened = {},
                                          const PlayerFeed *feed = nullptr);

/// \brief The state machine's settings of \a opt: its url, loop, --idle (a live address that fell
/// silent is opened again), stereo mode, stiffness (N/m), volume (%) and mute; the default keys.
player::PlayerSettings playerSettings(const PlayOptions &opt);

} // namespace depthtouch::cli
