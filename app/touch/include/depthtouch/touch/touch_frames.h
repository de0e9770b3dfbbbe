#pragma once
/// \file
/// \brief The depth frames of `depthtouch touch`'s offline replay (haptics::replay()), as
/// haptics::FrameProvider adapters: a file's depth video read by a receiver::DepthFile, the same
/// with a material track attached (docs/materials.md), and frames that a stop flag ends.
///
/// A material track's frame k goes with depth frame k and the last one holds
/// (media::MaterialTrack: an image is a still map; a DepthTouch file gives its stream titled
/// `material`), resized nearest-neighbour to the depth grid. The replay asks for frames in
/// increasing order and holds two at a time: MaterialFrameProvider keeps the material of the last
/// kKeptFrames depth frames. Frames are scene::DepthFrameView (docs/architecture.md §3).
/// Thread-safety: not thread-safe (the replay's thread uses them); StoppableFrames' flag may be
/// set from any thread or a signal handler.

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <utility>

#include "depthtouch/haptics/replay.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/material_track.h"
#include "depthtouch/receiver/depth_file.h"

namespace depthtouch::touch {

/// \brief The depth frames of a replay that a stop flag ends: once it is set, every frame fails
/// with Errc::Timeout (the replay asks for the next frame on every update of a video of two frames
/// or more).
class StoppableFrames final : public haptics::FrameProvider {
public:
    /// \param inner the frames (outlives this); \param stop the flag (outlives this).
    StoppableFrames(haptics::FrameProvider &inner, const std::atomic<bool> &stop) noexcept
        : inner_(inner), stop_(stop)
    {
    }
    [[nodiscard]] std::size_t frameCount() const noexcept override { return inner_.frameCount(); }
    Result<scene::DepthFrameView> frame(std::size_t i) noexcept override
    {
        if (stop_.load(std::memory_order_relaxed))
            return unexpected(Errc::Timeout, "stopped by a signal");
        return inner_.frame(i);
    }

private:
    haptics::FrameProvider &inner_;
    const std::atomic<bool> &stop_;
};

/// \brief A receiver::DepthFile (opened) as the replay's frame provider. Errors: the file's.
class DepthFileFrames final : public haptics::FrameProvider {
public:
    explicit DepthFileFrames(std::unique_ptr<receiver::DepthFile> file) : file_(std::move(file)) {}
    [[nodiscard]] std::size_t frameCount() const noexcept override { return file_->frameCount(); }
    Result<scene::DepthFrameView> frame(std::size_t i) noexcept override { return file_->frame(i); }
    [[nodiscard]] const receiver::DepthFile &file() const noexcept { return *file_; }

private:
    std::unique_ptr<receiver::DepthFile> file_;
};

/// \brief A FrameProvider whose frames carry the material of a media::MaterialTrack.
class MaterialFrameProvider final : public haptics::FrameProvider {
public:
    /// Material frames kept for the replay's frames i and i+1 (and a margin).
    static constexpr std::size_t kKeptFrames = 4;

    /// \param depth the depth frames; \param source the material codes (read as Rgb24).
    MaterialFrameProvider(std::unique_ptr<haptics::FrameProvider> depth,
                          std::unique_ptr<media::FrameSource> source)
        : depth_(std::move(depth)), source_(std::move(source)), track_(*source_)
    {
    }

    [[nodiscard]] std::size_t frameCount() const noexcept override { return depth_->frameCount(); }

    /// \return depth frame \a i with its material. Errors: the depth's; the material source's
    /// (Errc::InvalidArgument when it has no frame); Errc::InvalidArgument for a frame older than
    /// the kKeptFrames last ones.
    Result<scene::DepthFrameView> frame(std::size_t i) noexcept override
    {
        auto view = depth_->frame(i);
        if (!view)
            return view;
        if (i + kKeptFrames < read_)
            return unexpected(Errc::InvalidArgument, "material frames are read in order only");
        while (read_ <= i) {
            auto image = track_.next(view->width, view->height);
            if (!image)
                return unexpected(image.error());
            kept_[read_ % kKeptFrames] = std::move(*image);
            ++read_;
        }
        const media::Image &m = kept_[i % kKeptFrames];
        view->material = {m.data.data(), m.stride};
        return view;
    }

    /// \return material frames read from the source (the rest of the depth frames held the last).
    [[nodiscard]] long long framesRead() const noexcept { return track_.framesRead(); }

private:
    std::unique_ptr<haptics::FrameProvider> depth_;
    std::unique_ptr<media::FrameSource> source_;
    media::MaterialTrack track_;
    std::array<media::Image, kKeptFrames> kept_{};
    std::size_t read_ = 0; ///< Material frames made so far (for depth frames 0 .. read_ − 1).
};

} // namespace depthtouch::touch
