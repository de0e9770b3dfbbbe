/// \file
/// \brief PrepWorker: see prep_worker.h.

#include "prep_worker.h"

#include <algorithm>

#include "depthtouch/platform/log.h"
#include "depthtouch/platform/thread_config.h"
#include "depthtouch/platform/work_queue.h"

#include "depth_view.h"

DT_LOG_CATEGORY(Playback)

namespace depthtouch::playback {

const hal::ImageView *pictureOf(const receiver::StoredFrame *color,
                                const receiver::StoredFrame *depth,
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

void PrepWorker::Slot::reset() noexcept
{
    key = nullptr;
    depth.reset();
    color.reset();
    cancelled = false;
    state = State::Free;
}

PrepWorker::PrepWorker()
{
    thread_.emplace(platform::kPrepThread, platform::kPlainThreadOptions,
                    [this](platform::StopToken) { run(); });
    if (auto r = thread_->start(); !r) {
        DT_LOG_ONCE(Playback, Warning, "No thread to make frames ahead (%s): drawn as they come",
                    r.error().what);
        thread_.reset();
    }
}

PrepWorker::~PrepWorker()
{
    platform::raiseAndNotifyAll(mutex_, quit_, cv_);
    if (thread_)
        thread_->join();
}

PrepWorker::Slot *PrepWorker::freeSlot(const receiver::PairedFrame *pending,
                                       int pendingCount) noexcept
{
    for (Slot &s : slots_)
        if (s.state == State::Free)
            return &s;
    for (Slot &s : slots_) {
        bool wanted = false;
        for (int i = 0; i < pendingCount; ++i)
            wanted = wanted || (pending[i].depth && pending[i].depth.get() == s.key);
        if (s.state == State::Ready && !wanted) {
            s.reset();
            return &s;
        }
    }
    return nullptr;
}

void PrepWorker::submit(const receiver::PairedFrame &f, const receiver::PairedFrame *pending,
                        int pendingCount, const render::MeshOptions &mesh, bool convertColor)
{
    if (!f.depth || !running())
        return;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Slot &s : slots_)
        if (s.state != State::Free && s.key == f.depth.get())
            return;
    Slot *free = freeSlot(pending, pendingCount);
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

render::FramePrep *PrepWorker::take(const receiver::StoredFrame *key)
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

void PrepWorker::release(render::FramePrep *prep)
{
    std::lock_guard<std::mutex> lock(mutex_);
    for (Slot &s : slots_)
        if (&s.prep == prep)
            s.reset();
}

void PrepWorker::clear()
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

void PrepWorker::run()
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
            job->convertColor
                ? pictureOf(job->color ? job->color.get() : nullptr, job->depth.get(), spec)
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

} // namespace depthtouch::playback
