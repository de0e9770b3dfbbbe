#pragma once
/// \file
/// \brief Depth data enhancement (paper §V.B): median filter → feature points sampled adaptively
/// from the depth's variation → 2-D Delaunay triangulation → Gaussian smoothing of the mesh heights
/// → re-render of the mesh into a depth map; plus the measures that say what it did (points kept,
/// error, roughness, edges).
///
/// All depths are nearness levels (0 = far plane, v_max = near plane; docs/architecture.md §3) as
/// float; positions are pixels (column x right, row y down). Level thresholds in the options
/// default to an 8-bit scale (v_max = 255); use EnhanceOptions::forScale() for 16-bit nearness.
///
/// The mesh is a model of the surface with no more vertices than the error tolerance needs: flat
/// and planar regions get a few large triangles (their sensor noise disappears), depth edges and
/// curved surfaces get small ones (edges stay sharp). Thread-safety: every function is reentrant
/// (no shared state).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "depthtouch/depth/plane.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::depth {

/// \brief A feature point: a pixel position (column x, row y).
struct PixelPoint {
    int x = 0;
    int y = 0;
    friend bool operator==(const PixelPoint &, const PixelPoint &) = default;
};

/// \brief A triangle mesh over the image plane: vertex positions (pixels), heights (nearness
/// levels) and triangles as counter-clockwise (in x right, y down: clockwise on screen) vertex
/// index triples.
struct Mesh {
    std::vector<PixelPoint> vertices;
    std::vector<float> heights;                          ///< One per vertex (nearness levels).
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< Indices into vertices.
};

/// \brief What decides where a block of the sampling quadtree is split.
enum class SamplingCriterion : std::uint8_t {
    /// Split while the depth inside the block departs from the bilinear interpolation of its four
    /// corners by
    /// more than the tolerance on average (mean abs), or by more than outlierFactor × tolerance at
    /// any sample.
    /// Planes, however steep, stay coarse; curvature and edges (where the gradient changes) refine;
    /// noise below
    /// the tolerance does not. Default: the model needs no more points than the tolerance requires.
    LinearError,
    /// Paper-literal first-gradient analysis: split while block side × the mean first-order
    /// gradient magnitude
    /// in the block (Sobel, levels/pixel) exceeds the tolerance, i.e. while the depth varies across
    /// the block by
    /// more than the tolerance. Density ∝ (gradient / tolerance)²: steep planes and noise get dense
    /// points.
    Gradient,
};

/// \brief Options of samplePoints().
struct SamplingOptions {
    float tolerance = 1.0f; ///< Error tolerance in nearness levels (> 0); smaller → more points.
    float outlierFactor =
        4.0f; ///< LinearError: a single sample off by more than this × tolerance splits.
    SamplingCriterion criterion = SamplingCriterion::LinearError;
    int maxBlock = 32; ///< Largest block side (pixels): the sparsest point spacing. ≥ minBlock.
    int minBlock = 1; ///< Smallest block side (pixels): the densest spacing, at edges. ≥ 1. With 1,
                      ///< no triangle spans a depth step wider than one pixel.
};

/// \brief Paper §V.B step 2: feature points sampled adaptively over a quadtree of blocks covering
/// the image; a block is split (see SamplingCriterion) until it meets the tolerance or reaches
/// minBlock; the points are the corners of the final blocks, so the four image corners and the
/// border are always included and the points' convex hull is the whole image. \param[in] filtered
/// W×H median-filtered depth (levels), W, H ≥ 2 \return the points, each once, in row-major order
/// of discovery (no particular order is promised).
std::vector<PixelPoint> samplePoints(const Plane<float> &filtered, const SamplingOptions &options);

/// \brief Paper §V.B step 3: 2-D Delaunay triangulation of \a points in image coordinates (CGAL
/// Delaunay_triangulation_2, exact predicates). Heights are taken from \a heights at each point.
/// \param[in] points distinct pixel positions inside \a heights
/// \param[in] heights W×H depth (levels) the vertices take their height from
/// \return the mesh; Errc::InvalidArgument when fewer than 3 points, duplicates, points outside the
/// plane, or
///         all points collinear; Errc::NotSupported when built without CGAL.
Result<Mesh> triangulate(const std::vector<PixelPoint> &points, const Plane<float> &heights);

/// \brief Options of smoothHeights().
struct SmoothOptions {
    int iterations = 1; ///< Smoothing passes (0 = none); more passes widen the Gaussian.
    float sigma = 1.0f; ///< Gaussian width in units of the vertex's mean edge length (> 0).
    float edgeThreshold =
        2.0f; ///< Levels: a mesh edge whose line departs from the surface by more than this
              ///< crosses a depth discontinuity and is not smoothed across.
};

/// \brief Paper §V.B step 4: Gaussian smoothing of the vertex heights over the mesh neighbourhood.
///
/// Each pass replaces every vertex height by the value at the vertex of the plane fitted by
/// weighted least squares to the vertex and its 1-ring neighbours, with Gaussian weights
/// `exp(−(d/(σ·d̄))²/2)` of the image distance d (d̄: mean distance to the neighbours). A
/// Gaussian-weighted plane fit instead of a weighted mean: any plane is reproduced exactly, so
/// tilted surfaces are not bent at irregular neighbourhoods and borders. Neighbours across a depth
/// discontinuity are left out: the mesh edge to them is checked against \a surface (largest
/// departure of the surface along the edge from the straight line > edgeThreshold). A vertex with
/// fewer than three usable points keeps its height. \param[in,out] mesh triangulated mesh
/// \param[in] surface W×H depth the mesh was made from (median-filtered)
void smoothHeights(Mesh &mesh, const Plane<float> &surface, const SmoothOptions &options);

/// \brief Paper §V.B step 5: renders the mesh into a W×H depth map by rasterising each triangle and
/// interpolating heights barycentrically at pixel centres (pixel (x, y) is the point (x, y)).
/// Exact for planes up to float rounding.
/// \param[out] uncovered if not null: number of pixels outside every triangle (left at 0); 0 for a
/// mesh made
///             by samplePoints() + triangulate().
Plane<float> renderMesh(const Mesh &mesh, int width, int height, std::size_t *uncovered = nullptr);

/// \brief Options of the measures in EnhanceReport.
struct MeasureOptions {
    /// Flat region: pixels whose (2·flatMargin+1)² neighbourhood has first-order gradient below
    /// this (levels/pixel) in the median-filtered input. Roughness is measured there.
    float flatGradient = 1.0f;
    int flatMargin = 3;
    /// Strong edges: gradient magnitude of the median-filtered input of at least this
    /// (levels/pixel).
    float edgeGradient = 5.0f;
    /// Edge contrast = max − min of the depth in the (2·edgeRadius+1)² window around an edge pixel.
    int edgeRadius = 2;
};

/// \brief Options of enhance().
struct EnhanceOptions {
    int medianRadius = 2; ///< Median window (2r+1)²: 5×5 by default. 0 = no median filter.
    SamplingOptions sampling{};
    SmoothOptions smoothing{};
    MeasureOptions measure{};

    /// Defaults with every level threshold scaled from 8-bit to nearness of full scale \a vmax
    /// (e.g. 65535: tolerance 257 levels).
    static EnhanceOptions forScale(double vmax);
};

/// \brief Surface roughness and edge sharpness of one depth map, measured on masks of a reference
/// map.
struct SurfaceMeasures {
    double roughness =
        0.0; ///< RMS of the 4-neighbour Laplacian over the flat mask (levels); 0 on planes.
    double edgeContrast = 0.0; ///< Mean local depth range at strong-edge pixels (levels).
};

/// \brief What enhance() did and how well.
struct EnhanceReport {
    std::size_t pixels = 0; ///< W·H.
    std::size_t points = 0; ///< Feature points (mesh vertices) kept.
    std::size_t triangles = 0;
    double meanAbsError =
        0.0;               ///< |enhanced − median-filtered input|, mean over all pixels (levels).
    double rmsError = 0.0; ///< Same, root mean square.
    double p99AbsError = 0.0;   ///< Same, 99th percentile.
    double maxAbsError = 0.0;   ///< Same, maximum (at depth edges, where triangles span the step).
    std::size_t flatPixels = 0; ///< Size of the flat mask (MeasureOptions).
    std::size_t edgePixels = 0; ///< Size of the strong-edge mask.
    SurfaceMeasures input;      ///< The depth given to enhance().
    SurfaceMeasures median;     ///< After the median filter.
    SurfaceMeasures enhanced;   ///< The result.

    /// points / pixels.
    [[nodiscard]] double pointsFraction() const noexcept
    {
        return pixels == 0 ? 0.0 : static_cast<double>(points) / static_cast<double>(pixels);
    }
};

/// \brief The enhanced depth map with its report.
struct EnhanceResult {
    Plane<float> depth; ///< W×H nearness levels.
    EnhanceReport report;
};

/// \brief Runs the whole §V.B pipeline on a hole-free depth map (fill it first: fill.h) and
/// measures it. \param[in] nearness W×H nearness levels, W, H ≥ 2, no holes \return result and
/// report; Errc::InvalidArgument for a map smaller than 2×2 or invalid options
///         (tolerance ≤ 0, minBlock < 1, maxBlock < minBlock, medianRadius < 0), Errc::NotSupported
///         when built without CGAL.
Result<EnhanceResult> enhance(const Plane<float> &nearness, const EnhanceOptions &options);

/// \brief Roughness and edge contrast of \a depth on the flat and edge masks of \a reference (both
/// W×H). \param[out] flatPixels, edgePixels if not null: the mask sizes.
SurfaceMeasures measureSurface(const Plane<float> &reference, const Plane<float> &depth,
                               const MeasureOptions &options, std::size_t *flatPixels = nullptr,
                               std::size_t *edgePixels = nullptr);

} // namespace depthtouch::depth
