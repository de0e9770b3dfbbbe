/// \file
/// \brief The demo's feel measure (demo_feel.h): the force log against the clip's decoded depth.

#include "depthtouch/demo/demo_feel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <glm/geometric.hpp>

#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/media/frame_source.h"

namespace depthtouch::demo {

namespace {

/// The clip's depth as the player touches it: 8-bit nearness (the luma of the depth stream), in
/// the default scene box, frame i at media time i / fps.
class ClipSurface final : public DemoSurface {
public:
    /// \return an error text, or empty.
    std::string load(const std::string &clip)
    {
        media::SourceOptions so;
        so.streamTitle = "depth";
        auto src = media::openFfmpegFrameSource(clip, so);
        if (!src)
            return std::string("cannot read the clip's depth: ") + src.error().what;
        fps_ = (*src)->info().fps; // > 0: the stream's rate, or SourceOptions::fps (30)
        for (;;) {
            auto f = (*src)->next(media::PixelFormat::Gray8);
            if (!f)
                break;
            frames_.push_back(std::move(f->image));
        }
        if (frames_.size() < 2)
            return "the clip's depth has fewer than 2 frames";
        field_ = haptics::HeightField(scene::SceneBox{});
        // The backdrop: the nearest surface in the outer tenth of the first frame on both sides.
        const media::Image &f0 = frames_.front();
        int maxV = 0;
        for (int y = 0; y < f0.height; ++y)
            for (int x = 0; x < f0.width; ++x)
                if (x < f0.width / 10 || x >= f0.width - f0.width / 10)
                    maxV = std::max(maxV, static_cast<int>(f0.row(y)[x]));
        backdropZ_ = (maxV / 255.0 - 0.5) * scene::SceneBox{}.depth;
        return {};
    }

    /// Sets the surface at media time \a t (frames i and i + 1 interpolated, as the renderer does).
    void setTime(double t) override
    {
        const auto n = static_cast<long long>(frames_.size());
        const long long i =
            std::clamp(static_cast<long long>(std::floor(t * fps_ + 1e-9)), 0LL, n - 1);
        const scene::DepthFrameView cur = view(static_cast<std::size_t>(i));
        const scene::DepthFrameView next = view(static_cast<std::size_t>(std::min(i + 1, n - 1)));
        (void)field_.setFrames(cur, i + 1 < n ? &next : nullptr);
        field_.setTime(t, true);
        prev_ = view(static_cast<std::size_t>(std::max(i - 1, 0LL)));
        cur_ = cur;
        next_ = next;
    }
    /// \return the surface height under (x, y), m; NaN off the frame.
    [[nodiscard]] double heightAt(double x, double y) const noexcept override
    {
        return field_.contains(x, y) ? field_.heightAt(x, y) : std::nan("");
    }
    /// \return the player's fingertip radius in the clip's box (RendererConfig's default), m.
    [[nodiscard]] double fingerReach() const noexcept override
    {
        haptics::RendererConfig config;
        config.box = field_.box();
        return config.fingerRadiusInBox();
    }
    /// \return true when a sample within a finger's reach of (x, y) (the renderer's stencil, 1.5 %
    /// of the box width) moves by more than the cut threshold from the previous frame to the
    /// current one or from it to the next (of the last setTime()).
    [[nodiscard]] bool cutAt(double x, double y) const noexcept override
    {
        const double reach = fingerReach();
        for (int j = -1; j <= 1; ++j) {
            for (int i = -1; i <= 1; ++i) {
                const double px = x + i * reach;
                const double py = y + j * reach;
                if (!field_.contains(px, py))
                    continue;
                const int c = static_cast<int>(std::lround(field_.xToColumn(px)));
                const int r = static_cast<int>(std::lround(field_.yToRow(py)));
                const double z = field_.frameZ(cur_, c, r);
                if (std::fabs(field_.frameZ(next_, c, r) - z) > field_.cutThreshold() ||
                    std::fabs(z - field_.frameZ(prev_, c, r)) > field_.cutThreshold())
                    return true;
            }
        }
        return false;
    }
    /// \return the height of the backdrop (curtain), m.
    [[nodiscard]] double backdropZ() const noexcept override { return backdropZ_; }

private:
    [[nodiscard]] scene::DepthFrameView view(std::size_t i) const noexcept
    {
        const media::Image &im = frames_[i];
        return {im.data.data(),
                im.width,
                im.height,
                im.stride,
                scene::SampleFormat::Gray8,
                static_cast<double>(i) / fps_};
    }

    std::vector<media::Image> frames_;
    double fps_ = 30.0;
    haptics::HeightField field_;
    scene::DepthFrameView prev_{};
    scene::DepthFrameView cur_{};
    scene::DepthFrameView next_{};
    double backdropZ_ = 0.0;
};

/// Contact updates pressed less than this deep are left out of the stiffness felt, m.
constexpr double kStiffnessMinDepth = 0.0005;
/// The renderer's force clamp, N: updates near it are left out of the stiffness felt.
const double kDemoMaxForce = haptics::RendererConfig{}.maxForce;
/// The haptic task's force slew limit, N/s: updates whose force moved at it (catching up with a
/// proxy that jumped, as at a silhouette) are left out of the stiffness felt.
const double kDemoForceRate = haptic_task::HapticTaskConfig{}.maxForceRate;
/// After a safety release the renderer ramps the force back in over this time, s: those updates
/// are left out of the stiffness felt too.
const double kDemoRampTime = haptics::RendererConfig{}.rampTime;

} // namespace

std::vector<LogRow> readForceLog(const std::string &path)
{
    std::vector<LogRow> rows;
    std::ifstream in(path);
    std::string line;
    std::getline(in, line); // header
    while (std::getline(in, line)) {
        LogRow r;
        int contact = 0;
        int released = 0;
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%d,%d,%lf,%lf", &r.t,
                        &r.hip.x, &r.hip.y, &r.hip.z, &r.proxy.x, &r.proxy.y, &r.proxy.z,
                        &r.force.x, &r.force.y, &r.force.z, &contact, &released, &r.playT,
                        &r.gain) != 14)
            continue;
        r.contact = contact != 0;
        r.released = released != 0;
        rows.push_back(r);
    }
    return rows;
}

std::vector<double> playTimes(const std::vector<LogRow> &rows)
{
    std::vector<double> play(rows.size(), 0.0);
    for (std::size_t i = 0; i < rows.size(); ++i)
        play[i] = rows[i].playT - rows.front().playT;
    return play;
}

std::unique_ptr<DemoSurface> loadClipSurface(const std::string &clip, std::string &error)
{
    auto surface = std::make_unique<ClipSurface>();
    error = surface->load(clip);
    if (!error.empty())
        return nullptr;
    return surface;
}

DemoFeel measureFeel(const std::vector<LogRow> &rows, const std::vector<double> &play,
                     DemoSurface &surface, std::vector<std::array<double, 6>> &plot)
{
    std::vector<haptics::FeelSample> samples(rows.size());
    DemoFeel d;
    constexpr std::size_t kSpeedRows = 10; // lateral speed over 10 updates
    double releasedAt = -1e9;              // play time of the last released update, s
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const LogRow &r = rows[i];
        if (r.released)
            releasedAt = play[i];
        haptics::FeelSample &s = samples[i];
        // The rise of the surface under the HIP's x–y since the update before (feel.h: a surface
        // arriving over the finger covers it), unknown across a loop's restart of media time.
        double before = std::nan("");
        if (i > 0 && r.t >= rows[i - 1].t) {
            surface.setTime(rows[i - 1].t);
            before = surface.heightAt(r.hip.x, r.hip.y);
        }
        surface.setTime(r.t);
        s.t = play[i];
        s.hip = r.hip;
        s.force = r.force;
        s.surfaceZ = surface.heightAt(r.hip.x, r.hip.y);
        s.surfaceRise = s.surfaceZ - before;
        if (s.surfaceZ > r.hip.z) // judged by the distance to the surface, as in bench feel
            s.depthInside = haptics::depthInside(
                [&surface](double x, double y) { return surface.heightAt(x, y); }, r.hip,
                s.surfaceZ - r.hip.z);
        if (surface.fingerReach() > 0.0)
            s.reachSurfaceZ = haptics::reachHeight(
                [&surface](double x, double y) { return surface.heightAt(x, y); }, r.hip.x, r.hip.y,
                surface.fingerReach());
        s.released = r.released;
        s.surfaceCut = surface.cutAt(r.proxy.x, r.proxy.y) ||
                       (i > 0 && surface.cutAt(rows[i - 1].proxy.x, rows[i - 1].proxy.y));
        const std::size_t j = i >= kSpeedRows ? i - kSpeedRows : 0;
        const double span = play[i] - play[j];
        const double speed =
            span > 0.0 ? std::hypot(r.hip.x - rows[j].hip.x, r.hip.y - rows[j].hip.y) / span : 0.0;
        s.sliding = r.contact && speed > 0.002;
        s.held = r.contact && speed <= 0.002;
        const double dt = i + 1 < rows.size() ? play[i + 1] - play[i] : 0.0;
        const double under = surface.heightAt(r.proxy.x, r.proxy.y);
        const bool onFigure = r.contact && under > surface.backdropZ() + kFigureMargin;
        if (r.contact) {
            d.contactSeconds += dt;
            if (onFigure)
                d.figureSeconds += dt;
            const double depth = glm::length(r.proxy - r.hip);
            const double force = glm::length(r.force);
            const double step = i > 0 ? play[i] - play[i - 1] : 0.0;
            const bool slewing =
                i > 0 && glm::length(r.force - rows[i - 1].force) >= 0.9 * kDemoForceRate * step;
            // The renderer's ramp after its release, and the task's output ramp after a watchdog
            // trip (a late wake-up on a loaded machine): a ramped force is not the surface's.
            const bool ramping = play[i] - releasedAt < kDemoRampTime || r.gain < 1.0;
            const bool resting = std::abs(r.proxy.z - under) < kRestTolerance;
            if (!r.released && !slewing && !ramping && resting && depth > kStiffnessMinDepth &&
                force < 0.95 * kDemoMaxForce)
                (onFigure ? d.figureStiffness : d.backdropStiffness).push_back(force / depth);
        }
        plot.push_back({play[i], glm::length(r.force), r.contact ? 1.0 : 0.0, 1e3 * r.hip.z,
                        1e3 * s.surfaceZ, onFigure ? 1.0 : 0.0});
    }
    d.feel = haptics::computeFeel(samples);
    return d;
}

} // namespace depthtouch::demo
