#pragma once
/// \file
/// \brief `depthtouch touch --material SRC`: the depth frames of a replay with a material track
/// attached (docs/materials.md). Material frame k goes with depth frame k and the last one holds
/// (media::MaterialTrack: an image is a still map; a DepthTouch file gives its stream titled
/// `material`), resized nearest-neighbour to the depth grid. Used by cmd_touch.cpp only.
///
/// The replay asks for frames in increasing order and holds two at a time (haptics::replay()):
/// the provider keeps the material of the last kKeptFrames depth frames. Not thread-safe.

#include <array>
#include <cstdio>
#include <memory>
#include <utility>

#include "depthtouch/haptics/replay.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/material_track.h"

namespace depthtouch::cli {

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

} // namespace depthtouch::cli
