#pragma once
/// \file
/// \brief PrepWorker: makes the CPU half of upcoming frames (render::FramePrep: mesh and colour
/// conversion) on a thread of its own (kPrepThread), while the render thread draws the current
/// frame and llvmpipe's threads rasterize it; and pictureOf(), the picture the renderer shows for
/// a frame. Up to kSlots frames; a slot keeps its frames referenced until it is released.
///
/// Thread-safety: every member function on one thread (the render thread); the worker thread is
/// internal. Built with EGL/GLES only (gl_presenter.cpp).

#include <array>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>

#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/receiver/receiver.h"
#include "depthtouch/render/renderer.h"

namespace depthtouch::playback {

/// \return the picture the renderer shows for a frame of colour \a color and depth \a depth
/// (either may be null): the colour frame, or a gray depth frame as a picture when there is no
/// colour stream (\a spec then says so); null when neither, or when the colour frame came as
/// dma-bufs (the renderer imports those itself).
const hal::ImageView *pictureOf(const receiver::StoredFrame *color,
                                const receiver::StoredFrame *depth,
                                render::ColorSpec &spec) noexcept;

/// See the file comment.
class PrepWorker {
public:
    static constexpr std::size_t kSlots = 3;

    /// Starts the worker thread; when it cannot start (logged once) nothing is made ahead and
    /// take() gives null.
    PrepWorker();
    /// Stops and joins the worker thread.
    ~PrepWorker();
    PrepWorker(const PrepWorker &) = delete;
    PrepWorker &operator=(const PrepWorker &) = delete;

    /// \return whether the worker thread runs (else submit() queues nothing).
    [[nodiscard]] bool running() const noexcept { return thread_ && thread_->joinable(); }

    /// \brief Queues \a f (a pending frame with depth) unless it is queued already or no slot is
    /// free; a finished slot whose frame is not among the \a pendingCount frames \a pending
    /// (dropped) is reused.
    void submit(const receiver::PairedFrame &f, const receiver::PairedFrame *pending,
                int pendingCount, const render::MeshOptions &mesh, bool convertColor);

    /// \return the finished prep of depth frame \a key (waiting while it is being made), or null
    /// when it was not queued. Give it back with release().
    render::FramePrep *take(const receiver::StoredFrame *key);

    /// \brief Gives back a prep from take().
    void release(render::FramePrep *prep);

    /// \brief Drops every prep and the frame references they hold (seek, new session), waiting
    /// for the one being made (one mesh build): afterwards no frame of the old session is
    /// referenced.
    void clear();

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

        void reset() noexcept;
    };

    /// Guarded by mutex_: a free slot for a new job, or null.
    Slot *freeSlot(const receiver::PairedFrame *pending, int pendingCount) noexcept;
    void run();

    std::mutex mutex_;
    std::condition_variable cv_;
    bool quit_ = false;
    std::array<Slot, kSlots> slots_;
    std::optional<platform::RealtimeThread> thread_; // last: started once the members above exist
};

} // namespace depthtouch::playback
