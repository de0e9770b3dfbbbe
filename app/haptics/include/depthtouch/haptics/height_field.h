#pragma once
/// \file
/// \brief The touchable surface: an implicit triangulated height field over the current and the
/// next buffered depth frame, with local surface interpolation (paper IV.B, Eq. 1;
/// docs/architecture.md §3).
///
/// No mesh is ever built: a vertex height is computed from the samples only when an update asks for
/// it, so an update costs the same at 720×486 and at 3840×2160. Thread-safety: thread-bound (the
/// haptic thread); the frames it views must stay alive and unchanged while they are set.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptics {

/// \brief One triangle of the grid: cell (c, r) split by the diagonal (c, r)–(c+1, r+1)
/// (docs/architecture.md §3).
///
/// `upper == 0`: vertices (c, r), (c+1, r), (c+1, r+1) — the half where (u − c) ≥ (v − r).
/// `upper == 1`: vertices (c, r), (c+1, r+1), (c, r+1). Columns/rows are sample indices.
struct TriangleId {
    int c = 0;
    int r = 0;
    int upper = 0;
    friend bool operator==(const TriangleId &, const TriangleId &) = default;
};

/// \return the grid coordinates (column, row) of vertex \a k (0..2) of \a tri, in the order above.
inline void triangleVertex(const TriangleId &tri, int k, int &c, int &r) noexcept
{
    if (k == 0) {
        c = tri.c;
        r = tri.r;
    } else if (k == 1) {
        c = tri.c + 1;
        r = tri.upper ? tri.r + 1 : tri.r;
    } else {
        c = tri.upper ? tri.c : tri.c + 1;
        r = tri.r + 1;
    }
}

/// \brief The three vertices of \a tri on \a surf, in triangleVertex() order.
/// \param[in] surf any surface with `glm::dvec3 vertex(int c, int r)` (scene-box frame, m)
/// \param[out] v the vertices, m
template <class Surface>
inline void triangleVertices(const Surface &surf, const TriangleId &tri,
                             glm::dvec3 (&v)[3]) noexcept
{
    for (int k = 0; k < 3; ++k) {
        int c = 0;
        int r = 0;
        triangleVertex(tri, k, c, r);
        v[k] = surf.vertex(c, r);
    }
}

/// \brief A W×H height field in the scene box, interpolated in time between two frames.
///
/// Frame (docs/architecture.md §3): metres, origin at the box centre, x right, y up, z toward the
/// viewer. Vertex (c, r) is at `x = (c − (W−1)/2)·s`, `y = ((H−1)/2 − r)·s`, `s = box.width/(W−1)`,
/// `z = (v/v_max − 0.5)·box.depth`. Grid coordinates `u = x/s + (W−1)/2` (column) and
/// `v = (H−1)/2 − y/s` (row) are used internally.
///
/// Time (paper Eq. 1): after setTime(t, true) a vertex height is `z_i + (z_{i+1} − z_i)·α`,
/// `α = (t − t_i)/(t_{i+1} − t_i)` clamped to [0, 1]; with setTime(t, false) or no next frame it is
/// z_i (sample-and-hold). A vertex whose height changes by more than the cut threshold between the
/// two frames is held at z_i until the frame boundary instead of being interpolated: a scene cut or
/// the edge of a fast object stays a step that force-jump safety (paper IV.C) can see, rather than
/// a fast ramp that it cannot tell from a firm stroke.
///
/// Holes (docs/architecture.md §3 "Holes"): a sample below its frame's DepthFrameView::holeBelow
/// was not measured. Its vertex lies holeDrop() (1 m) below the back of the box: free space to a
/// HIP anywhere in the box, and a cliff at the hole's border, so that a finger slides off the
/// measured surface into the hole rather than onto an invented one. A vertex that turns from
/// measured to hole (or back) between frames i and i+1 changes by more than any cut threshold and
/// is held at frame i until the boundary, like any cut.
class HeightField {
public:
    HeightField() noexcept = default;
    /// \param box scene box (both sizes > 0, checked by setFrames()).
    explicit HeightField(SceneBox box) noexcept
        : box_(box), halfDepth_(0.5 * box.depth), holeZ_(-halfDepth_ - holeDrop()),
          cut_(0.25 * box.depth)
    {
    }

    /// \brief Views \a current (frame i) and optionally \a next (frame i+1). No copy, no
    /// allocation. \param next may be null (then the surface is held at frame i); same W×H as \a
    /// current, PTS greater than current's. \return Errc::InvalidArgument (and the previous frames
    /// stay set) when a frame is malformed, the sizes differ, the PTS do not increase or the box is
    /// not positive.
    [[nodiscard]] Result<void> setFrames(const DepthFrameView &current,
                                         const DepthFrameView *next) noexcept;

    /// \brief Sets the haptic time \a t (s, same clock as the frames' PTS) and whether to
    /// interpolate.
    void setTime(double t, bool interpolate) noexcept;

    /// \brief Vertices whose height changes by more than \a metres between frame i and i+1 are held
    /// (not interpolated). Default 0.25·box depth; +infinity interpolates every vertex.
    void setCutThreshold(double metres) noexcept
    {
        cutSetting_ = metres;
        cut_ = std::isnan(metres) ? 0.25 * box_.depth : metres;
    }
    /// \return the cut threshold in effect, m.
    [[nodiscard]] double cutThreshold() const noexcept { return cut_; }

    [[nodiscard]] bool valid() const noexcept { return current_.data != nullptr; }
    [[nodiscard]] int columns() const noexcept { return current_.width; }  ///< W
    [[nodiscard]] int rows() const noexcept { return current_.height; }    ///< H
    [[nodiscard]] double spacing() const noexcept { return spacing_; }     ///< s, m
    [[nodiscard]] double alpha() const noexcept { return alpha_; } ///< Eq. 1 weight in [0, 1]
    [[nodiscard]] const SceneBox &box() const noexcept { return box_; }
    [[nodiscard]] const DepthFrameView &current() const noexcept { return current_; }
    [[nodiscard]] bool hasNext() const noexcept { return hasNext_; }
    /// \return frame i+1 (empty when !hasNext()).
    [[nodiscard]] const DepthFrameView &next() const noexcept { return next_; }

    /// Grid ↔ scene-box coordinates (pixels ↔ m).
    [[nodiscard]] double xToColumn(double x) const noexcept { return x * invSpacing_ + halfW_; }
    [[nodiscard]] double yToRow(double y) const noexcept { return halfH_ - y * invSpacing_; }
    [[nodiscard]] double columnToX(double u) const noexcept { return (u - halfW_) * spacing_; }
    [[nodiscard]] double rowToY(double v) const noexcept { return (halfH_ - v) * spacing_; }

    /// \return z of \a frame's sample (c, r), m, without interpolation.
    [[nodiscard]] double frameZ(const DepthFrameView &frame, int c, int r) const noexcept
    {
        const auto far = static_cast<double>(frame.farCode());
        return (static_cast<double>(frame.sample(c, r)) - far) *
                   (box_.depth / (maxSampleValue(frame.format) - far)) -
               0.5 * box_.depth;
    }

    /// \return the interpolated height of vertex (c, r), m. \pre 0 ≤ c < W, 0 ≤ r < H.
    [[nodiscard]] double vertexZ(int c, int r) const noexcept
    {
        if (alpha_ <= 0.0) {
            const std::uint32_t s = load(current_, curWide_, c, r);
            return s < current_.holeBelow
                       ? holeZ_
                       : (static_cast<double>(s) - farCurrent_) * zScaleCurrent_ - halfDepth_;
        }
        std::uint32_t s0;
        std::uint32_t s1;
        if (sameLayout_) {
            // Both frames 16-bit with the same stride (the usual case): one offset for both.
            const std::size_t off = static_cast<std::size_t>(r) * current_.strideBytes +
                                    2 * static_cast<std::size_t>(c);
            std::uint16_t a;
            std::uint16_t b;
            std::memcpy(&a, current_.data + off, sizeof a);
            std::memcpy(&b, next_.data + off, sizeof b);
            s0 = a;
            s1 = b;
        } else {
            s0 = load(current_, curWide_, c, r);
            s1 = load(next_, nextWide_, c, r);
        }
        const double z0 =
            s0 < current_.holeBelow
                ? holeZ_
                : (static_cast<double>(s0) - farCurrent_) * zScaleCurrent_ - halfDepth_;
        const double z1 = s1 < next_.holeBelow
                              ? holeZ_
                              : (static_cast<double>(s1) - farNext_) * zScaleNext_ - halfDepth_;
        const double dz = z1 - z0;
        if (std::fabs(dz) > cut_)
            return z0;
        return z0 + dz * alpha_;
    }

    /// Depth of a hole's vertex under the back of the box, m (see the class comment).
    static constexpr double holeDrop() noexcept { return 1.0; }
    /// How far under the back of the box a height must lie to be on a hole's cliff
    /// (besideHole()), m: a micrometre, above any rounding of the far plane's height.
    static constexpr double kBesideHoleMargin = 1e-6;
    /// \return true when a height from this field (vertexZ(), heightAt()) was measured: no hole's
    /// vertex weighs in it by a thousandth or more (at that weight a hole's vertex drags an
    /// interpolated height holeDrop()/1000, 1 mm, under the back of the box). False for NaN (off
    /// the grid). A measured height is neither a hole nor NaN: !measured(z) && !isnan(z) is a hole.
    [[nodiscard]] bool measured(double z) const noexcept
    {
        return z >= -halfDepth_ - 1e-3 * holeDrop();
    }
    /// \return the z of a hole's vertex, m: −box depth/2 − holeDrop().
    [[nodiscard]] double holeZ() const noexcept { return holeZ_; }
    /// \return true when a height from this field (vertexZ(), heightAt()) lies at least half of
    /// holeDrop() under the box: on or beside a hole, no measured surface.
    [[nodiscard]] bool overHole(double z) const noexcept
    {
        return z < -halfDepth_ - 0.5 * holeDrop();
    }
    /// \return true when a height from this field lies under the back of the box at all: no
    /// measured vertex does (the far plane is the deepest measured height), so it is interpolated
    /// from a hole's vertex, on the cliff at a hole's border.
    [[nodiscard]] bool besideHole(double z) const noexcept
    {
        return z < -halfDepth_ - kBesideHoleMargin;
    }

    /// \return vertex (c, r) in the scene-box frame, m.
    [[nodiscard]] glm::dvec3 vertex(int c, int r) const noexcept
    {
        return {columnToX(c), rowToY(r), vertexZ(c, r)};
    }

    /// \return true when (x, y) (m) lies over the grid (inside the box's x–y extent, borders
    /// included).
    [[nodiscard]] bool contains(double x, double y) const noexcept
    {
        if (!valid())
            return false;
        const double u = xToColumn(x);
        const double v = yToRow(y);
        return u >= 0.0 && u <= current_.width - 1 && v >= 0.0 && v <= current_.height - 1;
    }

    /// \return the surface height h(x, y), m, on the triangle under (x, y). \pre contains(x, y).
    [[nodiscard]] double heightAt(double x, double y) const noexcept
    {
        const double u = xToColumn(x);
        const double v = yToRow(y);
        const TriangleId t = triangleAtGrid(u, v);
        const double fu = u - t.c;
        const double fv = v - t.r;
        const double h00 = vertexZ(t.c, t.r);
        const double h11 = vertexZ(t.c + 1, t.r + 1);
        if (t.upper == 0) {
            const double h10 = vertexZ(t.c + 1, t.r);
            return h00 + fu * (h10 - h00) + fv * (h11 - h10);
        }
        const double h01 = vertexZ(t.c, t.r + 1);
        return h00 + fv * (h01 - h00) + fu * (h11 - h01);
    }

    /// \return the triangle under (x, y). \pre contains(x, y).
    [[nodiscard]] TriangleId triangleAt(double x, double y) const noexcept
    {
        return triangleAtGrid(xToColumn(x), yToRow(y));
    }

private:
    /// The triangle under grid point (u, v), clamped to the grid.
    [[nodiscard]] TriangleId triangleAtGrid(double u, double v) const noexcept
    {
        // Truncation is floor() wherever it matters: for u in (−1, 0) both clamp to column 0.
        const int c = std::clamp(static_cast<int>(u), 0, current_.width - 2);
        const int r = std::clamp(static_cast<int>(v), 0, current_.height - 2);
        return TriangleId{c, r, (u - c) >= (v - r) ? 0 : 1};
    }

    /// Sample (c, r) of \a frame; \a wide: Gray16 (else Gray8). Same value as frame.sample(c, r).
    static std::uint32_t load(const DepthFrameView &frame, bool wide, int c, int r) noexcept
    {
        const std::uint8_t *row = frame.data + static_cast<std::size_t>(r) * frame.strideBytes;
        if (!wide)
            return row[c];
        std::uint16_t v;
        std::memcpy(&v, row + 2 * static_cast<std::size_t>(c), sizeof v);
        return v;
    }

    SceneBox box_{};
    DepthFrameView current_{};
    DepthFrameView next_{};
    bool hasNext_ = false;
    bool curWide_ = false;  ///< current_ is Gray16
    bool nextWide_ = false; ///< next_ is Gray16
    bool sameLayout_ = false; ///< both frames Gray16 with the same stride
    double spacing_ = 0.0;
    double invSpacing_ = 0.0;
    double halfW_ = 0.0;
    double halfH_ = 0.0;
    double halfDepth_ = 0.0;
    double holeZ_ = -holeDrop();
    double zScaleCurrent_ = 0.0; ///< Metres per code above farCurrent_.
    double zScaleNext_ = 0.0;
    double farCurrent_ = 0.0; ///< The far plane's code (DepthFrameView::farCode()).
    double farNext_ = 0.0;
    double alpha_ = 0.0;
    double cutSetting_ = std::nan(""); ///< NaN: 0.25·box depth
    double cut_ = 0.25 * SceneBox{}.depth;
};

} // namespace depthtouch::haptics
