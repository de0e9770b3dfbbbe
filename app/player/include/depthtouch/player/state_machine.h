#pragma once
/// \file
/// \brief The player's state machine: states, the actions it asks the pipeline to carry out, the
/// events it reports, and the command handlers of the command table (command.h).
///
/// \verbatim
///            play, toggle-pause            opened                pause, toggle-pause
///   Idle ───────────────────────► Opening ───────► Playing ─────────────────────────► Paused
///   Stopped ────────────────────►    │               ▲   ◄─────────────────────────    │
///   Error ──────────────────────►    │               │       play, toggle-pause        │
///                                    │     seek, recenter, end of stream with loop:    │
///                                    │     state kept (Playing stays Playing, Paused   │
///                                    │     stays Paused)                               │
///   stop (Opening, Playing, Paused, Error), end of stream without loop, a silent live stream
///   ──► Stopped
///   open failed, any action failing (Io, NoDevice, ...), onFailure() ──► Error
///   quit (any state): stops when active, then every command is refused
/// \endverbatim
///
/// Rules: a command that is not valid in the current state (its CommandSpec::validIn) is refused
/// with a reason and has no effect: no PlayerActions call, no state or setting change, no event.
/// A valid command calls at most one action; when it succeeds the new state and settings are taken
/// and listeners are told. When the action fails with a *refusal* (Errc InvalidArgument,
/// NotSupported, InvalidState or Busy: the pipeline promises it changed nothing) the command is
/// refused with the action's reason and nothing changes; any other failure (Io, NoDevice, ...)
/// moves the machine to Error with that reason. After quit every command is refused.
///
/// Thread-safety: thread-bound (the main thread). Listeners are called synchronously on that
/// thread; a listener must not send commands from its callback (such a command is refused).
/// Design: docs/architecture.md §5 (main thread), docs/style.md §7.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/player/command.h"
#include "depthtouch/player/key_bindings.h"
#include "depthtouch/options/option_range.h"

namespace depthtouch::player {

/// \brief What the state machine asks the player pipeline to do (implemented by `play`; by a fake
/// in tests).
///
/// Each call returns when the pipeline has carried it out (or started it, for open()). Errors with
/// code InvalidArgument, NotSupported, InvalidState or Busy mean "refused, nothing changed"; other
/// codes mean the pipeline failed. Called on the state machine's thread only.
class PlayerActions {
public:
    virtual ~PlayerActions() = default;

    /// Starts opening \a url (a path or stream URL). Completion is reported later through
    /// StateMachine::onOpened() or onOpenFailed() (possibly before open() returns is not allowed:
    /// report after it returned).
    [[nodiscard]] virtual Result<void> open(std::string_view url) = 0;
    /// Starts presenting video and running haptics from the current position (after open).
    [[nodiscard]] virtual Result<void> startPlayback() = 0;
    /// Freezes video and media time; the haptic surface stays touchable.
    [[nodiscard]] virtual Result<void> pause() = 0;
    /// Continues after pause().
    [[nodiscard]] virtual Result<void> resume() = 0;
    /// Stops playback and releases the stream; a later open() starts again.
    [[nodiscard]] virtual Result<void> stop() = 0;
    /// Seeks by \a seconds from the current position (Relative) or to \a seconds (Absolute).
    /// Flushes the decoders and re-seats the haptic surface without a force kick; keeps the
    /// paused/playing condition.
    [[nodiscard]] virtual Result<void> seek(double seconds, SeekMode mode) = 0;
    /// Starts the stream again from its beginning at its end, with loop on: a seek to 0 that is
    /// no viewer's command (nothing is shown for it on screen, as mpv's --loop-file). The default
    /// is seek(0, Absolute).
    [[nodiscard]] virtual Result<void> restartForLoop() { return seek(0.0, SeekMode::Absolute); }
    /// Changes how the two eye views are packed.
    [[nodiscard]] virtual Result<void> setStereoMode(StereoMode mode) = 0;
    /// Turns force output on or off (off: zero force, the haptic task keeps running).
    [[nodiscard]] virtual Result<void> setHapticsEnabled(bool enabled) = 0;
    /// Sets the surface stiffness \a newtonsPerMetre (N/m), already within its one range
    /// options::kStiffness (depthtouch/options/option_range.h).
    [[nodiscard]] virtual Result<void> setStiffness(double newtonsPerMetre) = 0;
    /// Re-seats the haptic workspace centre on the surface (the proxy is released, no force kick).
    [[nodiscard]] virtual Result<void> recenter() = 0;
    /// Saves the next presented frame as a PNG snapshot. The default refuses with
    /// Errc::NotSupported (a player without snapshots).
    [[nodiscard]] virtual Result<void> snapshot()
    {
        return unexpected(Errc::NotSupported, "this player takes no snapshots");
    }
    /// Brings the on-screen display up for its time (play --osd-seconds), changing nothing else
    /// (mpv's show-progress; Kodi's OSD on OK). The default refuses with Errc::NotSupported (a
    /// player without an on-screen display).
    [[nodiscard]] virtual Result<void> showProgress()
    {
        return unexpected(Errc::NotSupported, "this player has no on-screen display");
    }
    /// Sets the volume of the sound to \a percent (0..kMaxVolume, already checked) and mutes or
    /// unmutes it; kept for the inputs opened later. The defaults refuse with Errc::NotSupported
    /// (a player without sound).
    [[nodiscard]] virtual Result<void> setVolume(double percent)
    {
        (void)percent;
        return unexpected(Errc::NotSupported, "this player has no sound");
    }
    [[nodiscard]] virtual Result<void> setMute(bool mute)
    {
        (void)mute;
        return unexpected(Errc::NotSupported, "this player has no sound");
    }
    /// Starts opening \a url again after its live stream fell silent, and keeps trying until a
    /// sender comes (a failed try is retried, not reported) or stop() or open() abandons it.
    /// Completion is reported as for open(). The default opens once, as open().
    [[nodiscard]] virtual Result<void> awaitNextSender(std::string_view url) { return open(url); }
    /// What the remote's input device now is (StateMachine::setRemoteConnected(), called when it
    /// changes): there (true), waited for or lost (false), or no remote (none); a player with an
    /// on-screen display shows it there. The default shows it nowhere.
    virtual void showRemoteConnected(std::optional<bool> connected) { (void)connected; }

    /// \name Queries (the properties time-pos, duration, percent-pos, haptic-force, contact,
    /// haptic-device-connected)
    ///@{
    /// Where the media is, s: the position of the presented frame from the stream's start, and the
    /// stream's length; NaN where unknown (nothing open; a live stream's length). The default
    /// knows neither.
    struct MediaPosition {
        double timePos = std::numeric_limits<double>::quiet_NaN();
        double duration = std::numeric_limits<double>::quiet_NaN();
    };
    [[nodiscard]] virtual MediaPosition mediaPosition() const { return {}; }
    /// The force commanded to the haptic device, |F| in N; NaN without a haptic task (nothing
    /// open, no device). The default has none.
    [[nodiscard]] virtual double hapticForce() const
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    /// Whether the haptic device is connected and answering (false: lost, or not yet plugged in
    /// where the player waits for it, hal::BackendConfig::awaitDevice); none without a haptic
    /// task (nothing open, no device). The default has none.
    [[nodiscard]] virtual std::optional<bool> hapticDeviceConnected() const { return {}; }
    ///@}

protected:
    PlayerActions() = default;
    DT_DISABLE_COPY_AND_MOVE(PlayerActions)
};

/// What a PlayerEvent reports.
enum class PlayerEventKind : std::uint8_t {
    StateChanged,      ///< state holds the new state.
    StereoModeChanged, ///< stereoMode holds the new mode.
    HapticsChanged,    ///< haptics holds the new switch.
    StiffnessChanged,  ///< stiffness holds the new value (N/m).
    LoopChanged,       ///< loop holds the new flag.
    Seeked,            ///< A seek was carried out.
    EndOfFile,         ///< The stream ended (message: "eof" or "silent").
    Error,             ///< A failure; message holds the reason (the state becomes Error).
    Quit,              ///< quit was accepted: the player should shut down.
    // mpv's file events (its JSON IPC and libmpv), for every file the playlist opens:
    StartFile,       ///< A file starts opening (playlistEntryId: its playlist entry).
    FileLoaded,      ///< It opened and plays.
    FileEnded,       ///< It ended: message is mpv's reason (eof, stop, quit, error); detail:
                     ///< for eof "eof" or "silent", for error mpv's file_error text.
    PlaybackRestart, ///< Playback (re)started: after FileLoaded, after each seek and loop.
    Idle,            ///< Nothing plays any more (a file ended and no other opens).
};

/// \return the event's name: "state", "stereo-mode", "haptics", "stiffness", "loop", "seek",
/// "end-of-stream", "error", "shutdown", "start-file", "file-loaded", "end-file",
/// "playback-restart", "idle" (static string).
const char *playerEventName(PlayerEventKind kind) noexcept;

/// \brief One event, with a snapshot of the machine after it.
struct PlayerEvent {
    PlayerEventKind kind = PlayerEventKind::StateChanged;
    PlayerState state = PlayerState::Idle;
    StereoMode stereoMode = StereoMode::SideBySide;
    bool haptics = true;
    double stiffness = 0.0; ///< N/m.
    bool loop = false;
    std::string message; ///< Error reason, end-of-file reason; empty otherwise.
    std::string detail;  ///< FileEnded: the end's detail (see PlayerEventKind::FileEnded).
    std::int64_t playlistEntryId = 0; ///< StartFile, FileEnded: mpv's playlist_entry_id.
};

/// \brief Receives the events of a StateMachine (on its thread).
class PlayerListener {
public:
    virtual ~PlayerListener() = default;
    virtual void onPlayerEvent(const PlayerEvent &event) = 0;

protected:
    PlayerListener() = default;
    DT_DISABLE_COPY_AND_MOVE(PlayerListener)
};

/// A query result: nothing, a flag, a number or a text.
using Value = std::variant<std::monostate, bool, double, std::string>;

/// \brief The result of one command.
struct CommandOutcome {
    bool accepted = false;
    std::string reason; ///< Why it was refused or failed; empty when accepted.
    Value data;         ///< Query result ("get"); monostate otherwise.

    static CommandOutcome accept(Value value = {}) { return {true, {}, std::move(value)}; }
    static CommandOutcome refuse(std::string why) { return {false, std::move(why), {}}; }
};

/// \brief Start-up settings of the machine (from options and the config file).
struct PlayerSettings {
    std::string url;   ///< What "play" opens when it names nothing.
    bool loop = false; ///< End of stream seeks to 0 and keeps playing.
    /// A live stream that fell silent is opened again at once (PlayerActions::awaitNextSender(),
    /// state Opening), so that the next sender on its address plays without a `play` command; off:
    /// it stays Stopped.
    bool reopenWhenSilent = false;
    StereoMode stereoMode = StereoMode::SideBySide;
    bool haptics = true;
    /// N/m, clamped into options::kStiffness, the range of every stiffness setting (the caller
    /// refuses a value outside it first); "stiffness +" or "-" steps by its step, 100 N/m.
    double stiffness = 800.0;
    /// The sound's start volume, %, clamped into options::kVolume (0..130); steps of 2 %.
    double volume = 100.0;
    bool mute = false;
    KeyMap keys; ///< The remote's keys (the defaults, or as key map files rebound them).
};

/// \brief The player state machine. See the file comment for the diagram and the rules.
class StateMachine {
public:
    /// \param[in] actions The pipeline; must outlive the machine.
    /// \param[in] settings Initial settings; the machine does not push them to \a actions (the
    /// player starts its pipeline with the same settings).
    StateMachine(PlayerActions &actions, PlayerSettings settings);
    ~StateMachine() = default;

    /// \brief Carries out \a command if it is valid in the current state (see the file comment).
    CommandOutcome execute(const Command &command);
    /// \brief Parses \a text (parseCommandText()) and executes it; a parse error is a refusal.
    CommandOutcome execute(std::string_view text);
    /// \return whether \a id is valid in the current state (quit not yet requested).
    [[nodiscard]] bool isValid(CommandId id) const noexcept;

    /// \name Notifications from the pipeline
    /// Each returns false when it does not apply to the current state (a late notification) and
    /// then changes nothing.
    ///@{
    /// Opening finished: starts playback (Playing), or Error when startPlayback() fails.
    bool onOpened();
    /// Opening failed: Error with \a reason. \a kind says whose the failure is: the input's
    /// (InvalidArgument, the default: a file or stream that does not open or play) or the system's
    /// (OutOfResources: a thread that could not be started), which errorKind() then answers.
    bool onOpenFailed(std::string_view reason, Errc kind = Errc::InvalidArgument);
    /// The last frame was presented (Playing or Paused): with loop, seeks to 0 and stays; without,
    /// stops (Stopped). Listeners get EndOfFile.
    bool onEndOfStream();
    /// A live stream sent nothing for a while (its sender stopped; Playing or Paused): stops
    /// (Stopped) whatever loop says, since a live stream cannot be looped. Listeners get EndOfFile
    /// with "silent". With PlayerSettings::reopenWhenSilent the machine then waits for the next
    /// sender on the same address (awaitNextSender(), Opening); without it a later `play` does.
    bool onStreamSilent();
    /// The pipeline failed while Opening, Playing or Paused (device unplugged, decode error):
    /// Error with \a reason.
    bool onFailure(std::string_view reason);
    ///@}

    /// \name Current state and settings
    ///@{
    [[nodiscard]] PlayerState state() const noexcept { return state_; }
    [[nodiscard]] StereoMode stereoMode() const noexcept { return stereoMode_; }
    [[nodiscard]] bool hapticsEnabled() const noexcept { return haptics_; }
    [[nodiscard]] double stiffness() const noexcept { return stiffness_; } ///< N/m.
    [[nodiscard]] bool loop() const noexcept { return loop_; }
    [[nodiscard]] double volume() const noexcept { return volume_; } ///< %.
    [[nodiscard]] bool muted() const noexcept { return mute_; }
    [[nodiscard]] const std::string &url() const noexcept { return url_; }
    /// mpv's playlist: its entries, and the current one from 0 (-1: none, the player is idle).
    [[nodiscard]] std::size_t playlistCount() const noexcept { return playlist_.size(); }
    [[nodiscard]] std::ptrdiff_t playlistPos() const noexcept { return current_; }
    /// The key bindings the remote and mpv's keypress use (fixed at construction).
    [[nodiscard]] const KeyMap &keyMap() const noexcept { return keys_; }
    /// The reason of the last failure (kept until the next one).
    [[nodiscard]] const std::string &errorReason() const noexcept { return errorReason_; }
    /// The kind of the last failure: the Errc of the action that failed, InvalidArgument for a
    /// failure reported without one (onFailure(), onOpenFailed() without a kind).
    [[nodiscard]] Errc errorKind() const noexcept { return errorKind_; }
    /// True once quit was accepted.
    [[nodiscard]] bool quitRequested() const noexcept { return quit_; }
    /// What the remote's input device is: there (true), waited for (false: not plugged in, with
    /// hal::BackendConfig::awaitDevice), or no remote (none). The property remote-connected.
    [[nodiscard]] std::optional<bool> remoteConnected() const noexcept { return remoteConnected_; }
    /// The control loop tells the machine what its remote is (ControlLoop, after each poll); a
    /// change is passed on to PlayerActions::showRemoteConnected() (the on-screen display).
    void setRemoteConnected(std::optional<bool> connected)
    {
        if (connected == remoteConnected_)
            return;
        remoteConnected_ = connected;
        actions_.showRemoteConnected(connected);
    }
    ///@}

    /// Adds \a listener (not owned; must outlive the machine or be removed). Setup only.
    void addListener(PlayerListener *listener);
    void removeListener(PlayerListener *listener);

private:
    friend struct CommandHandlers;

    /// Applies the result of an action: success → \a onSuccess runs and the command is accepted;
    /// refusal → refused with the action's reason; failure → Error.
    template <class F> CommandOutcome apply(const char *what, Result<void> r, F &&onSuccess);
    void setState(PlayerState state);
    void fail(std::string reason, Errc kind = Errc::InvalidArgument);
    /// The outcome of the player action \a action ("start", "stop"): \a next when \a r
    /// succeeded, else Error with the reason "ACTION failed: WHY".
    void enterOrFail(PlayerState next, const char *action, const Result<void> &r);
    void emit(PlayerEventKind kind, std::string message = {});

    /// \name The playlist and mpv's file events (state_machine_files.cpp)
    ///@{
    /// Makes \a url the whole playlist, none of it current.
    void replacePlaylist(const std::string &url);
    /// The outcome of the failed action \a r: refused (nothing changed) or Error (as apply()).
    CommandOutcome refuseOrFail(const char *what, const Result<void> &r);
    /// Stops what plays and opens entry \a index (mpv's file change). \return the outcome.
    CommandOutcome openEntry(std::size_t index);
    /// The file of the current entry starts: end-file (stop) of an active one, then start-file.
    void beginFile();
    /// The active file ended with mpv's \a reason (end-file); \a detail as in FileEnded.
    void endFile(const char *reason, std::string detail = {});
    /// The player came to rest (Stopped, Error) after a file: no entry is current; idle.
    void enterIdle();
    /// Whether quit is stopping the file (its end-file says quit, and no idle follows).
    [[nodiscard]] bool quitting() const noexcept;
    /// mpv's loadfile and playlist-next/prev (the command table's handlers).
    CommandOutcome loadFile(const Command &command);
    CommandOutcome playlistStep(const Command &command);
    /// Stopped after the stream's end (onEndOfStream without loop): the next entry opens.
    void endOfStream(const Result<void> &stopped);
    ///@}

    struct PlaylistEntry {
        std::string url;
        std::int64_t id = 0; ///< mpv's playlist_entry_id: 1, 2, ... in the order of adding.
    };
    std::vector<PlaylistEntry> playlist_;
    std::ptrdiff_t current_ = -1; ///< The current entry's index; -1: none.
    std::int64_t nextEntryId_ = 1;
    bool fileActive_ = false;         ///< start-file was sent and its end-file not yet.
    bool fileLoaded_ = false;         ///< file-loaded was sent for the active file.
    std::int64_t activeEntryId_ = 0;  ///< The active file's entry id.
    const char *endReason_ = nullptr; ///< The next end-file's reason (nullptr: stop).
    std::string endDetail_;           ///< Its detail.
    bool advancing_ = false;          ///< Another entry opens after this end: no idle.

    PlayerActions &actions_;
    std::vector<PlayerListener *> listeners_;
    PlayerState state_ = PlayerState::Idle;
    std::string url_;
    bool loop_;
    bool reopenWhenSilent_;
    StereoMode stereoMode_;
    bool haptics_;
    double stiffness_;
    double volume_; ///< %.
    bool mute_;
    KeyMap keys_;
    std::string errorReason_;
    Errc errorKind_ = Errc::InvalidArgument;
    bool quit_ = false;
    bool eofReached_ = false;             ///< The stream ended without loop (mpv's eof-reached).
    std::optional<bool> remoteConnected_; ///< setRemoteConnected(): none without a remote.
    bool notifying_ = false; ///< True while listeners run: commands from them are refused.
};

/// \return true when \a code means "refused, nothing changed" (InvalidArgument, NotSupported,
/// InvalidState, Busy) rather than a failure.
bool isRefusal(Errc code) noexcept;

} // namespace depthtouch::player
