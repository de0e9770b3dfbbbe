#pragma once
/// \file
/// \brief Playback: the set-top box's player pipeline behind the state machine
/// (docs/architecture.md §1 and §5): receiver (demux → decode → PTS pairing on the decode thread) →
/// depth pairs into the haptic task's lock-free handoff and color + depth into the stereo renderer
/// on the render thread, presented on a hal::Display paced by its refresh; the SCHED_FIFO haptic
/// task renders the force on the same depth frames at the servo rate.
///
/// Timing: the render thread keeps the media clock (FrameClock). When the first frame after open()
/// or a seek is on screen (after its draw: a preroll), media time = its PTS; frame i is presented
/// at origin + PTS_i (late frames whose successor is also due are skipped and counted as dropped).
/// When frame i goes on screen the render thread publishes the pair (depth i, depth i+1) to the
/// DepthHandoff (each new depth frame copied once), whose media origin is the same clock origin,
/// so the haptic time and the picture agree and the surface is interpolated between the two
/// frames at the servo rate (paper IV.B). Pausing freezes the media clock for both: the surface
/// stays touchable and holds still. A seek drops the frames queued before it, shows the first
/// frame of the new position and restarts the haptic time there keeping the proxy and the force
/// (HapticTask::requestClockRestart()): no force kick, no dip.
///
/// Level of detail: the drawn mesh's block budget follows the measured draw times
/// (render::LodController, `lodTarget` of the refresh period), so a slow renderer draws a coarser
/// surface instead of dropping frames; the haptic task always touches the full-resolution frames.
///
/// Inputs without depth play flat (2D) with haptics off, and info().notes says so; inputs without
/// color show the depth as gray.
///
/// Thread-safety: the PlayerActions calls, report(), stats() and the destructor on one thread (the
/// main thread, with the StateMachine). Internally, started from the thread table
/// (platform/thread_config.h): the render thread (kRenderThread, owns the GL context while the
/// Playback lives; from the first open), its prep worker (kPrepThread) and recorder
/// (kRecordThread); the receiver's decode thread and the haptic task's threads; and the opener's
/// threads (async_opener.h, plain threads: at most two, one of them an abandoned, interrupted
/// open).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/audio_source.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/playback/audio_player.h"
#include "depthtouch/player/state_machine.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::playback {

/// \brief Settings of a Playback (the `play` options).
struct PlaybackConfig {
    /// Largest output width and height, pixels (Playback::create and `play --size` check it).
    static constexpr int kMaxOutputSize = 8192;
    /// Largest fixed mesh step (a power of two).
    static constexpr int kMaxMeshStep = 64;
    /// Largest maxLateness, s (Playback::create and `play --max-lateness` check it).
    static constexpr double kMaxLateness = 10.0;

    receiver::ReceiverConfig receiver{};
    /// Haptic task: servo rate, renderer (stiffness N/m, scene box, fixes), force log path,
    /// SCHED_FIFO requirement. Its stiffness is the start value of setStiffness().
    haptic_task::HapticTaskConfig haptics{};
    bool hapticsEnabled = true;
    player::StereoMode stereoMode = player::StereoMode::SideBySide;
    /// Output size, pixels; 0 = twice the depth width × the depth height (side-by-side at full
    /// resolution per eye), limited to 3840 × 2160.
    int outputWidth = 0;
    int outputHeight = 0;
    /// Frame-compatible packing: each eye squeezed into its half of the frame for a 3D TV to
    /// stretch back (the broadcast convention for a display-sized output). false: each eye drawn
    /// at its own aspect (the default 2W × H output, where each half is a full-resolution eye).
    bool frameCompatible = true;
    /// Refresh rate asked of the display, Hz (0: the backend's default).
    double refreshHz = 0.0;
    /// Side-by-side snapshots: PNG of the presented frame every snapshotEvery frames into
    /// snapshotDir (empty: none; 0: only on request).
    std::string snapshotDir;
    std::uint64_t snapshotEvery = 0;
    /// Recording of the output: every presented frame, as the viewer sees it, into an H.264
    /// 4:2:0 file (MKV/MP4/TS by extension; needs a display with a GL context). PTS is the
    /// presentation time since the first recorded frame (pauses and seeks show as they happened).
    /// Empty: none.
    std::string recordPath;
    int recordCrf = 20;                    ///< x264 CRF of the recording.
    std::string recordPreset = "veryfast"; ///< x264 preset of the recording.
    bool osd = true; ///< On-screen display (state, haptics switch, force bar).
    /// Seconds the on-screen display stays up after playback starts and after each command (as a
    /// TV's does); it stays up while paused. 0 = always shown (when osd).
    double osdSeconds = 4.0;
    bool avatar = true; ///< Proxy sphere and HIP marker.
    /// Mesh step of the drawn surface: 0 = adaptive level of detail, else a fixed power of two.
    int meshStep = 0;
    /// Level-of-detail control (meshStep 0): the share of the display's refresh period (of the
    /// frame period when that is shorter) that drawing a frame may take; the mesh's block budget
    /// follows the measured draw times (render::LodController). Within one refresh, a frame that
    /// comes late after a stall is caught up at the next refresh; 30 fps on a 60 Hz display
    /// thus gets 15 ms at 0.9. 0 = off (the mesh always at its full tolerance).
    double lodTarget = 0.9;
    /// Longest time a frame may be taken to be drawn after its time, seconds. A frame whose
    /// successor is due too is still drawn while it is less late than this, and the frames after
    /// it catch up (a frame drawn within one refresh period shows at the next refresh). A stall of
    /// the machine then delays a few frames instead of skipping one: a skipped frame is a jerk in
    /// the motion, a picture up to this late for a moment is not. Later frames are skipped
    /// (counted as dropped) until the player is back in time, and so are late frames once no
    /// frame has been on time for 3 × maxLateness (a machine too slow to catch up, or 60 fps on a
    /// 60 Hz display, where no refresh can be saved). 0 (the default): skip a frame as soon as its
    /// successor is due. Catching up needs frames drawn well within a refresh period: with the
    /// level of detail at 0.9 of it on llvmpipe, 0.1 s gave more late frames and, under heavy
    /// host steal, more drops than 0 (README, "Real input").
    double maxLateness = 0.0;
    /// A live stream (a source that cannot seek: a network stream, a FIFO) from which nothing came
    /// for this long, seconds (at least 4 frame periods), while it plays is reported silent
    /// (player::StateMachine::onStreamSilent(): "end-file" "silent", then Stopped, or Opening
    /// while it waits for the next sender) instead of waiting for the source's I/O time-out. The
    /// receiver's buffers hold a few tenths of a second of frames on top: the report comes
    /// about 1.6 s after a 30 fps sender stopped. 0: never. An adaptive input (an HLS ladder,
    /// hal::MediaInfo::renditions) is not watched: a slow link delivers it a segment at a time.
    double liveSilenceSeconds = 1.0;
    /// Sound (`play --no-audio` turns it off): the input's first audio stream through
    /// PlaybackHal::audioOutput, as the master clock (audio_player.h). Inputs that cannot seek (a
    /// live stream, a FIFO) play without sound: their audio is not read twice.
    bool audioEnabled = true;
    AudioPlayerConfig audio{}; ///< The start volume and mute, the device's queue.
    /// A/V log (`play --av-log`): a CSV written by close(), one row per presented frame while
    /// sound played (the first 65536): `time_s` (s from the first row, the player's clock),
    /// `pts_s` (the frame's PTS, s), `offset_ms` (the media time heard when it was presented
    /// minus its PTS, ms). Empty: none.
    std::string avLogPath;
};

/// \brief The HAL objects a Playback uses (the executable chooses the backends).
struct PlaybackHal {
    /// Makes a Closed media source for each open().
    std::function<Result<std::unique_ptr<hal::MediaSource>>()> makeSource;
    receiver::DecoderFactory makeDecoder; ///< One decoder per used stream.
    hal::Display *display = nullptr;      ///< Required; opened by create().
    hal::HapticDevice *device = nullptr;  ///< Optional: nullptr plays without haptics.
    platform::Clock *clock = nullptr;     ///< Required.
    /// Optional: the sound device (nullptr plays without sound), opened for each input with sound
    /// and closed with it.
    hal::AudioOutput *audioOutput = nullptr;
    /// Optional with audioOutput: opens the first audio stream of an input (media::AudioReader);
    /// a null source: the input has no sound.
    std::function<Result<std::unique_ptr<hal::AudioSource>>(const std::string &url)>
        makeAudioSource;
    /// A live input's sound (optional with audioOutput): decodes the packets of \a stream that the
    /// receiver hands to LiveAudio::sink (media::AudioReader::fromPackets()).
    struct LiveAudio {
        std::unique_ptr<hal::AudioSource> source;
        std::shared_ptr<hal::AudioPacketSink> sink;
    };
    std::function<Result<LiveAudio>(const hal::AudioStreamInfo &stream)> makeLiveAudioSource;
    /// Optional: a clock the media follows when the input has no sound playing (a GStreamer
    /// pipeline's, whose buffers' running time is the PTS: depthtouchsink). Called on the render
    /// thread about once a refresh; the picture's media origin, and with it the haptic task's time
    /// for Eq. 1, moves onto it where it is more than 2 ms away, as it follows the sound
    /// (FrameClock::follow()). Must be thread-safe and return quickly; null: the player's own
    /// clock.
    std::function<MasterClock()> masterClock;
};

/// \brief Counters since create() (all opens together). Plain values.
struct PlaybackStats {
    std::uint64_t opens = 0;
    std::uint64_t framesReceived = 0;  ///< Paired frames taken from the decode thread.
    std::uint64_t framesPresented = 0; ///< present() calls that succeeded.
    /// Frames skipped because their successor was already due and they were more than
    /// PlaybackConfig::maxLateness late.
    std::uint64_t framesDropped = 0;
    std::uint64_t framesLate = 0; ///< Presented more than one frame period after their time.
    double lateMsMax = 0.0;       ///< Most a presented frame was late (taken after its time), ms.
    std::uint64_t presentErrors = 0;
    std::uint64_t renderErrors = 0;
    std::uint64_t depthPairsPublished = 0; ///< Pairs handed to the haptic task.
    std::uint64_t seeks = 0;
    std::uint64_t endsOfStream = 0;
    std::uint64_t snapshotsWritten = 0;
    std::uint64_t framesRecorded = 0;
    std::uint64_t framesPreparedAhead =
        0;                    ///< Drawn with a mesh (and colour) made ahead on a worker.
    double renderMsP50 = 0.0; ///< Time to draw one output frame (upload, both eyes), ms.
    double renderMsP99 = 0.0;
    double meshTrianglesP50 = 0.0; ///< Triangles drawn per frame, median (under the LOD control).
    std::size_t lodBudget = 0;     ///< The LOD's leaf-block budget at the last frame (0: no LOD).
    std::uint64_t framesLodLimited = 0; ///< Frames whose mesh the LOD budget made coarser.
    double presentedFps = 0.0; ///< framesPresented over the time spent playing (not paused).
    /// Tune-in time of the last open: seconds from open() (or awaitNextSender()) to its first
    /// frame on screen — the source's open and probe, the wait for a key frame of every stream,
    /// decode and draw; 0 until it has one. On the Playback's clock.
    double playingSeconds = 0.0;
    double tuneInSeconds = 0.0;
    /// The last colour frame that came as dma-bufs was imported by the GPU without a copy.
    bool zeroCopy = false;
    std::uint64_t colorFramesImported = 0;       ///< Dma-buf colour frames imported (zero-copy).
    std::uint64_t colorFramesDmaBufUploaded = 0; ///< Dma-buf colour frames uploaded instead.
    receiver::ReceiverStats receiver{};          ///< Of the current (or last) open.
    /// Why the recording was lost (not finished at the end, or stopped by an error); empty when
    /// it was written or none was asked for.
    std::string recordingLost;
    std::string snapshotLost; ///< Why a snapshot was not written (the first); empty when none.
    /// The sound (all opens together): the device's underruns, its queue at the last turn (ms),
    /// and the A/V offset of the presented frames (the media time heard when a frame went on
    /// screen minus its PTS, ms; positive: the sound is ahead): the median offset and the 99th
    /// percentile of |offset|; 0 when nothing was measured.
    std::uint64_t audioUnderruns = 0;
    double audioDelayMs = 0.0;
    double avOffsetMsP50 = 0.0;
    double avOffsetMsP99 = 0.0;
    std::string audioLost; ///< Why the sound stopped (an unplugged device); empty when it did not.
    std::string avLogLost; ///< Why the A/V log was not written; empty when it was or none asked.
};

/// What open() found about the stream, for the summary.
struct PlaybackInfo {
    std::string url;
    std::string mode; ///< "color+depth", "color-only", "depth-only".
    int depthWidth = 0, depthHeight = 0;
    int colorWidth = 0, colorHeight = 0;
    double fps = 0.0;
    int outputWidth = 0, outputHeight = 0;
    bool haptics = false; ///< A haptic task runs (depth present and a device given).
    std::string audio;    ///< The sound played, e.g. "48000 Hz 2 ch"; empty: none.
    bool gl = false;      ///< Frames are drawn with the stereo renderer (else only presented).
    std::vector<std::string> notes;
};

/// See the file comment.
class Playback final : public player::PlayerActions {
public:
    /// \brief Opens the display and starts the render thread (idle until open()).
    /// \return Errc::InvalidArgument (missing HAL object, bad config), the display's open() error.
    static Result<std::unique_ptr<Playback>> create(const PlaybackConfig &config,
                                                    const PlaybackHal &hal);
    /// Stops everything (zero force first) and closes the display.
    ~Playback() override;

    /// \name player::PlayerActions (main thread)
    ///@{
    /// \brief Starts opening \a url (see report()). \return Errc::OutOfResources when no thread
    /// could be started for it; every other failure comes later as onOpenFailed().
    [[nodiscard]] Result<void> open(std::string_view url) override;
    /// \brief Opens \a url as open() does, trying again every 0.5 s until a sender comes (a live
    /// address whose stream fell silent); stop(), open() and quitting abandon the waiting.
    [[nodiscard]] Result<void> awaitNextSender(std::string_view url) override;
    /// The on-screen display reads "REMOTE: NO DEVICE" while \a connected is false (and comes
    /// up when the remote goes or comes back).
    void showRemoteConnected(std::optional<bool> connected) override;
    [[nodiscard]] Result<void> startPlayback() override;
    [[nodiscard]] Result<void> pause() override;
    [[nodiscard]] Result<void> resume() override;
    [[nodiscard]] Result<void> stop() override;
    [[nodiscard]] Result<void> seek(double seconds, player::SeekMode mode) override;
    /// seek(0, Absolute) without bringing the OSD up: the loop's restart is no viewer's command.
    [[nodiscard]] Result<void> restartForLoop() override;
    /// The presented frame's position from the stream's first frame and the stream's length (the
    /// container's duration; NaN for a live stream), s; NaN for both when nothing is open.
    [[nodiscard]] MediaPosition mediaPosition() const override;
    /// |F| of the haptic task's last command, N; NaN without a haptic task.
    [[nodiscard]] double hapticForce() const override;
    /// Whether the haptic task's device is connected and answering; none without a haptic task.
    [[nodiscard]] std::optional<bool> hapticDeviceConnected() const override;
    [[nodiscard]] Result<void> setStereoMode(player::StereoMode mode) override;
    [[nodiscard]] Result<void> setHapticsEnabled(bool enabled) override;
    [[nodiscard]] Result<void> setStiffness(double newtonsPerMetre) override;
    [[nodiscard]] Result<void> recenter() override;
    /// Brings the on-screen display up (the render thread restarts its --osd-seconds).
    [[nodiscard]] Result<void> showProgress() override;
    /// The volume of the sound, percent (0..AudioPlayerConfig::kMaxVolume, clamped), and mute;
    /// kept for the next inputs; each brings the on-screen display up.
    [[nodiscard]] Result<void> setVolume(double percent) override;
    [[nodiscard]] Result<void> setMute(bool mute) override;
    /// Errc::InvalidState without PlaybackConfig::snapshotDir, when the folder takes no file or
    /// when an earlier snapshot could not be written (refused: playback goes on),
    /// Errc::NotSupported on a display that draws nothing (mock); else requestSnapshot().
    [[nodiscard]] Result<void> snapshot() override;
    ///@}

    /// \brief Ends playback for good (the destructor does it too): stops what plays, ends the
    /// recording and writes the snapshots still queued, and stops the render thread; stats()
    /// then tells what was lost (PlaybackStats::recordingLost, snapshotLost). Nothing plays after
    /// it. Idempotent.
    void close();

    /// \brief Tells \a machine what happened since the last call: open finished or failed, end of
    /// stream, a failure of the pipeline, a live stream silent for
    /// PlaybackConfig::liveSilenceSeconds (onStreamSilent()). Call it from the main loop every few
    /// milliseconds.
    /// open() returns at once: the media source's open and probe run on a thread of their own
    /// (a FIFO without a writer or a silent stream blocks there, not the main thread), and the
    /// call of report() after they finished builds the session and reports onOpened() or
    /// onOpenFailed(). stop() or another open() abandons an open in progress.
    void report(player::StateMachine &machine);

    /// \return the counters (render-thread figures as of its last frame).
    [[nodiscard]] PlaybackStats stats() const;
    /// \return the stream description of the last successful open().
    [[nodiscard]] const PlaybackInfo &info() const noexcept { return info_; }
    /// \return the haptic task of the current open, or nullptr (no depth, no device, stopped).
    [[nodiscard]] haptic_task::HapticTask *hapticTask() noexcept;
    /// \return the haptic statistics of the last haptic task (kept after stop()), or nullopt.
    [[nodiscard]] std::optional<haptic_task::HapticStats> hapticStats();
    /// \return the media position of the frame on screen, s from the first frame.
    [[nodiscard]] double position() const noexcept;
    /// Asks for a snapshot of the next presented frame. Thread-safe.
    void requestSnapshot() noexcept;

    struct Impl;

private:
    /// open() and awaitNextSender(): tears the session down and starts the opener.
    [[nodiscard]] Result<void> startOpening(std::string_view url, bool untilOpened);
    explicit Playback(std::unique_ptr<Impl> impl);
    /// Builds the session on \a rec once the opener has opened it (main thread, from report()).
    void finishOpen(std::unique_ptr<receiver::Receiver> rec);
    /// Reports a live stream from which nothing came for PlaybackConfig::liveSilenceSeconds.
    void watchSilence(player::StateMachine &machine);
    /// seek() and restartForLoop(): the seek itself, clamped to the stream.
    [[nodiscard]] Result<void> seekTo(double seconds, player::SeekMode mode);
    std::unique_ptr<Impl> impl_;
    PlaybackInfo info_;
};

} // namespace depthtouch::playback
