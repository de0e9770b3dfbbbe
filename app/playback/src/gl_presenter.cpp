/// \file
/// \brief The GL Presenter (builds with EGL/GLES): the stereo renderer draws each frame into a
/// render target, blitted to the display's frame buffer; on a GPU every depth sample is drawn from
/// a static grid unless its draw time is over the target, otherwise (and on a software rasterizer)
/// the level of detail (a step per tile from precomputed index ranges, MeshMode::Blocks) follows
/// the draw times; the prep worker makes upcoming frames' meshes ahead; the recorder and the
/// snapshotter read the target back. See presenter.h.

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/lod_controller.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"

#include "depth_view.h"
#include "prep_worker.h"
#include "presenter.h"
#include "recorder.h"

DT_LOG_CATEGORY(Playback)

namespace depthtouch::playback {

namespace {

/// The OSD's words for the sound: "  MUTED" or "  VOL 50%".
std::string soundStatus(double volume, bool muted)
{
    if (muted)
        return "  MUTED";
    char buf[24];
    std::snprintf(buf, sizeof buf, "  VOL %.0f%%", volume);
    return buf;
}

render::StereoMode toRenderMode(player::StereoMode m) noexcept
{
    switch (m) {
    case player::StereoMode::SideBySide:
        return render::StereoMode::SideBySide;
    case player::StereoMode::TopAndBottom:
        return render::StereoMode::TopAndBottom;
    case player::StereoMode::Anaglyph:
        return render::StereoMode::Anaglyph;
    case player::StereoMode::Mono:
        return render::StereoMode::Mono;
    case player::StereoMode::Interleaved:
        return render::StereoMode::RowInterleaved;
    }
    return render::StereoMode::SideBySide;
}

/// See the file comment.
class GlPresenter final : public Presenter {
public:
    GlPresenter(const PlaybackConfig &config, hal::Display &display, platform::Clock &clock,
                std::atomic<bool> &snapshotRequest, const std::atomic<std::uint64_t> &osdEvents)
        : config_(config), display_(display), clock_(clock), snapshotRequest_(snapshotRequest),
          osdEvents_(osdEvents)
    {
    }

    void contextReady() override { gl_ = true; }
    void newSession() override
    {
        if (prepWorker_)
            prepWorker_->clear();
        renderer_.reset(); // re-created for the new stream's sizes
        target_.reset();
        lod_.reset();
        fullResolution_ = false;
        trialCount_ = 0;
    }
    void dropPrepared() override
    {
        if (prepWorker_)
            prepWorker_->clear();
    }
    void prepareAhead(const receiver::PairedFrame &next, const receiver::PairedFrame *queued,
                      int queuedCount) override
    {
        if (prepWorker_ && renderer_)
            prepWorker_->submit(next, queued, queuedCount, renderer_->options().mesh,
                                renderer_->convertsColorOnCpu());
    }
    DrawOutcome draw(const DrawInput &in) override;
    void finishDrawing(bool drawn) override
    {
        // A software rasterizer draws on the CPU: its work is waited for here (its present
        // would wait for it anyway), so the level of detail sees the time to draw. On a GPU the
        // first frames of the full-resolution mesh are waited for too, to see its draw time.
        if (!renderer_ || !drawn)
            return;
        if ((lod_ && renderer_->rendersInSoftware()) ||
            (fullResolution_ && trialCount_ < kTrialFrames))
            renderer_->finish();
    }
    std::optional<LodSample> afterPresent(double drawSeconds, bool drawn, bool presented,
                                          bool prerolling) override;
    void addStats(PlaybackStats &stats) const override
    {
        if (!renderer_)
            return;
        const render::DmaBufStats &ds = renderer_->dmaBufStats();
        stats.zeroCopy = ds.zeroCopy;
        stats.colorFramesImported = ds.imported;
        stats.colorFramesDmaBufUploaded = ds.uploaded;
    }
    OutputsLost shutdown() override
    {
        OutputsLost lost;
        lost.recording = recorder_.finish();
        if (snapshotter_) {
            if (auto f = snapshotter_->flush(); !f) {
                char why[160];
                lost.snapshot =
                    std::string("a snapshot was not written: ") + f.error().format(why, sizeof why);
            }
        }
        snapshotter_.reset();
        target_.reset();
        renderer_.reset();
        return lost;
    }

private:
    scene::DepthFrameView depthOf(const DrawInput &in);
    void ensureRendererAndTarget(hal::Size size, const scene::DepthFrameView &dv);
    void applyOptions(player::StereoMode mode, const scene::DepthFrameView &dv, double period);
    /// The level of detail's mesh for W×H depth into \a m (mode, tile, tolerance).
    static void toBlocks(render::MeshOptions &m, int width, int height);
    bool setPicture(const receiver::StoredFrame *depthFrame,
                    const receiver::StoredFrame *colorFrame, const scene::DepthFrameView &dv,
                    DrawOutcome &out);
    void setOverlays(const DrawInput &in);
    void output(hal::Size size, DrawOutcome &out);
    /// The full-resolution mesh's draw times: after kTrialFrames, a median over the level of
    /// detail's target hands the mesh to the level of detail (Blocks) and its controller.
    void checkFullResolution(double drawSeconds);

    /// Draw times of the full-resolution mesh looked at (each waited for with glFinish).
    static constexpr int kTrialFrames = 9;
    /// The level of detail's mean error budget, nearness levels (MeshOptions::tolerance).
    static constexpr double kBlocksTolerance = 0.4;

    const PlaybackConfig &config_;
    hal::Display &display_;
    platform::Clock &clock_;
    std::atomic<bool> &snapshotRequest_;
    const std::atomic<std::uint64_t> &osdEvents_;
    bool gl_ = false;
    std::unique_ptr<render::StereoRenderer> renderer_;
    std::optional<render::RenderTarget> target_;
    std::unique_ptr<render::Snapshotter> snapshotter_;
    Recorder recorder_;
    std::vector<std::uint8_t> flatDepth_;      // depth-less input: a flat surface
    std::unique_ptr<PrepWorker> prepWorker_;   // upcoming frames' meshes and colour, made ahead
    std::optional<render::LodController> lod_; // the mesh's block budget, from the draw times
    double lodTargetSeconds_ = 0.0;            // the draw-time goal (a share of the refresh)
    bool fullResolution_ = false;              // a GPU draws every depth sample (no --mesh-step)
    std::array<double, kTrialFrames> trial_{}; // the full mesh's draw times, s
    int trialCount_ = 0;
    std::uint64_t osdSeen_ = ~std::uint64_t{0};
    platform::TimePoint osdSince_{};
};

DrawOutcome GlPresenter::draw(const DrawInput &in)
{
    DrawOutcome out;
    if (!gl_)
        return out;
    out.drawn = false;
    const receiver::StoredFrame *depthFrame = in.frame.depth ? in.frame.depth.get() : nullptr;
    const receiver::StoredFrame *colorFrame = in.frame.color ? in.frame.color.get() : nullptr;
    const scene::DepthFrameView dv = depthOf(in);
    const hal::Size size = display_.size();
    ensureRendererAndTarget(size, dv);
    // Made before the first frame is drawn, so that frame is snapshot 0 (docs/playing.md: a PNG
    // every N frames from the first).
    if (!snapshotter_ && !config_.snapshotDir.empty())
        snapshotter_ = std::make_unique<render::Snapshotter>(config_.snapshotDir,
                                                             config_.snapshotEvery, "frame");
    if (renderer_ && target_ && dv.data != nullptr) {
        applyOptions(in.mode, dv, in.session.period);
        const bool ok = setPicture(depthFrame, colorFrame, dv, out);
        setOverlays(in);
        if (ok && renderer_->render(*target_))
            output(size, out);
    }
    return out;
}

/// The depth to draw: the frame's, or a flat surface of the colour frame's size without depth.
scene::DepthFrameView GlPresenter::depthOf(const DrawInput &in)
{
    if (in.frame.depth)
        return depthView(*in.frame.depth.get(), in.pts);
    scene::DepthFrameView dv;
    if (in.frame.color) {
        const int w = in.frame.color.get()->image.width;
        const int h = in.frame.color.get()->image.height;
        flatDepth_.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
        dv = {flatDepth_.data(),          w,     h, static_cast<std::size_t>(w),
              scene::SampleFormat::Gray8, in.pts};
    }
    return dv;
}

void GlPresenter::ensureRendererAndTarget(hal::Size size, const scene::DepthFrameView &dv)
{
    if (!renderer_) {
        render::RendererOptions ro;
        ro.box = config_.haptics.renderer.box;
        ro.stereo.frameCompatible = config_.frameCompatible;
        if (config_.meshStep > 0) {
            ro.mesh.mode = render::MeshMode::Fixed;
            ro.mesh.fixedStep = config_.meshStep;
            ro.mesh.tileSize = std::max(ro.mesh.tileSize, config_.meshStep);
        }
        auto r = render::StereoRenderer::create(ro);
        if (r)
            renderer_ = std::move(*r);
        else
            DT_LOG_ONCE(Playback, Error, "Cannot create the stereo renderer: %s", r.error().what);
        // On a GPU the surface the eyes see is the surface the hand touches: every depth sample,
        // from a static grid (no CPU work per frame), unless its draw time says otherwise
        // (checkFullResolution()). A software rasterizer keeps the level of detail (Blocks) and
        // its controller.
        if (renderer_ && config_.meshStep == 0 && config_.lodTarget > 0.0 &&
            !renderer_->rendersInSoftware()) {
            ro.mesh.mode = render::MeshMode::Fixed;
            ro.mesh.fixedStep = 1;
            // In the level of detail's tiles: should it take over, it draws its step-1 tiles
            // from this grid instead of making a second copy (renderer_blocks.cpp).
            if (dv.width > 1 && dv.height > 1)
                ro.mesh.tileSize = render::blockTileFor(dv.width, dv.height);
            fullResolution_ = static_cast<bool>(renderer_->setOptions(ro));
            trialCount_ = 0;
        }
    }
    if (!target_ && renderer_) {
        auto t = render::RenderTarget::create(size.width, size.height);
        if (t)
            target_ = std::move(*t);
        else
            DT_LOG_ONCE(Playback, Error, "Cannot create the render target: %s", t.error().what);
    }
}

/// Blocks' probes read the mean error about a tenth under the drawn surface's (the kitchen at
/// 720x486: 0.40 gives 0.485 levels measured, 0.50 gives 0.53), so it aims at 0.40 for a surface
/// within half a nearness level (docs/benchmarks.md, bench render blocks-*).
void GlPresenter::toBlocks(render::MeshOptions &m, int width, int height)
{
    m.mode = render::MeshMode::Blocks;
    m.tileSize = render::blockTileFor(width, height);
    m.maxStep = m.tileSize;
    m.tolerance = kBlocksTolerance;
}

/// The stereo mode, and the mesh budget of the level of detail (created with the first frame).
void GlPresenter::applyOptions(player::StereoMode mode, const scene::DepthFrameView &dv,
                               double period)
{
    render::RendererOptions ro = renderer_->options();
    ro.mode = toRenderMode(mode);
    // A frame drawn within one refresh period is on screen at its time even after a late one
    // (the next refresh catches up); one that takes longer stays a refresh late until a faster
    // one comes, and the next stall drops a frame. So the target is a share of the refresh
    // period (of the frame period when that is shorter, or the display does not say).
    const double refresh = display_.refreshHz();
    const double budgetPeriod = refresh > 0.0 ? std::min(period, 1.0 / refresh) : period;
    lodTargetSeconds_ = config_.lodTarget * budgetPeriod;
    // Without a fixed step the level of detail is a step per tile drawn from precomputed index
    // ranges (MeshMode::Blocks): its choice costs the prep thread a pass over the probes and the
    // tiles, not over the triangles.
    if (config_.meshStep == 0 && ro.mesh.mode != render::MeshMode::Fixed)
        toBlocks(ro.mesh, dv.width, dv.height);
    if (config_.lodTarget > 0.0 && config_.meshStep == 0 &&
        ro.mesh.mode == render::MeshMode::Blocks) {
        if (!lod_) {
            render::LodOptions lo;
            lo.targetSeconds = lodTargetSeconds_;
            lo.minBlocks =
                std::max<std::size_t>(lo.minBlocks, static_cast<std::size_t>(dv.width) *
                                                        static_cast<std::size_t>(dv.height) / 256);
            lod_.emplace(lo);
        }
        ro.mesh.maxBlocks = lod_->budget();
    }
    (void)renderer_->setOptions(ro);
}

/// Depth (with the prep made ahead, if any) and colour into the renderer. \return the depth's
/// result.
bool GlPresenter::setPicture(const receiver::StoredFrame *depthFrame,
                             const receiver::StoredFrame *colorFrame,
                             const scene::DepthFrameView &dv, DrawOutcome &out)
{
    if (!prepWorker_)
        prepWorker_ = std::make_unique<PrepWorker>();
    render::FramePrep *prep = depthFrame != nullptr ? prepWorker_->take(depthFrame) : nullptr;
    const bool ok = static_cast<bool>(prep != nullptr ? renderer_->setDepth(dv, *prep)
                                                      : renderer_->setDepth(dv));
    render::ColorSpec spec;
    const hal::ImageView *picture = pictureOf(colorFrame, depthFrame, spec);
    if (prep != nullptr && prep->hasRgba) {
        (void)renderer_->setColor(*prep);
    } else if (colorFrame != nullptr) {
        if (auto r = renderer_->setColorFrame(colorFrame->image, colorFrame->dmabuf, spec); !r)
            DT_LOG_ONCE(Playback, Warning, "Color frames not shown: %s", r.error().what);
    } else if (picture != nullptr) {
        (void)renderer_->setColor(*picture, spec);
    }
    if (prep != nullptr) {
        prepWorker_->release(prep);
        out.preparedAhead = true;
    }
    return ok;
}

/// The avatar (proxy and HIP) and the on-screen display.
void GlPresenter::setOverlays(const DrawInput &in)
{
    haptic_task::HapticTask *task = in.session.task.get();
    render::AvatarState avatar;
    if (config_.avatar && task != nullptr) {
        glm::dvec3 hip, proxy;
        if (task->lastPose(hip, proxy)) {
            avatar.visible = true;
            avatar.hip = hip;
            avatar.proxy = proxy;
        }
    }
    renderer_->setAvatar(avatar);
    if (const std::uint64_t n = osdEvents_.load(std::memory_order_relaxed); n != osdSeen_) {
        osdSeen_ = n;
        osdSince_ = clock_.now();
    }
    const bool osdUp = config_.osdSeconds <= 0.0 || in.paused ||
                       platform::toSeconds(clock_.now() - osdSince_) < config_.osdSeconds;
    if (config_.osd) {
        render::OsdState osd;
        osd.visible = osdUp;
        osd.status = in.paused ? "PAUSED" : "PLAYING";
        if (in.session.audio) // the sound's volume, as the remote's VOL+/VOL-/MUTE change it
            osd.status += soundStatus(in.session.audio->volume(), in.session.audio->muted());
        osd.hapticsOn = task != nullptr && task->enabled();
        osd.deviceConnected = task == nullptr || task->deviceConnected();
        osd.remoteConnected = in.remoteConnected;
        osd.force = task != nullptr ? glm::length(task->lastForce()) : 0.0;
        osd.maxForce = std::max(1e-3, config_.haptics.renderer.maxForce);
        osd.stiffness = task != nullptr ? task->stiffness() : 0.0;
        renderer_->setOsd(osd);
    }
}

/// The rendered target to the display, the recording and the snapshots.
void GlPresenter::output(hal::Size size, DrawOutcome &out)
{
    if (target_->blitTo(display_.framebuffer(), size.width, size.height))
        out.drawn = true;
    if (!config_.recordPath.empty() && !recorder_.failed) {
        std::string err;
        if (!recorder_.isOpen())
            err = recorder_.open(config_, target_->width(), target_->height());
        if (err.empty())
            err = recorder_.add(*target_, clock_.now());
        if (err.empty()) {
            out.recorded = true;
        } else {
            recorder_.failed = true;
            out.recordError = std::move(err);
        }
    }
    if (snapshotter_) {
        if (snapshotRequest_.exchange(false))
            snapshotter_->request();
        auto w = snapshotter_->onFrame(*target_);
        if (!w) {
            DT_LOG_ONCE(Playback, Warning, "Snapshot not written: %s", w.error().what);
            char why[160];
            out.snapshotError =
                std::string("a snapshot was not written: ") + w.error().format(why, sizeof why);
        } else if (*w) {
            out.snapshotWritten = true;
        }
    }
}

void GlPresenter::checkFullResolution(double drawSeconds)
{
    trial_[static_cast<std::size_t>(trialCount_ % kTrialFrames)] = drawSeconds;
    if (++trialCount_ < kTrialFrames)
        return;
    std::array<double, kTrialFrames> sorted = trial_;
    std::nth_element(sorted.begin(), sorted.begin() + kTrialFrames / 2, sorted.end());
    const double median = sorted[kTrialFrames / 2];
    if (!(median > lodTargetSeconds_))
        return;
    // Straight to the level of detail's own mesh, so that the frames prepared ahead from now on
    // are made for it (a quadtree of the default options at 4K costs the prep thread a second).
    render::RendererOptions ro = renderer_->options();
    ro.mesh = render::MeshOptions{};
    // The size of the full-resolution grid just drawn.
    toBlocks(ro.mesh, renderer_->mesh().columns(), renderer_->mesh().rows());
    if (lod_)
        ro.mesh.maxBlocks = lod_->budget();
    if (renderer_->setOptions(ro)) {
        fullResolution_ = false;
        DT_LOG(
            Playback, Info,
            "The full-resolution mesh takes %.1f ms to draw (target %.1f ms): level of detail on",
            median * 1e3, lodTargetSeconds_ * 1e3);
    }
}

std::optional<LodSample> GlPresenter::afterPresent(double drawSeconds, bool drawn, bool presented,
                                                   bool prerolling)
{
    if (!renderer_ || !drawn || !presented || prerolling)
        return std::nullopt;
    if (fullResolution_) {
        checkFullResolution(drawSeconds);
        LodSample s;
        s.triangles = static_cast<double>(renderer_->mesh().stats().triangles);
        return s;
    }
    if (!lod_)
        return std::nullopt;
    const render::MeshStats &mesh = renderer_->mesh().stats();
    lod_->update(drawSeconds, mesh);
    LodSample s;
    s.budget = lod_->budget();
    s.limited = mesh.budgetLimited;
    s.triangles = static_cast<double>(mesh.triangles);
    return s;
}

} // namespace

std::unique_ptr<Presenter> makePresenter(const PlaybackConfig &config, hal::Display &display,
                                         platform::Clock &clock, std::atomic<bool> &snapshotRequest,
                                         const std::atomic<std::uint64_t> &osdEvents)
{
    return std::make_unique<GlPresenter>(config, display, clock, snapshotRequest, osdEvents);
}

bool presenterDraws(const hal::Display &display) noexcept
{
    return display.capabilities().hasGlesContext;
}

} // namespace depthtouch::playback
