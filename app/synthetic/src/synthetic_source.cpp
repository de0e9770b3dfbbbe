/// \file
/// \brief `synthetic:NAME` sources (see synthetic_source.h): a SyntheticRenderer owns a thread with
/// a headless EGL display, its GL ES context and one synthetic::SyntheticScene; the color, depth
/// and material sources of one scene ask it for frames by index. Each frame is drawn once for every
/// stream attached, kept in a small cache until the other stream takes it, and the next frame is
/// drawn ahead while the caller encodes the current one.

#include "depthtouch/synthetic/synthetic_source.h"

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <optional>
#include <string>
#include <thread>

#include "depthtouch/hal/backends.h"
#include "depthtouch/media/image_convert.h"
#include "depthtouch/platform/work_queue.h"

#include "depthtouch/synthetic/synthetic_scene.h"

namespace depthtouch::synthetic {

using media::findShared;
using media::persistentText;
using media::readSpecFrameSize;
using media::wantsDepthStream;

namespace {

/// Frames the renderer keeps for a stream that has not taken them yet.
constexpr std::size_t kCachedFrames = 4;

/// The streams of a scene, as SyntheticRenderer indexes them.
constexpr int kColor = 0;
constexpr int kDepth = 1;
constexpr int kMaterial = 2;
constexpr int kStreams = 3;

int streamOf(const SyntheticSpec &spec) noexcept
{
    return spec.material ? kMaterial : (spec.depth ? kDepth : kColor);
}

std::string numberText(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// "Unknown synthetic scene 'x' (the scenes are head, spheres, cut)", from the scene list.
const char *unknownSceneMessage(std::string_view name)
{
    std::string t = "Unknown synthetic scene '" + std::string(name) + "' (the scenes are";
    const char *sep = " ";
    for (const synthetic::SceneInfo &s : synthetic::listScenes()) {
        t += sep;
        t += s.name;
        sep = ", ";
    }
    return persistentText(t + ")");
}

hal::ImageView viewOf(media::Image &image)
{
    hal::ImageView v;
    v.width = image.width;
    v.height = image.height;
    switch (image.format) {
    case media::PixelFormat::Gray8:
        v.format = hal::PixelFormat::Gray8;
        break;
    case media::PixelFormat::Gray16:
        v.format = hal::PixelFormat::Gray16;
        break;
    case media::PixelFormat::Rgb24:
        v.format = hal::PixelFormat::Rgb24;
        break;
    }
    v.planes[0] = {image.data.data(), static_cast<int>(image.stride)};
    return v;
}

} // namespace

/// \brief Renders frames of one scene on its own thread (the GL context is current there only).
/// Thread-safe: sources on any threads may call take().
class SyntheticRenderer {
public:
    /// Starts the thread and waits until it has its display, context and scene.
    /// Errors: NotSupported (no OpenGL ES display or context; a scene that does not build).
    static Result<std::shared_ptr<SyntheticRenderer>>
    start(const SyntheticSpec &spec, std::shared_ptr<std::atomic<std::uint64_t>> drawnTotal,
          DisplayOpener openDisplay);

    ~SyntheticRenderer()
    {
        platform::raiseAndNotifyAll(mutex_, stop_, wake_);
        if (thread_.joinable())
            thread_.join();
    }
    SyntheticRenderer(const SyntheticRenderer &) = delete;
    SyntheticRenderer &operator=(const SyntheticRenderer &) = delete;

    /// A source of stream \a stream (kColor, kDepth, kMaterial) starts or stops taking frames: the
    /// frames drawn from then on include that stream or not.
    void attach(int stream)
    {
        const std::lock_guard lock(mutex_);
        ++users_[stream];
    }
    void detach(int stream)
    {
        const std::lock_guard lock(mutex_);
        --users_[stream];
    }

    /// \brief Frame \a index of one stream: Rgb24 color, nearness in \a nearFormat (Gray8 or
    /// Gray16), or Rgb24 material codes. \a ahead: the frame the caller will ask next (drawn
    /// meanwhile), if any.
    /// \return the image (scene size). Errors: those of SyntheticScene::render(); Io when the
    /// render thread has ended.
    Result<media::Image> take(std::uint64_t index, int stream, media::PixelFormat nearFormat,
                              std::optional<std::uint64_t> ahead)
    {
        std::unique_lock lock(mutex_);
        const bool depth = stream == kDepth;
        if (depth)
            nearFormat_ = nearFormat;
        for (;;) {
            if (const Entry *e = find(index)) {
                if (e->failed)
                    return unexpected(e->error);
                const media::Image &part = e->images[stream];
                if (!part.empty() && (!depth || part.format == nearFormat)) {
                    media::Image copy = part;
                    if (ahead && find(*ahead) == nullptr) {
                        ahead_ = ahead;
                        lock.unlock();
                        wake_.notify_all();
                    }
                    return copy;
                }
            }
            if (threadEnded_)
                return unexpected(Errc::Io, "The synthetic scene's render thread has ended");
            bool pending = false;
            for (const Want &w : wants_)
                pending = pending || (w.index == index && w.streams[stream]);
            if (!pending) {
                Want w{index, {}};
                w.streams[stream] = true;
                wants_.push_back(w);
            }
            wake_.notify_all();
            const std::uint64_t seen = drawn_;
            done_.wait(lock, [&] { return drawn_ != seen || threadEnded_; });
        }
    }

    [[nodiscard]] double nearMetres() const noexcept { return nearM_; }
    [[nodiscard]] double farMetres() const noexcept { return farM_; }

private:
    struct Entry {
        std::uint64_t index = 0;
        media::Image images[kStreams]; ///< Color, nearness, material; empty when not drawn.
        bool failed = false;
        Error error{};
    };
    struct Want {
        std::uint64_t index = 0;
        bool streams[kStreams] = {};
    };

    SyntheticRenderer(const SyntheticSpec &spec,
                      std::shared_ptr<std::atomic<std::uint64_t>> drawnTotal,
                      DisplayOpener openDisplay)
        : spec_(spec), drawnTotal_(std::move(drawnTotal)), openDisplay_(std::move(openDisplay))
    {
    }

    /// Whether \a e holds every stream \a w asks (an ahead want, with no stream named, is met by
    /// any entry). Called with mutex_ held.
    bool has(const Entry &e, const Want &w) const noexcept
    {
        if (e.failed)
            return true;
        return (!w.streams[kColor] || !e.images[kColor].empty()) &&
               (!w.streams[kDepth] ||
                (!e.images[kDepth].empty() && e.images[kDepth].format == nearFormat_)) &&
               (!w.streams[kMaterial] || !e.images[kMaterial].empty());
    }

    const Entry *find(std::uint64_t index) const noexcept
    {
        for (const Entry &e : cache_)
            if (e.index == index)
                return &e;
        return nullptr;
    }

    /// The render thread: display, context and scene live and die here.
    void run()
    {
        hal::DisplayConfig dc;
        dc.width = 16; // the scene draws into its own framebuffer: the display's can be tiny
        dc.height = 16;
        auto display = openDisplay_();
        std::unique_ptr<synthetic::SyntheticScene> scene;
        Error failure{};
        bool failed = false;
        const auto fail = [&](const std::string &what) {
            failed = true;
            failure =
                Error(Errc::NotSupported,
                      persistentText("No OpenGL ES display for the synthetic scene: " + what));
        };
        if (!display) {
            char buf[256];
            fail(std::string("the headless EGL display failed: ") +
                 display.error().format(buf, sizeof buf));
        } else if (!(*display)->capabilities().hasGlesContext) {
            fail("the headless display has no OpenGL ES context");
        } else if (auto o = (*display)->open(dc); !o) {
            char buf[256];
            fail(std::string("cannot open the headless EGL display: ") +
                 o.error().format(buf, sizeof buf));
        } else if (auto c = (*display)->makeCurrent(); !c) {
            char buf[256];
            fail(std::string("cannot make its GL context current: ") +
                 c.error().format(buf, sizeof buf));
        } else {
            auto s = synthetic::SyntheticScene::create(spec_.scene, spec_.width, spec_.height,
                                                       spec_.fps);
            if (!s) {
                failed = true;
                failure = s.error();
                if (failure.code == Errc::InvalidState)
                    failure.code = Errc::NotSupported; // no GL ES 3 context current
            } else {
                scene = std::move(*s);
            }
        }
        {
            const std::lock_guard lock(mutex_);
            started_ = true;
            startFailed_ = failed;
            startError_ = failure;
            if (scene) {
                nearM_ = scene->nearMetres();
                farM_ = scene->farMetres();
            }
            threadEnded_ = failed;
        }
        done_.notify_all();
        if (!failed)
            serve(*scene);
        scene.reset(); // its GL objects go while the context is current
        if (display && *display)
            (*display)->close();
    }

    void serve(synthetic::SyntheticScene &scene)
    {
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || !wants_.empty() || ahead_.has_value(); });
            if (stop_)
                break;
            Want w;
            if (!wants_.empty()) {
                w = wants_.front();
                wants_.pop_front();
            } else {
                w.index = *ahead_;
                ahead_.reset();
            }
            // A want made while this frame was being drawn ahead is met already.
            if (const Entry *e = find(w.index); e != nullptr && has(*e, w))
                continue;
            // Draw every attached stream, so the other one finds the frame in the cache.
            for (int k = 0; k < kStreams; ++k)
                w.streams[k] = w.streams[k] || users_[k] > 0;
            const media::PixelFormat nearFormat = nearFormat_;
            lock.unlock();

            Entry e;
            e.index = w.index;
            hal::ImageView views[kStreams];
            for (int k = 0; k < kStreams; ++k) {
                if (!w.streams[k])
                    continue;
                e.images[k] =
                    media::Image::make(spec_.width, spec_.height,
                                       k == kDepth ? nearFormat : media::PixelFormat::Rgb24);
                views[k] = viewOf(e.images[k]);
            }
            auto r = scene.render(w.index, views[kColor], views[kDepth], views[kMaterial]);
            if (!r) {
                e.failed = true;
                e.error = r.error();
            }

            lock.lock();
            for (auto it = cache_.begin(); it != cache_.end(); ++it) {
                if (it->index == e.index) {
                    cache_.erase(it);
                    break;
                }
            }
            cache_.push_back(std::move(e));
            while (cache_.size() > kCachedFrames) {
                auto oldest = cache_.begin();
                for (auto it = cache_.begin(); it != cache_.end(); ++it)
                    if (it->index < oldest->index)
                        oldest = it;
                cache_.erase(oldest);
            }
            ++drawn_;
            drawnTotal_->fetch_add(1, std::memory_order_relaxed);
            done_.notify_all();
        }
    }

    const SyntheticSpec spec_;
    const std::shared_ptr<std::atomic<std::uint64_t>> drawnTotal_;
    const DisplayOpener openDisplay_;
    std::thread thread_;

    std::mutex mutex_;
    std::condition_variable wake_; ///< To the render thread: a want, a frame ahead, or stop.
    std::condition_variable done_; ///< From the render thread: started, or a frame drawn.
    // Guarded by mutex_:
    bool stop_ = false;
    bool started_ = false;
    bool startFailed_ = false;
    bool threadEnded_ = false;
    Error startError_{};
    double nearM_ = 0.0;
    double farM_ = 0.0;
    int users_[kStreams] = {};
    media::PixelFormat nearFormat_ = media::PixelFormat::Gray8;
    std::deque<Want> wants_;
    std::optional<std::uint64_t> ahead_;
    std::deque<Entry> cache_;
    std::uint64_t drawn_ = 0;
};

Result<std::shared_ptr<SyntheticRenderer>>
SyntheticRenderer::start(const SyntheticSpec &spec,
                         std::shared_ptr<std::atomic<std::uint64_t>> drawnTotal,
                         DisplayOpener openDisplay)
{
    std::shared_ptr<SyntheticRenderer> r(
        new SyntheticRenderer(spec, std::move(drawnTotal), std::move(openDisplay)));
    r->thread_ = std::thread([raw = r.get()] { raw->run(); });
    std::unique_lock lock(r->mutex_);
    r->done_.wait(lock, [&] { return r->started_; });
    if (r->startFailed_) {
        const Error e = r->startError_;
        lock.unlock();
        return unexpected(e); // the destructor joins the ended thread
    }
    return r;
}

namespace {

/// One stream of a synthetic scene as a FrameSource.
class SyntheticFrameSource final : public media::ConvertingFrameSource {
public:
    SyntheticFrameSource(std::shared_ptr<SyntheticRenderer> renderer, const SyntheticSpec &spec)
        : renderer_(std::move(renderer)), spec_(spec)
    {
        renderer_->attach(streamOf(spec_));
        info_.width = spec.width;
        info_.height = spec.height;
        info_.fps = spec.fps;
        info_.nativeFormat = spec.depth ? media::PixelFormat::Gray8 : media::PixelFormat::Rgb24;
        info_.frameCount = spec.frames;
        info_.description = "synthetic " + spec.scene + " " + std::to_string(spec.width) + "x" +
                            std::to_string(spec.height) + " " + numberText(spec.fps) + " fps " +
                            (spec.material ? "material" : (spec.depth ? "nearness" : "color"));
        if (spec.depth)
            info_.tags = {{"depth_near", numberText(renderer_->nearMetres())},
                          {"depth_far", numberText(renderer_->farMetres())},
                          {"depth_mapping", "inverse_z"}};
    }
    ~SyntheticFrameSource() override { renderer_->detach(streamOf(spec_)); }

    Result<media::SourceFrame> next(media::PixelFormat format, int width, int height) override
    {
        const auto frames = static_cast<std::uint64_t>(spec_.frames);
        if (spec_.frames > 0 && index_ >= frames)
            return unexpected(Errc::EndOfStream, "End of the synthetic clip");
        if (width < 0 || height < 0)
            return unexpected(Errc::InvalidArgument, "Frame size must not be negative");
        // The nearness the scene computes in the depth of the layout asked (16-bit when asked).
        const media::PixelFormat drawn =
            spec_.depth ? (format == media::PixelFormat::Gray16 ? media::PixelFormat::Gray16
                                                                : media::PixelFormat::Gray8)
                        : media::PixelFormat::Rgb24;
        std::optional<std::uint64_t> ahead;
        if (spec_.frames == 0 || index_ + 1 < frames)
            ahead = index_ + 1;
        auto image = renderer_->take(index_, streamOf(spec_), drawn, ahead);
        if (!image)
            return unexpected(image.error());
        media::SourceFrame frame;
        frame.pts = static_cast<double>(index_) / spec_.fps;
        frame.image = std::move(*image);
        if (auto conformed = converter_.conform(frame.image, format, width, height); !conformed)
            return unexpected(conformed.error());
        ++index_;
        return frame;
    }

private:
    std::shared_ptr<SyntheticRenderer> renderer_;
    SyntheticSpec spec_;
    std::uint64_t index_ = 0;
};

} // namespace

Result<SyntheticSpec> parseSyntheticSpec(std::string_view target,
                                         const media::SourceOptions &options)
{
    const std::size_t comma = target.find(',');
    const std::string_view name = target.substr(0, comma);
    const hal::OptionList list(comma == std::string_view::npos ? std::string_view{}
                                                               : target.substr(comma + 1));
    SyntheticSpec spec;
    bool known = false;
    for (const synthetic::SceneInfo &s : synthetic::listScenes())
        known = known || name == s.name;
    if (!known)
        return unexpected(Errc::InvalidArgument, unknownSceneMessage(name));
    spec.scene = std::string(name);

    static constexpr const char *kKeys[] = {"size", "fps", "frames", "stream"};
    if (const std::string_view unknown = list.firstUnknownKey(kKeys, std::size(kKeys));
        !unknown.empty())
        return unexpected(Errc::InvalidArgument,
                          persistentText("Unknown synthetic source option '" +
                                         std::string(unknown) +
                                         "' (the options are size, fps, frames, stream)"));
    DT_TRY(readSpecFrameSize(list, options,
                             "A synthetic scene takes no demuxer or pixel format option",
                             "Synthetic size must be WxH (pixels)", spec.width, spec.height));
    if (spec.width < 16 || spec.height < 16 || spec.width > 4096 || spec.height > 4096)
        return unexpected(Errc::InvalidArgument, "Synthetic size must be 16..4096 pixels a side");

    auto fps = list.getDouble("fps", options.fps);
    if (!fps || !(*fps >= 1.0 && *fps <= 1000.0))
        return unexpected(Errc::InvalidArgument, "Synthetic fps must be 1..1000 frames/s");
    spec.fps = *fps;

    const auto defaultFrames =
        options.loop ? 0 : static_cast<int>(std::lround(kSyntheticDefaultSeconds * spec.fps));
    auto frames = list.getInt("frames", defaultFrames);
    if (!frames || *frames < 0)
        return unexpected(Errc::InvalidArgument,
                          "Synthetic frames must be a count >= 0 (0: endless)");
    spec.frames = *frames;

    const std::string_view stream = list.find("stream").value_or(std::string_view{});
    if (stream == "material" || (stream.empty() && options.streamTitle == "material")) {
        spec.material = true;
        return spec;
    }
    auto depth = wantsDepthStream(stream, options);
    if (!depth)
        return unexpected(depth.error());
    spec.depth = *depth;
    return spec;
}

SyntheticSourceFactory::~SyntheticSourceFactory() = default;

SyntheticSourceFactory::SyntheticSourceFactory(DisplayOpener openDisplay)
    : openDisplay_(std::move(openDisplay))
{
}

std::uint64_t SyntheticSourceFactory::framesDrawn() const noexcept
{
    return drawn_->load(std::memory_order_relaxed);
}

Result<std::unique_ptr<media::FrameSource>>
SyntheticSourceFactory::open(std::string_view target, const media::SourceOptions &options)
{
    auto spec = parseSyntheticSpec(target, options);
    if (!spec)
        return unexpected(spec.error());
    const std::string key = spec->scene + "/" + std::to_string(spec->width) + "x" +
                            std::to_string(spec->height) + "@" + numberText(spec->fps);
    const std::lock_guard lock(mutex_);
    std::shared_ptr<SyntheticRenderer> renderer = findShared(renderers_, key);
    if (!renderer) {
        auto started = SyntheticRenderer::start(*spec, drawn_, openDisplay_);
        if (!started)
            return unexpected(started.error());
        renderer = std::move(*started);
        renderers_.emplace_back(key, renderer);
    }
    return std::unique_ptr<media::FrameSource>(
        std::make_unique<SyntheticFrameSource>(std::move(renderer), *spec));
}

} // namespace depthtouch::synthetic
