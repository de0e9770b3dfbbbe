/// \file
/// \brief Playback: see playback.h.

#include "depthtouch/playback/playback.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>

#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/percentile.h"
#include "depthtouch/receiver/decoder_thread.h"

#include "async_opener.h"

#if DT_PLAYBACK_HAVE_GL
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/image.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/lod_controller.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"
#endif

DT_LOG_CATEGORY(Playback)

namespace depthtouch::playback {

using platform::percentile;

namespace {

using platform::Duration;
using platform::TimePoint;

double ptsSeconds(hal::Pts pts) noexcept
{
    return static_cast<double>(pts.count()) * 1e-9;
}

hal::Pts ptsFromSeconds(double s) noexcept
{
    return hal::Pts(static_cast<std::int64_t>(std::llround(s * 1e9)));
}

/// One open stream: what open() builds and stop() destroys (main thread), used by the render
/// thread between the two (see Impl::session).
struct Session {
    std::unique_ptr<receiver::Receiver> receiver;
    std::unique_ptr<receiver::DecoderThread> decoder;
    std::unique_ptr<haptic_task::DepthHandoff> handoff;
    std::unique_ptr<haptic_task::HapticTask> task;
    double period = 1.0 / 30.0; ///< Frame period, s.
    double startPts = 0.0;      ///< PTS of the first frame (s); positions count from it.
    hal::DisplayConfig displayConfig; ///< For the display's first open.
    bool haveStart = false;
};


#if DT_PLAYBACK_HAVE_GL
render::StereoMode toRenderMode(player::StereoMode m) noexcept
{
    switch (m) {
    case player::StereoMode::SideBySide: return render::StereoMode::SideBySide;
    case player::StereoMode::TopAndBottom: return render::StereoMode::TopAndBottom;
    case player::StereoMode::Anaglyph: return render::StereoMode::Anaglyph;
    case player::StereoMode::Mono: return render::StereoMode::Mono;
    case player::StereoMode::Interleaved: return render::StereoMode::RowInterleaved;
    }
    return render::StereoMode::SideBySide;
}
#endif

#if DT_PLAYBACK_HAVE_GL
/// The output recording (render thread): presented frames read back and encoded.
/// The recording: frames read back on the render thread, encoded by a thread of its own (x264's
/// time per frame would otherwise add to every frame's draw). At most
/// kQueue frames wait; when the encoder is that far behind the render thread waits for it, so
/// every presented frame is recorded.
class Recorder {
public:
    bool failed = false; ///< Render thread: recording stopped after an error.

    ~Recorder() { finish(); }

    /// \return whether open() succeeded.
    [[nodiscard]] bool isOpen() const noexcept { return encoder_ != nullptr; }

    /// \return an error text, or empty.
    std::string open(const PlaybackConfig &config, int width, int height)
    {
        media::MuxerOptions mo;
        mo.output = config.recordPath;
        auto m = media::Muxer::open(mo);
        if (!m)
            return std::string("cannot record to '") + config.recordPath + "': " + m.error().what;
        media::VideoEncoderConfig vc;
        vc.codec = media::VideoCodec::H264Yuv420p;
        vc.width = width & ~1;
        vc.height = height & ~1;
        vc.crf = config.recordCrf;
        vc.preset = config.recordPreset;
        vc.title = "output";
        auto e = media::VideoEncoder::create(vc, **m);
        if (!e)
            return std::string("cannot record: ") + e.error().what;
        if (auto r = (*m)->start(); !r)
            return std::string("cannot record: ") + r.error().what;
        muxer_ = std::move(*m);
        encoder_ = std::move(*e);
        width_ = vc.width;
        height_ = vc.height;
        try {
            thread_ = std::thread([this] { encodeLoop(); });
        } catch (const std::system_error &) {
            encoder_.reset();
            muxer_.reset();
            return "cannot record: no thread for the encoder";
        }
        return {};
    }

    /// Reads \a target back and queues it for encoding at presentation time \a now.
    /// \return an error text (of this frame, or of the encoding of an earlier one).
    std::string add(const render::RenderTarget &target, TimePoint now)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        spaceCv_.wait(lock, [this] { return queue_.size() < kQueue || !error_.empty(); });
        if (!error_.empty())
            return error_;
        Job job;
        if (!spare_.empty()) {
            job.image = std::move(spare_.back());
            spare_.pop_back();
        }
        lock.unlock();
        if (job.image.width != width_ || job.image.height != height_)
            job.image = media::Image::make(width_, height_, media::PixelFormat::Rgb24);
        if (auto r = target.readRgb(rgb_); !r)
            return std::string("cannot read the frame back: ") + r.error().what;
        const std::size_t srcRow = static_cast<std::size_t>(target.width()) * 3;
        const std::size_t dstRow = static_cast<std::size_t>(width_) * 3;
        for (int y = 0; y < height_; ++y)
            std::memcpy(job.image.row(y), rgb_.data() + static_cast<std::size_t>(y) * srcRow, dstRow);
        if (lastPts_ < 0.0)
            start_ = now;
        double pts = platform::toSeconds(now - start_);
        if (pts <= lastPts_)
            pts = lastPts_ + 1e-3;
        lastPts_ = pts;
        job.pts = pts;
        lock.lock();
        queue_.push_back(std::move(job));
        workCv_.notify_one();
        return {};
    }

    /// Encodes what is queued, ends the file and stops the thread (once).
    void finish() noexcept
    {
        if (!thread_.joinable())
            return;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        workCv_.notify_one();
        thread_.join();
        const bool ok = error_.empty() && encoder_->flush() && muxer_->finish();
        if (!ok)
            DT_LOG(Playback, Error, "The recording could not be finished%s%s", error_.empty() ? "" : ": ",
                   error_.c_str());
        encoder_.reset();
        muxer_.reset();
    }

private:
    struct Job {
        media::Image image;
        double pts = 0.0;
    };
    static constexpr std::size_t kQueue = 3;

    void encodeLoop()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            workCv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
            if (queue_.empty())
                return;
            Job job = std::move(queue_.front());
            queue_.pop_front();
            lock.unlock();
            auto r = encoder_->encode(job.image, job.pts);
            lock.lock();
            if (!r && error_.empty()) {
                error_ = std::string("cannot encode the recording: ") + r.error().what;
                queue_.clear();
            }
            spare_.push_back(std::move(job.image));
            spaceCv_.notify_one();
        }
    }

    std::unique_ptr<media::Muxer> muxer_;
    std::unique_ptr<media::VideoEncoder> encoder_;
    int width_ = 0;
    int height_ = 0;
    std::vector<std::uint8_t> rgb_; ///< Render thread: the read-back.
    TimePoint start_{};
    double lastPts_ = -1.0;
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable workCv_;  ///< A job or stop for the encoder thread.
    std::condition_variable spaceCv_; ///< Room in the queue (or an error) for the render thread.
    std::deque<Job> queue_;           ///< Guarded by mutex_.
    std::vector<media::Image> spare_; ///< Encoded frames' images, reused (guarded by mutex_).
    std::string error_;               ///< First encoding error (guarded by mutex_).
    bool stop_ = false;               ///< Guarded by mutex_.
};
#endif

} // namespace

struct Playback::Impl {
    PlaybackConfig config;
    PlaybackHal hal;
    platform::Clock &clock;

    // --- Main thread -> render thread (guarded by mutex) ---
    mutable std::mutex mutex;
    std::condition_variable cv;
    Session *session = nullptr;    ///< Current session (owned by `owned`), or null.
    std::uint64_t sessionGen = 0;  ///< Bumped when session changes.
    std::uint64_t sessionAck = 0;  ///< The render thread dropped everything of older sessions.
    bool playing = false;          ///< startPlayback() was called for this session.
    bool paused = false;
    std::uint64_t seekGen = 0;     ///< Bumped by seek().
    double seekTarget = 0.0;       ///< s, stream timeline (absolute).
    player::StereoMode stereoMode;
    bool quit = false;
    // Render thread -> main (guarded by mutex).
    double position = 0.0;         ///< s from the first frame.
    PlaybackStats stats;           ///< Render-thread counters (copied out by stats()).
    std::string failure;           ///< Pipeline failure not yet reported.
    std::string displayError;      ///< The render thread could not open the display.
    std::vector<double> renderMs;  ///< Draw time per frame, ms (first 2^16 frames).
    std::vector<double> meshTriangles; ///< Triangles drawn per frame under the LOD (first 2^16).
    bool endOfStream = false;      ///< Not yet reported.

    // --- Main thread only ---
    std::unique_ptr<Session> owned;
    AsyncOpener opener;     ///< The source's open and probe, off the main thread.
    std::string openingUrl; ///< What the opener opens.
    bool openDone = false;  ///< open() finished: report onOpened().
    std::string openError;  ///< open() failed: report onOpenFailed().
    bool hapticsEnabled;
    double stiffness;
    std::optional<haptic_task::HapticStats> lastHapticStats;

    std::atomic<bool> snapshotRequest{false};
    std::atomic<std::uint64_t> osdEvents{0}; ///< Commands that bring the on-screen display up.
    std::thread renderThread;

    Impl(const PlaybackConfig &c, const PlaybackHal &h)
        : config(c), hal(h), clock(*h.clock), stereoMode(c.stereoMode),
          hapticsEnabled(c.hapticsEnabled), stiffness(c.haptics.renderer.stiffness)
    {
        renderMs.reserve(std::size_t{1} << 16);
        meshTriangles.reserve(std::size_t{1} << 16);
    }

    /// Hands \a next (may be null) to the render thread and waits until it dropped every frame of
    /// the previous session.
    void switchSession(Session *next)
    {
        std::unique_lock<std::mutex> lock(mutex);
        session = next;
        playing = false;
        paused = false;
        endOfStream = false;
        const std::uint64_t gen = ++sessionGen;
        cv.notify_all();
        if (renderThread.joinable())
            cv.wait(lock, [&] { return sessionAck >= gen || quit; });
    }

    void tearDown()
    {
        opener.abandon();
        switchSession(nullptr);
        if (!owned)
            return;
        if (owned->task) {
            owned->task->stop();
            lastHapticStats = owned->task->stats();
        }
        if (owned->decoder)
            owned->decoder->stop();
        {
            std::lock_guard<std::mutex> lock(mutex);
            stats.receiver = owned->receiver ? owned->receiver->stats() : stats.receiver;
        }
        owned.reset();
    }

    void renderLoop();
};

// ---------------------------------------------------------------------------------------------
// The render thread.

namespace {

/// The render thread's view of one session: frames it holds and its media clock.
struct RenderState {
    Session *session = nullptr;
    std::uint64_t gen = 0;
    receiver::PairedFrame shown;      ///< On screen.
    receiver::PairedFrame pending[2]; ///< Taken from the decoder, not yet shown.
    int pendingCount = 0;
    bool clockStarted = false;
    bool prerolling = false;     ///< The first frame after open or seek is being drawn: the media
                                 ///< clock is anchored again when it is on screen.
    TimePoint origin{};          ///< Clock time at which media time (stream PTS, s) is 0.
    TimePoint onTimeAt{};        ///< When a frame was last taken less than a frame period late.
    double pausedAt = 0.0;       ///< Media time frozen by pause, s.
    bool wasPaused = false;
    std::uint64_t seekSeen = 0;
    bool reseat = false;         ///< Next shown frame comes after a seek: re-seat the proxy.
    bool eosSent = false;
    bool anyFrame = false;       ///< The decoder has given a frame in this session.
    TimePoint playStart{};
    bool playClockRunning = false;
    double playingSeconds = 0.0;

    /// \return whether pending[0] is skipped at \a now: its successor is due too, and it is more
    /// than \a maxLateness late or the player has not been on time for 3 × maxLateness. A stall
    /// of L seconds is caught up within about 2L more (one refresh gained per frame at 30 fps on
    /// 60 Hz); frames late for longer mean the player cannot catch up (a slow machine, or 60 fps
    /// on 60 Hz), and are skipped as with no lateness allowed.
    [[nodiscard]] bool skipsFront(TimePoint now, double maxLateness) const noexcept
    {
        if (pendingCount < 2 || now < origin + platform::fromSeconds(ptsSeconds(pending[1].pts)))
            return false;
        const double late = platform::toSeconds(now - origin) - ptsSeconds(pending[0].pts);
        return late > maxLateness || platform::toSeconds(now - onTimeAt) > 3.0 * maxLateness;
    }
    [[nodiscard]] bool haveShown() const noexcept
    {
        return static_cast<bool>(shown.color) || static_cast<bool>(shown.depth);
    }
    void dropFrames() noexcept
    {
        shown = receiver::PairedFrame{};
        for (auto &p : pending)
            p = receiver::PairedFrame{};
        pendingCount = 0;
    }
    void popFront() noexcept
    {
        pending[0] = std::move(pending[1]);
        pending[1] = receiver::PairedFrame{};
        --pendingCount;
    }
};

/// Copies one stored depth frame into a handoff slot (rows packed).
void copyDepth(const receiver::StoredFrame &f, const haptic_task::DepthSlot &slot, int width,
               int height, std::size_t bytesPerSample)
{
    const std::size_t rowBytes = static_cast<std::size_t>(width) * bytesPerSample;
    const int h = std::min(height, f.image.height);
    const std::size_t copyBytes =
        std::min(rowBytes, static_cast<std::size_t>(f.image.width) * bytesPerSample);
    for (int y = 0; y < h; ++y)
        std::memcpy(slot.data + static_cast<std::size_t>(y) * rowBytes, f.image.row(0, y),
                    copyBytes);
}

haptics::DepthFrameView depthView(const receiver::StoredFrame &f, double pts) noexcept;

#if DT_PLAYBACK_HAVE_GL
/// The picture the renderer shows for a frame of colour \a color and depth \a depth (either may be
/// null): the colour frame, or a gray depth frame as a picture when there is no colour stream; null
/// when neither, or when the colour frame came as dma-bufs (the renderer imports those itself).
const hal::ImageView *pictureOf(const receiver::StoredFrame *color, const receiver::StoredFrame *depth,
                                render::ColorSpec &spec) noexcept
{
    if (color != nullptr) {
        spec = render::ColorSpec{};
        return color->dmabuf.empty() ? &color->image : nullptr;
    }
    if (depth != nullptr && depth->image.format == hal::PixelFormat::Gray8) {
        spec = render::ColorSpec{render::YuvMatrix::Bt601, true};
        return &depth->image;
    }
    return nullptr;
}

/// \brief Makes the CPU half of upcoming frames (render::FramePrep: mesh and colour conversion) on
/// a thread of its own, while the render thread draws the current frame and llvmpipe's threads
/// rasterize it. Up to kSlots frames; a slot keeps its frames referenced until it is released.
class PrepWorker {
public:
    static constexpr std::size_t kSlots = 3;

    PrepWorker() : thread_([this] { run(); }) {}
    ~PrepWorker()
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            quit_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    PrepWorker(const PrepWorker &) = delete;
    PrepWorker &operator=(const PrepWorker &) = delete;

    /// Queues \a f (a pending frame with depth) unless it is queued already or no slot is free;
    /// a finished slot whose frame is not among \a pending (dropped) is reused.
    void submit(const receiver::PairedFrame &f, const receiver::PairedFrame *pending, int pendingCount,
                const render::MeshOptions &mesh, bool convertColor)
    {
        if (!f.depth)
            return;
        std::lock_guard<std::mutex> lock(mutex_);
        Slot *free = nullptr;
        for (Slot &s : slots_) {
            if (s.state != State::Free && s.key == f.depth.get())
                return;
            if (free == nullptr && s.state == State::Free)
                free = &s;
        }
        if (free == nullptr) {
            for (Slot &s : slots_) {
                bool wanted = false;
                for (int i = 0; i < pendingCount; ++i)
                    wanted = wanted || (pending[i].depth && pending[i].depth.get() == s.key);
                if (s.state == State::Ready && !wanted) {
                    s.reset();
                    free = &s;
                    break;
                }
            }
        }
        if (free == nullptr)
            return;
        free->key = f.depth.get();
        free->depth = f.depth.share();
        free->color = f.color ? f.color.share() : receiver::FrameHandle{};
        free->mesh = mesh;
        free->convertColor = convertColor;
        free->state = State::Queued;
        cv_.notify_all();
    }

    /// \return the finished prep of depth frame \a key (waiting while it is being made), or null
    /// when it was not queued. Give it back with release().
    render::FramePrep *take(const receiver::StoredFrame *key)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (Slot &s : slots_) {
            if (s.state == State::Free || s.key != key)
                continue;
            cv_.wait(lock, [&] { return s.state != State::Queued && s.state != State::Running; });
            if (s.state != State::Ready || !s.prep.built()) {
                s.reset();
                return nullptr;
            }
            s.state = State::InUse;
            return &s.prep;
        }
        return nullptr;
    }

    void release(render::FramePrep *prep)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Slot &s : slots_)
            if (&s.prep == prep)
                s.reset();
    }

    /// Drops every prep and the frame references they hold (seek, new session), waiting for the
    /// one being made (one mesh build): afterwards no frame of the old session is referenced.
    void clear()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (Slot &s : slots_) {
            if (s.state == State::Running)
                s.cancelled = true;
            else
                s.reset();
        }
        cv_.wait(lock, [&] {
            return std::none_of(slots_.begin(), slots_.end(),
                                [](const Slot &s) { return s.state == State::Running; });
        });
    }

private:
    enum class State : std::uint8_t { Free, Queued, Running, Ready, InUse };
    struct Slot {
        const receiver::StoredFrame *key = nullptr;
        receiver::FrameHandle depth;
        receiver::FrameHandle color;
        render::MeshOptions mesh{};
        bool convertColor = false;
        bool cancelled = false;
        State state = State::Free;
        render::FramePrep prep;

        void reset() noexcept
        {
            key = nullptr;
            depth.reset();
            color.reset();
            cancelled = false;
            state = State::Free;
        }
    };

    void run()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            Slot *job = nullptr;
            cv_.wait(lock, [&] {
                if (quit_)
                    return true;
                for (Slot &s : slots_)
                    if (s.state == State::Queued) {
                        job = &s;
                        return true;
                    }
                return false;
            });
            if (quit_)
                return;
            job->state = State::Running;
            lock.unlock();
            // The slot's handles keep both frames alive; only this thread touches a Running slot.
            render::ColorSpec spec;
            const hal::ImageView *color =
                job->convertColor ? pictureOf(job->color ? job->color.get() : nullptr, job->depth.get(), spec)
                                  : nullptr;
            const bool built =
                static_cast<bool>(job->prep.build(depthView(*job->depth, 0.0), color, spec, job->mesh));
            lock.lock();
            if (job->cancelled || !built)
                job->reset();
            else
                job->state = State::Ready;
            cv_.notify_all();
        }
    }

    std::mutex mutex_;
    std::condition_variable cv_;
    bool quit_ = false;
    std::array<Slot, kSlots> slots_;
    std::thread thread_; // last: started once the members above exist
};
#endif

haptics::DepthFrameView depthView(const receiver::StoredFrame &f, double pts) noexcept
{
    haptics::DepthFrameView v;
    v.data = f.image.planes[0].data;
    v.width = f.image.width;
    v.height = f.image.height;
    v.strideBytes = static_cast<std::size_t>(f.image.planes[0].strideBytes);
    v.format = f.image.format == hal::PixelFormat::Gray16 ? haptics::SampleFormat::Gray16
                                                          : haptics::SampleFormat::Gray8;
    v.pts = pts;
    return v;
}

} // namespace

void Playback::Impl::renderLoop()
{
    bool gl = false;
#if DT_PLAYBACK_HAVE_GL
    std::unique_ptr<render::StereoRenderer> renderer;
    std::optional<render::RenderTarget> target;
    std::unique_ptr<render::Snapshotter> snapshotter;
    Recorder recorder;
    std::vector<std::uint8_t> flatDepth; // depth-less input: a flat surface
    std::unique_ptr<PrepWorker> prepWorker; // upcoming frames' meshes and colour, made ahead
    std::optional<render::LodController> lod; // the mesh's block budget, from the draw times
#endif
    RenderState rs;
    std::uint64_t osdSeen = ~std::uint64_t{0};
    TimePoint osdSince{};

    for (;;) {
        // Commands and session changes.
        bool pausedNow = false;
        std::uint64_t seekGenNow = 0;
        double seekTo = 0.0;
        player::StereoMode modeNow;
        {
            std::unique_lock<std::mutex> lock(mutex);
            if (quit)
                break;
            if (rs.gen != sessionGen) {
                rs.dropFrames();
                rs = RenderState{};
                rs.session = session;
                rs.gen = sessionGen;
                rs.seekSeen = seekGen;
#if DT_PLAYBACK_HAVE_GL
                if (prepWorker)
                    prepWorker->clear();
                renderer.reset(); // re-created for the new stream's sizes
                target.reset();
                lod.reset();
#endif
                // The display belongs to this thread: opened here (sized for the first stream)
                // so that its GL context is current here and nowhere else.
                if (rs.session != nullptr && hal.display->state() != hal::Display::State::Open) {
                    if (auto r = hal.display->open(rs.session->displayConfig); !r) {
                        displayError = std::string("cannot open the display: ") + r.error().what;
                    } else if (hal.display->capabilities().hasGlesContext) {
                        if (auto c = hal.display->makeCurrent(); !c)
                            DT_LOG(Playback, Warning,
                                   "No GL context (%s): frames are presented undrawn",
                                   c.error().what);
                        else
                            gl = true;
                    }
                }
                sessionAck = sessionGen;
                cv.notify_all();
            }
            if (rs.session == nullptr || !playing) {
                cv.wait_for(lock, std::chrono::milliseconds(20));
                continue;
            }
            pausedNow = paused;
            seekGenNow = seekGen;
            seekTo = seekTarget;
            modeNow = stereoMode;
        }
        Session &s = *rs.session;
        const TimePoint now = clock.now();

        // Playing time (for the presented frame rate).
        if (!pausedNow && !rs.playClockRunning) {
            rs.playStart = now;
            rs.playClockRunning = true;
        } else if (pausedNow && rs.playClockRunning) {
            rs.playingSeconds += platform::toSeconds(now - rs.playStart);
            rs.playClockRunning = false;
        }

        // Seek: drop what was queued; the decode thread restarts at the target.
        if (seekGenNow != rs.seekSeen) {
            rs.seekSeen = seekGenNow;
            for (auto &p : rs.pending)
                p = receiver::PairedFrame{};
            rs.pendingCount = 0;
            rs.clockStarted = false;
            rs.reseat = true;
            rs.eosSent = false;
#if DT_PLAYBACK_HAVE_GL
            if (prepWorker)
                prepWorker->clear();
#endif
            s.decoder->seek(ptsFromSeconds(seekTo));
        }

        // Pause: the media clock stands still (the haptic time with it).
        if (pausedNow && rs.clockStarted) {
            if (!rs.wasPaused)
                rs.pausedAt = platform::toSeconds(now - rs.origin);
            rs.origin = now - platform::fromSeconds(rs.pausedAt);
            if (s.handoff)
                s.handoff->setMediaOrigin(rs.origin);
        }
        rs.wasPaused = pausedNow;

        // Take frames (never blocks).
        while (rs.pendingCount < 2 &&
               s.decoder->poll(rs.pending[static_cast<std::size_t>(rs.pendingCount)])) {
            ++rs.pendingCount;
            rs.anyFrame = true;
            std::lock_guard<std::mutex> lock(mutex);
            ++stats.framesReceived;
        }
#if DT_PLAYBACK_HAVE_GL
        // The next frame to show gets its mesh and colour made ahead while this thread draws (the
        // first, or the second when it is due already and the first will be dropped).
        if (prepWorker && renderer && rs.pendingCount > 0 && rs.clockStarted) {
            const bool skipFirst = rs.skipsFront(now, config.maxLateness);
            prepWorker->submit(rs.pending[skipFirst ? 1 : 0], rs.pending, rs.pendingCount,
                               renderer->options().mesh, renderer->convertsColorOnCpu());
        }
#endif
        if (s.decoder->failed()) {
            std::lock_guard<std::mutex> lock(mutex);
            if (failure.empty())
                failure = std::string("decoding failed: ") + s.decoder->error().what;
        }

        if (rs.pendingCount == 0 && !rs.anyFrame && s.decoder->finished() && !rs.eosSent) {
            // The input ended before its first complete frame (a file cut after its header): a
            // failure, not a player that shows nothing for ever.
            rs.eosSent = true;
            std::lock_guard<std::mutex> lock(mutex);
            if (failure.empty())
                failure = "the input ended before its first complete frame (truncated?)";
        }
        if (rs.pendingCount == 0) {
            // End of stream: the last frame has had its time on screen.
            if (!rs.eosSent && s.decoder->finished() && rs.haveShown() &&
                (!rs.clockStarted ||
                 platform::toSeconds(now - rs.origin) >= ptsSeconds(rs.shown.pts) + s.period)) {
                rs.eosSent = true;
                std::lock_guard<std::mutex> lock(mutex);
                endOfStream = true;
                ++stats.endsOfStream;
            }
            clock.sleepFor(std::chrono::milliseconds(2));
            continue;
        }

        receiver::PairedFrame &next = rs.pending[0];
        const double pts = ptsSeconds(next.pts);
        if (!s.haveStart) {
            std::lock_guard<std::mutex> lock(mutex);
            s.startPts = pts;
            s.haveStart = true;
        }
        if (!rs.clockStarted) {
            // First frame after open or seek: media time starts at its PTS now, and again when it
            // is on screen (preroll), so the time its first draw takes (shader compilation, first
            // uploads, a seek's decode) does not make the frames after it late.
            rs.origin = now - platform::fromSeconds(pts);
            rs.onTimeAt = now;
            rs.clockStarted = true;
            rs.prerolling = true;
            rs.pausedAt = pts;
            if (s.handoff)
                s.handoff->setMediaOrigin(rs.origin);
        } else {
            if (pausedNow && !rs.reseat && rs.haveShown()) {
                clock.sleepFor(std::chrono::milliseconds(5));
                continue;
            }
            const TimePoint due = rs.origin + platform::fromSeconds(pts);
            if (now < due) {
                clock.sleepUntil(std::min(due, now + std::chrono::milliseconds(5)));
                continue;
            }
            // Late: skip this frame when its successor is due too and it is too late to catch
            // up (RenderState::skipsFront); else draw it, and the next frames catch up.
            const double late = platform::toSeconds(now - due);
            if (rs.skipsFront(now, config.maxLateness)) {
                rs.popFront();
                std::lock_guard<std::mutex> lock(mutex);
                ++stats.framesDropped;
                continue;
            }
            if (late <= s.period)
                rs.onTimeAt = now;
            std::lock_guard<std::mutex> lock(mutex);
            if (late > s.period)
                ++stats.framesLate;
            stats.lateMsMax = std::max(stats.lateMsMax, 1e3 * late);
        }

        // Frame i goes on screen: the haptic task gets (depth i, depth i+1).
        rs.shown = std::move(next);
        rs.popFront();
        if (s.handoff && rs.shown.depth) {
            const receiver::DepthPair dp = rs.shown.depthPair();
            const std::size_t bps = s.handoff->format() == haptics::SampleFormat::Gray16 ? 2 : 1;
            haptic_task::DepthSlot cur = s.handoff->beginFrame();
            copyDepth(*dp.current, cur, s.handoff->width(), s.handoff->height(), bps);
            cur.pts = ptsSeconds(dp.currentPts);
            if (dp.next != nullptr) {
                haptic_task::DepthSlot nxt = s.handoff->beginFrame();
                copyDepth(*dp.next, nxt, s.handoff->width(), s.handoff->height(), bps);
                nxt.pts = ptsSeconds(dp.nextPts);
                s.handoff->publish(cur, &nxt);
            } else {
                s.handoff->publish(cur, nullptr);
            }
            if (rs.reseat && s.task)
                s.task->requestClockRestart();
            std::lock_guard<std::mutex> lock(mutex);
            ++stats.depthPairsPublished;
        }
        rs.reseat = false;

        // Draw and present.
        const TimePoint drawStart = clock.now();
        bool drawn = true;
#if DT_PLAYBACK_HAVE_GL
        if (gl) {
            drawn = false;
            const receiver::StoredFrame *depthFrame = rs.shown.depth ? rs.shown.depth.get() : nullptr;
            const receiver::StoredFrame *colorFrame = rs.shown.color ? rs.shown.color.get() : nullptr;
            haptics::DepthFrameView dv;
            if (depthFrame != nullptr) {
                dv = depthView(*depthFrame, pts);
            } else if (colorFrame != nullptr) {
                const int w = colorFrame->image.width;
                const int h = colorFrame->image.height;
                flatDepth.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
                dv = {flatDepth.data(), w, h, static_cast<std::size_t>(w),
                      haptics::SampleFormat::Gray8, pts};
            }
            if (!renderer) {
                render::RendererOptions ro;
                ro.box = config.haptics.renderer.box;
                ro.stereo.frameCompatible = config.frameCompatible;
                if (config.meshStep > 0) {
                    ro.mesh.mode = render::MeshMode::Fixed;
                    ro.mesh.fixedStep = config.meshStep;
                    ro.mesh.tileSize = std::max(ro.mesh.tileSize, config.meshStep);
                }
                auto r = render::StereoRenderer::create(ro);
                if (r)
                    renderer = std::move(*r);
                else
                    DT_LOG_ONCE(Playback, Error, "Cannot create the stereo renderer: %s",
                                r.error().what);
            }
            const hal::Size size = hal.display->size();
            if (!target && renderer) {
                auto t = render::RenderTarget::create(size.width, size.height);
                if (t)
                    target = std::move(*t);
                else
                    DT_LOG_ONCE(Playback, Error, "Cannot create the render target: %s",
                                t.error().what);
            }
            if (renderer && target && dv.data != nullptr) {
                render::RendererOptions ro = renderer->options();
                ro.mode = toRenderMode(modeNow);
                if (config.lodTarget > 0.0 && config.meshStep == 0 &&
                    ro.mesh.mode == render::MeshMode::Quadtree) {
                    if (!lod) {
                        render::LodOptions lo;
                        // A frame drawn within one refresh period is on screen at its time even
                        // after a late one (the next refresh catches up); one that takes longer
                        // stays a refresh late until a faster one comes, and the next stall drops
                        // a frame. So the target is a share of the refresh period (of the frame
                        // period when that is shorter, or the display does not say).
                        const double refresh = hal.display->refreshHz();
                        const double budgetPeriod =
                            refresh > 0.0 ? std::min(s.period, 1.0 / refresh) : s.period;
                        lo.targetSeconds = config.lodTarget * budgetPeriod;
                        lo.minBlocks = std::max<std::size_t>(
                            lo.minBlocks, static_cast<std::size_t>(dv.width) *
                                              static_cast<std::size_t>(dv.height) / 256);
                        lod.emplace(lo);
                    }
                    ro.mesh.maxBlocks = lod->budget();
                }
                (void)renderer->setOptions(ro);
                if (!prepWorker)
                    prepWorker = std::make_unique<PrepWorker>();
                render::FramePrep *prep = depthFrame != nullptr ? prepWorker->take(depthFrame) : nullptr;
                bool ok = static_cast<bool>(prep != nullptr ? renderer->setDepth(dv, *prep)
                                                            : renderer->setDepth(dv));
                render::ColorSpec spec;
                const hal::ImageView *picture = pictureOf(colorFrame, depthFrame, spec);
                if (prep != nullptr && prep->hasRgba) {
                    (void)renderer->setColor(*prep);
                } else if (colorFrame != nullptr) {
                    if (auto r = renderer->setColorFrame(colorFrame->image, colorFrame->dmabuf, spec); !r)
                        DT_LOG_ONCE(Playback, Warning, "Color frames not shown: %s",
                                    r.error().what);
                } else if (picture != nullptr) {
                    (void)renderer->setColor(*picture, spec);
                }
                if (prep != nullptr) {
                    prepWorker->release(prep);
                    std::lock_guard<std::mutex> lock(mutex);
                    ++stats.framesPreparedAhead;
                }
                render::AvatarState avatar;
                if (config.avatar && s.task) {
                    glm::dvec3 hip, proxy;
                    if (s.task->lastPose(hip, proxy)) {
                        avatar.visible = true;
                        avatar.hip = hip;
                        avatar.proxy = proxy;
                    }
                }
                renderer->setAvatar(avatar);
                if (const std::uint64_t n = osdEvents.load(std::memory_order_relaxed); n != osdSeen) {
                    osdSeen = n;
                    osdSince = clock.now();
                }
                const bool osdUp = config.osdSeconds <= 0.0 || pausedNow ||
                                   platform::toSeconds(clock.now() - osdSince) < config.osdSeconds;
                if (config.osd) {
                    render::OsdState osd;
                    osd.visible = osdUp;
                    osd.status = pausedNow ? "PAUSED" : "PLAYING";
                    osd.hapticsOn = s.task != nullptr && s.task->enabled();
                    osd.force = s.task ? glm::length(s.task->lastForce()) : 0.0;
                    osd.maxForce = std::max(1e-3, config.haptics.renderer.maxForce);
                    renderer->setOsd(osd);
                }
                if (ok && renderer->render(*target)) {
                    if (target->blitTo(hal.display->framebuffer(), size.width, size.height))
                        drawn = true;
                    if (!config.recordPath.empty() && !recorder.failed) {
                        std::string err;
                        if (!recorder.isOpen())
                            err = recorder.open(config, target->width(), target->height());
                        if (err.empty())
                            err = recorder.add(*target, clock.now());
                        std::lock_guard<std::mutex> lock(mutex);
                        if (err.empty()) {
                            ++stats.framesRecorded;
                        } else {
                            recorder.failed = true;
                            failure = err;
                        }
                    }
                    if (snapshotter) {
                        if (snapshotRequest.exchange(false))
                            snapshotter->request();
                        auto w = snapshotter->onFrame(*target);
                        if (!w) {
                            DT_LOG_ONCE(Playback, Warning, "Snapshot not written: %s",
                                        w.error().what);
                        } else if (*w) {
                            std::lock_guard<std::mutex> lock(mutex);
                            ++stats.snapshotsWritten;
                        }
                    }
                }
            }
            if (!snapshotter && !config.snapshotDir.empty())
                snapshotter = std::make_unique<render::Snapshotter>(config.snapshotDir,
                                                                    config.snapshotEvery,
                                                                    "frame");
        }
#endif
#if DT_PLAYBACK_HAVE_GL
        // The level of detail follows the time to draw a frame, without the present's wait for the
        // vertical blank; a software rasterizer draws on the CPU, so its work is waited for here
        // (its present would wait for it anyway).
        if (lod && renderer && drawn && renderer->rendersInSoftware())
            renderer->finish();
#endif
        const double drawSeconds = platform::toSeconds(clock.now() - drawStart);
        const double ms = drawSeconds * 1e3;
        const auto presented = hal.display->present();
#if DT_PLAYBACK_HAVE_GL
        if (lod && renderer && drawn && presented && !rs.prerolling) {
            const render::MeshStats &mesh = renderer->mesh().stats();
            lod->update(drawSeconds, mesh);
            std::lock_guard<std::mutex> lock(mutex);
            stats.lodBudget = lod->budget();
            if (mesh.budgetLimited)
                ++stats.framesLodLimited;
            if (meshTriangles.size() < meshTriangles.capacity())
                meshTriangles.push_back(static_cast<double>(mesh.triangles));
        }
#endif
        if (rs.prerolling) {
            // The haptic time never runs backwards (it holds until the new origin catches up).
            rs.prerolling = false;
            rs.origin = clock.now() - platform::fromSeconds(pts);
            if (s.handoff)
                s.handoff->setMediaOrigin(rs.origin);
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (!drawn)
                ++stats.renderErrors;
            if (presented) {
                ++stats.framesPresented;
            } else {
                ++stats.presentErrors;
                // The window was closed or the display went away: playback cannot go on.
                if (presented.error().code == Errc::NoDevice && failure.empty())
                    failure = std::string("the display was lost: ") + presented.error().what;
            }
            position = pts - s.startPts;
            double played = rs.playingSeconds;
            if (rs.playClockRunning)
                played += platform::toSeconds(clock.now() - rs.playStart);
            stats.playingSeconds = played;
            stats.presentedFps =
                played > 0 ? static_cast<double>(stats.framesPresented) / played : 0.0;
            if (renderMs.size() < renderMs.capacity())
                renderMs.push_back(ms);
#if DT_PLAYBACK_HAVE_GL
            if (renderer) {
                const render::DmaBufStats &ds = renderer->dmaBufStats();
                stats.zeroCopy = ds.zeroCopy;
                stats.colorFramesImported = ds.imported;
                stats.colorFramesDmaBufUploaded = ds.uploaded;
            }
#endif
        }
        (void)gl;
    }

    // Leaving: drop frames; GL objects go while the context is current.
    rs.dropFrames();
    {
        std::lock_guard<std::mutex> lock(mutex);
        sessionAck = sessionGen;
        cv.notify_all();
    }
#if DT_PLAYBACK_HAVE_GL
    recorder.finish();
    snapshotter.reset();
    target.reset();
    renderer.reset();
#endif
    hal.display->close();
}

// ---------------------------------------------------------------------------------------------

Playback::Playback(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Result<std::unique_ptr<Playback>> Playback::create(const PlaybackConfig &config,
                                                   const PlaybackHal &hal)
{
    if (!hal.makeSource || !hal.makeDecoder || hal.display == nullptr || hal.clock == nullptr)
        return Error(Errc::InvalidArgument, "playback needs a media source, decoders, a display "
                                            "and a clock");
    if (auto r = config.haptics.validate(); !r)
        return r.error();
    if (config.outputWidth < 0 || config.outputHeight < 0 || config.outputWidth > 8192 ||
        config.outputHeight > 8192)
        return Error(Errc::InvalidArgument, "output size out of range");
    if (config.meshStep < 0 || config.meshStep > 64 ||
        (config.meshStep & (config.meshStep - 1)) != 0)
        return Error(Errc::InvalidArgument, "mesh step must be 0 or a power of two up to 64");
    if (!(config.maxLateness >= 0.0 && config.maxLateness <= 10.0))
        return Error(Errc::InvalidArgument, "max lateness must be in [0, 10] s");
    auto impl = std::make_unique<Impl>(config, hal);
    return std::unique_ptr<Playback>(new Playback(std::move(impl)));
}

Playback::~Playback()
{
    impl_->tearDown();
    {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        impl_->quit = true;
        impl_->cv.notify_all();
    }
    if (impl_->renderThread.joinable())
        impl_->renderThread.join();
}

Result<void> Playback::open(std::string_view url)
{
    Impl &m = *impl_;
    m.tearDown();
    m.openDone = false;
    m.openError.clear();
    // The source's open and probe may block (a FIFO without a writer, a silent stream): they run
    // on the opener's thread, and report() finishes the open when they are done.
    std::string why;
    if (!m.opener.start(m.hal.makeSource, std::string(url), m.hal.makeDecoder, m.config.receiver,
                        why))
        m.openError = std::move(why);
    m.openingUrl = std::string(url);
    return {};
}

void Playback::finishOpen(std::unique_ptr<receiver::Receiver> rec)
{
    Impl &m = *impl_;
    const std::string urlText = m.openingUrl;
    auto fail = [&](std::string why) { m.openError = std::move(why); };

    auto s = std::make_unique<Session>();
    s->receiver = std::move(rec);
    const receiver::ReceiverInfo &ri = s->receiver->info();
    PlaybackInfo info;
    info.url = urlText;
    info.mode = receiver::receiverModeName(ri.mode);
    info.notes = ri.notes;
    const hal::StreamInfo &main = ri.hasColor ? ri.color : ri.depth;
    if (ri.hasDepth) {
        info.depthWidth = ri.depth.width;
        info.depthHeight = ri.depth.height;
    }
    if (ri.hasColor) {
        info.colorWidth = ri.color.width;
        info.colorHeight = ri.color.height;
    }
    const hal::Pts period = ri.hasColor ? ri.colorPeriod : ri.depthPeriod;
    s->period = period.count() > 0 ? ptsSeconds(period) : 1.0 / 30.0;
    info.fps = 1.0 / s->period;

    // The haptic task on the depth frames.
    if (ri.hasDepth && m.hal.device != nullptr) {
        const haptics::SampleFormat fmt = ri.depthFormat == hal::PixelFormat::Gray16
                                              ? haptics::SampleFormat::Gray16
                                              : haptics::SampleFormat::Gray8;
        auto handoff = haptic_task::DepthHandoff::create(ri.depth.width, ri.depth.height, fmt);
        if (!handoff)
            return fail(std::string("cannot allocate the depth frames: ") +
                        handoff.error().what);
        s->handoff = std::move(*handoff);
        haptic_task::HapticTaskConfig tc = m.config.haptics;
        tc.startEnabled = m.hapticsEnabled;
        auto task = haptic_task::HapticTask::create(tc, *m.hal.device, *s->handoff, m.clock);
        if (!task)
            return fail(std::string("cannot create the haptic task: ") + task.error().what);
        s->task = std::move(*task);
        s->task->setStiffness(m.stiffness);
        info.haptics = true;
    } else if (!ri.hasDepth) {
        info.notes.emplace_back("no depth stream: playing flat (2D) with haptics off");
    } else {
        info.notes.emplace_back("no haptic device: playing without haptics");
    }

    // The display: sized for the stream on the first open (opened by the render thread).
    {
        const int w = ri.hasDepth ? ri.depth.width : main.width;
        const int h = ri.hasDepth ? ri.depth.height : main.height;
        s->displayConfig.width =
            m.config.outputWidth > 0 ? m.config.outputWidth : std::min(2 * w, 3840);
        s->displayConfig.height = m.config.outputHeight > 0 ? m.config.outputHeight : std::min(h, 2160);
        s->displayConfig.refreshHz = m.config.refreshHz;
    }
    if (!m.renderThread.joinable())
        m.renderThread = std::thread([&m] { m.renderLoop(); });

    s->decoder = std::make_unique<receiver::DecoderThread>(*s->receiver);
    if (auto r = s->decoder->start(); !r)
        return fail(std::string("cannot start the decode thread: ") + r.error().what);
    if (s->task) {
        if (auto r = s->task->start(); !r) {
            s->decoder->stop();
            return fail(std::string("cannot start the haptic task: ") + r.error().what);
        }
    }
    m.owned = std::move(s);
    {
        std::lock_guard<std::mutex> lock(m.mutex);
        ++m.stats.opens;
    }
    m.switchSession(m.owned.get());
    {
        std::unique_lock<std::mutex> lock(m.mutex);
        if (!m.displayError.empty()) {
            std::string why = std::move(m.displayError);
            m.displayError.clear();
            lock.unlock();
            m.tearDown();
            return fail(why);
        }
    }
    const hal::Size size = m.hal.display->size();
    info.outputWidth = size.width;
    info.outputHeight = size.height;
#if DT_PLAYBACK_HAVE_GL
    info.gl = m.hal.display->capabilities().hasGlesContext;
#endif
    if (!m.config.recordPath.empty() && !info.gl)
        info.notes.emplace_back("not recording: the display has no OpenGL ES context to read "
                                "frames from");
    info_ = std::move(info);
    m.openDone = true;
}

Result<void> Playback::startPlayback()
{
    Impl &m = *impl_;
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.session == nullptr)
        return Error(Errc::InvalidState, "nothing is open");
    m.playing = true;
    m.paused = false;
    m.cv.notify_all();
    return {};
}

Result<void> Playback::pause()
{
    Impl &m = *impl_;
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.session == nullptr)
        return Error(Errc::InvalidState, "nothing is playing");
    m.paused = true;
    return {};
}

Result<void> Playback::resume()
{
    Impl &m = *impl_;
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.session == nullptr)
        return Error(Errc::InvalidState, "nothing is open");
    m.paused = false;
    return {};
}

Result<void> Playback::stop()
{
    impl_->tearDown();
    return {};
}

Result<void> Playback::seek(double seconds, player::SeekMode mode)
{
    Impl &m = *impl_;
    m.osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (!std::isfinite(seconds))
        return Error(Errc::InvalidArgument, "seek: not a number");
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.session == nullptr)
        return Error(Errc::InvalidState, "nothing is open");
    const double start = m.session->haveStart ? m.session->startPts : 0.0;
    double target = mode == player::SeekMode::Absolute ? seconds : m.position + seconds;
    target = std::max(0.0, target);
    const double duration = ptsSeconds(m.session->receiver->info().duration);
    if (duration > 0.0)
        target = std::min(target, std::max(0.0, duration - m.session->period));
    m.seekTarget = start + target;
    m.position = target;
    ++m.seekGen;
    ++m.stats.seeks;
    m.endOfStream = false;
    return {};
}

Result<void> Playback::setStereoMode(player::StereoMode mode)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stereoMode = mode;
    return {};
}

Result<void> Playback::setHapticsEnabled(bool enabled)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    impl_->hapticsEnabled = enabled;
    if (impl_->owned && impl_->owned->task)
        impl_->owned->task->setEnabled(enabled);
    return {};
}

Result<void> Playback::setStiffness(double newtonsPerMetre)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (!(newtonsPerMetre > 0.0))
        return Error(Errc::InvalidArgument, "stiffness must be positive");
    impl_->stiffness = newtonsPerMetre;
    if (impl_->owned && impl_->owned->task)
        impl_->owned->task->setStiffness(newtonsPerMetre);
    return {};
}

Result<void> Playback::recenter()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (!impl_->owned || !impl_->owned->task)
        return Error(Errc::InvalidState, "no haptic task is running");
    impl_->owned->task->requestReseat();
    return {};
}

void Playback::report(player::StateMachine &machine)
{
    Impl &m = *impl_;
    if (std::optional<AsyncOpener::Outcome> opened = m.opener.poll()) {
        if (opened->receiver)
            finishOpen(std::move(opened->receiver));
        else
            m.openError = std::move(opened->error);
    }
    if (m.openDone) {
        m.openDone = false;
        machine.onOpened();
    }
    if (!m.openError.empty()) {
        const std::string why = std::move(m.openError);
        m.openError.clear();
        machine.onOpenFailed(why);
    }
    std::string failure;
    bool eos = false;
    {
        std::lock_guard<std::mutex> lock(m.mutex);
        failure.swap(m.failure);
        eos = m.endOfStream;
        m.endOfStream = false;
    }
    if (!failure.empty())
        machine.onFailure(failure);
    if (eos)
        machine.onEndOfStream();
}

PlaybackStats Playback::stats() const
{
    std::lock_guard<std::mutex> lock(impl_->mutex);
    PlaybackStats s = impl_->stats;
    s.renderMsP50 = percentile(impl_->renderMs, 0.50);
    s.renderMsP99 = percentile(impl_->renderMs, 0.99);
    s.meshTrianglesP50 = percentile(impl_->meshTriangles, 0.50);
    if (impl_->owned && impl_->owned->decoder)
        s.receiver = impl_->owned->decoder->stats();
    return s;
}

haptic_task::HapticTask *Playback::hapticTask() noexcept
{
    return impl_->owned ? impl_->owned->task.get() : nullptr;
}

std::optional<haptic_task::HapticStats> Playback::hapticStats()
{
    if (impl_->owned && impl_->owned->task)
        return impl_->owned->task->stats();
    return impl_->lastHapticStats;
}

double Playback::position() const noexcept
{
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->position;
}

void Playback::requestSnapshot() noexcept
{
    impl_->snapshotRequest.store(true);
}

} // namespace depthtouch::playback
