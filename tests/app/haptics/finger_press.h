#pragma once
/// \file
/// \brief Still 8-bit tables and a finger pressed on them, shared by the hole and release tests
/// (finger_hole_test.cpp, finger_release_test.cpp): frames are fed with no next frame (no Eq. 1
/// interpolation), so that what changes between them changes in one update.

#include <cmath>
#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "app/haptics/finger_log.h"
#include "app/haptics/synthetic.h"
#include "app/haptics/video.h"
#include "depthtouch/haptics/finger_renderer.h"

namespace depthtouch::haptics::test {

inline constexpr int kStillW = 320; ///< Frame width, pixels.
inline constexpr int kStillH = 240; ///< Frame height, pixels.

/// An 8-bit frame of a table at −5 mm with holes where \a hole(x, y), coded as `encode` codes
/// them (docs/architecture.md §3 "Holes"): holes 0 under the threshold 24, measured nearness n at
/// 48 + n·(255 − 48)/255. With \a threshold 0, as a file without holes: n itself, and code 0
/// (the far plane) where the hole is. Raised by \a over(x, y) (m) where that is given (an object,
/// a slope).
inline OwnedFrame tableWithHoles(const std::function<bool(double, double)> &hole,
                                 std::uint32_t threshold,
                                 const std::function<double(double, double)> &over = nullptr)
{
    const double far = 2.0 * threshold; // DepthFrameView::farCode()
    OwnedFrame f(kStillW, kStillH, SampleFormat::Gray8, 0.0);
    const auto code = [far](double z) {
        const double n = (z / kBox.depth + 0.5) * 255.0;
        return static_cast<std::uint32_t>(std::lround(far + n * (255.0 - far) / 255.0));
    };
    for (int r = 0; r < kStillH; ++r)
        for (int c = 0; c < kStillW; ++c) {
            const double x = sampleX(kBox, kStillW, c);
            const double y = sampleY(kBox, kStillW, kStillH, r);
            f.set(c, r, hole(x, y) ? 0u : code(-0.005 + (over ? over(x, y) : 0.0)));
        }
    f.setHoleBelow(threshold);
    return f;
}

/// A new finger (the default config) pressed at \a hip (m): it comes down onto it from 4 mm above
/// over the first 50 updates, then is fed still frames in turn at 1 kHz.
struct FramePress {
    explicit FramePress(const glm::dvec3 &at) : hip(at)
    {
        finger.reset(hip + glm::dvec3(0.0, 0.0, 0.004));
    }
    /// \a n updates on \a frame, the HIP moved up from \a from to \a to (m) over them.
    void run(const OwnedFrame &frame, int n, double from = 0.0, double to = 0.0)
    {
        ASSERT_TRUE(finger.setFrames(frame.view(), nullptr));
        for (int i = 0; i < n; ++i, ++k) {
            const double t = k / kRate;
            const double lift = k < 50 ? 0.004 * (1.0 - k / 50.0) : 0.0;
            const double moved = from + (to - from) * i / n;
            log.out.push_back(finger.update(hip + glm::dvec3(0.0, 0.0, lift + moved), t));
            log.t.push_back(t);
        }
    }
    [[nodiscard]] double force() const { return glm::length(log.out.back().force); }
    [[nodiscard]] int trips() const
    {
        int n = 0;
        for (const HapticOutput &o : log.out)
            n += o.released ? 1 : 0;
        return n;
    }

    FingerRenderer finger = makeFinger();
    glm::dvec3 hip;
    Log log;
    int k = 0;
};

} // namespace depthtouch::haptics::test
