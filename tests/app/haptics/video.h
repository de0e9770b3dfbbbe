#pragma once
/// \file
/// \brief A synthetic depth video for the scenarios: frame i is the surface z(x, y, i) sampled at
/// PTS i/fps; frames are generated on demand, two at a time (current and next), as the player does.

#include <cmath>
#include <functional>
#include <utility>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::test {

class SyntheticVideo {
public:
    /// z(x, y, frame index) → height, m.
    using Surface = std::function<double(double, double, int)>;

    /// Makes frame i directly (for fast separable surfaces).
    using FrameMaker = std::function<OwnedFrame(int)>;

    SyntheticVideo(SceneBox box, int w, int h, double fps, Surface z,
                   SampleFormat format = SampleFormat::Gray16)
        : box_(box), w_(w), h_(h), fps_(fps), z_(std::move(z)), format_(format), reference_(box)
    {
    }
    SyntheticVideo(SceneBox box, double fps, FrameMaker maker)
        : box_(box), w_(0), h_(0), fps_(fps), maker_(std::move(maker)), reference_(box)
    {
    }

    /// Index of the frame shown at haptic time \a t.
    [[nodiscard]] int frameAt(double t) const
    {
        return static_cast<int>(std::floor(t * fps_ + 1e-9));
    }

    /// Makes sure frames i = frameAt(t) and i+1 exist; \return true when they changed.
    bool advance(double t)
    {
        const int i = frameAt(t);
        if (i == index_)
            return false;
        if (index_ >= 0 && i == index_ + 1) {
            current_ = std::move(next_);
        } else {
            current_ = make(i);
        }
        next_ = make(i + 1);
        index_ = i;
        const DepthFrameView nv = next_.view();
        (void)reference_.setFrames(current_.view(), &nv);
        return true;
    }

    /// Hands the current pair to \a r (call after advance() returned true).
    void feed(HapticRenderer &r) const
    {
        const DepthFrameView nv = next_.view();
        (void)r.setFrames(current_.view(), &nv);
    }

    /// The interpolated surface (paper Eq. 1) at haptic time \a t, for checks.
    const HeightField &reference(double t)
    {
        reference_.setTime(t, true);
        return reference_;
    }

    [[nodiscard]] const SceneBox &box() const { return box_; }
    [[nodiscard]] double quantised(double z) const
    {
        return fromNearness(box_, format_, toNearness(box_, format_, z));
    }

private:
    OwnedFrame make(int i) const
    {
        if (maker_)
            return maker_(i);
        return makeFrame(
            box_, w_, h_, i / fps_, [this, i](double x, double y) { return z_(x, y, i); }, format_);
    }

    SceneBox box_;
    int w_;
    int h_;
    double fps_;
    Surface z_;
    FrameMaker maker_;
    SampleFormat format_ = SampleFormat::Gray16;
    int index_ = -1;
    OwnedFrame current_;
    OwnedFrame next_;
    HeightField reference_;
};

} // namespace depthtouch::haptics::test
