#pragma once
/// \file
/// \brief The affine map from a depth sample (column c, row r, nearness v) to the scene box
/// (docs/architecture.md §3 "Vertices"): the one the stereo renderer draws with and the haptic
/// renderer's HeightField touches with (haptics_unit_test checks that the two agree to the bit).
///
/// Thread-safety: value type.

#include <glm/vec3.hpp>

#include "depthtouch/scene/depth_frame.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::scene {

/// \brief `x = x0 + c·dx`, `y = y0 + r·dy`, `z = z0 + (v/v_max)·dz`. Metres.
///
/// For a W×H frame in a box of width b and depth d: dx = s = b/(W−1), dy = −s, x0 = −(W−1)/2·s,
/// y0 = (H−1)/2·s, z0 = −d/2, dz = d (docs/architecture.md §3 "Vertices"). A frame with holes
/// (DepthFrameView::holeBelow > 0) spans the box depth with its measured codes farCode()..v_max
/// instead: z0 = −d/2 − d·f/(v_max − f), dz = d·v_max/(v_max − f), f = farCode().
struct SurfaceMapping {
    int columns = 0;     ///< W, samples per row.
    int rows = 0;        ///< H, rows.
    double x0 = 0.0;     ///< x of column 0, m.
    double y0 = 0.0;     ///< y of row 0, m.
    double dx = 0.0;     ///< x step per column, m (= s).
    double dy = 0.0;     ///< y step per row, m (= −s).
    double z0 = 0.0;     ///< z at nearness 0, m.
    double dz = 0.0;     ///< z span from nearness 0 to v_max, m.
    double vmax = 255.0; ///< v_max of the sample format.

    /// \brief The mapping of \a frame in \a box, computed as the haptic renderer's HeightField
    /// computes its column, row and sample conversions (the same expressions, so the same bits).
    /// \return Errc::InvalidArgument when the box is not positive and finite or the frame is
    /// malformed (DepthFrameView::validate()).
    static Result<SurfaceMapping> of(const SceneBox &box, const DepthFrameView &frame) noexcept;

    /// \return the scene-box point of sample (c, r) with nearness \a v (levels), m.
    [[nodiscard]] glm::dvec3 point(double c, double r, double v) const noexcept
    {
        return {x0 + c * dx, y0 + r * dy, z0 + (v / vmax) * dz};
    }
    /// \return one nearness level in metres along z.
    [[nodiscard]] double levelMetres() const noexcept { return dz / vmax; }
    /// \return box width (x extent), m.
    [[nodiscard]] double width() const noexcept { return dx * (columns - 1); }
    /// \return box height (y extent), m.
    [[nodiscard]] double height() const noexcept { return -dy * (rows - 1); }
    /// \return the picture's width: the box plus half a sample at each side (W pixels, each
    /// centred on its sample), m.
    [[nodiscard]] double pictureWidth() const noexcept { return dx * columns; }
    /// \return the picture's height (H pixels), m.
    [[nodiscard]] double pictureHeight() const noexcept { return -dy * rows; }
};

} // namespace depthtouch::scene
