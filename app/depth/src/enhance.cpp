/// \file
/// \brief Depth enhancement pipeline (see enhance.h). The Delaunay step lives in delaunay.cpp
/// (CGAL).

#include "depthtouch/depth/enhance.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "depthtouch/depth/filters.h"

namespace depthtouch::depth {

namespace {

/// A quadtree block: the pixel rectangle [x0, x1] × [y0, y1], corners inclusive, x1 > x0, y1 > y0.
struct Block {
    int x0, y0, x1, y1;
};

/// True when the block's depth departs from the bilinear interpolation of its four corners by more
/// than \a meanLimit on average or by more than \a maxLimit at any sample.
bool exceedsLinearError(const Plane<float> &d, const Block &b, float meanLimit, float maxLimit)
{
    const float c00 = d.at(b.x0, b.y0);
    const float c10 = d.at(b.x1, b.y0);
    const float c01 = d.at(b.x0, b.y1);
    const float c11 = d.at(b.x1, b.y1);
    const float invW = 1.0f / static_cast<float>(b.x1 - b.x0);
    const float invH = 1.0f / static_cast<float>(b.y1 - b.y0);
    double sum = 0.0;
    for (int y = b.y0; y <= b.y1; ++y) {
        const float v = static_cast<float>(y - b.y0) * invH;
        const float left = c00 + (c01 - c00) * v;
        const float right = c10 + (c11 - c10) * v;
        for (int x = b.x0; x <= b.x1; ++x) {
            const float u = static_cast<float>(x - b.x0) * invW;
            const float e = std::fabs(d.at(x, y) - (left + (right - left) * u));
            if (e > maxLimit)
                return true;
            sum += static_cast<double>(e);
        }
    }
    const double n = static_cast<double>(b.x1 - b.x0 + 1) * static_cast<double>(b.y1 - b.y0 + 1);
    return sum / n > static_cast<double>(meanLimit);
}

/// Mean of \a g over the block.
double blockMean(const Plane<float> &g, const Block &b)
{
    double sum = 0.0;
    for (int y = b.y0; y <= b.y1; ++y)
        for (int x = b.x0; x <= b.x1; ++x)
            sum += static_cast<double>(g.at(x, y));
    return sum / (static_cast<double>(b.x1 - b.x0 + 1) * static_cast<double>(b.y1 - b.y0 + 1));
}

std::int64_t cross(PixelPoint o, PixelPoint a, PixelPoint b)
{
    return static_cast<std::int64_t>(a.x - o.x) * (b.y - o.y) -
           static_cast<std::int64_t>(a.y - o.y) * (b.x - o.x);
}

/// Largest departure of \a surface along the segment a–b from the straight line between its end
/// values.
float departureAlong(const Plane<float> &surface, PixelPoint a, PixelPoint b)
{
    const int n = std::max(std::abs(b.x - a.x), std::abs(b.y - a.y));
    const double ha = static_cast<double>(surface.at(a.x, a.y));
    const double hb = static_cast<double>(surface.at(b.x, b.y));
    if (n <= 1)
        return static_cast<float>(std::fabs(hb - ha));
    float worst = 0.0f;
    for (int k = 1; k < n; ++k) {
        const double t = static_cast<double>(k) / n;
        const int x = static_cast<int>(std::lround(a.x + t * (b.x - a.x)));
        const int y = static_cast<int>(std::lround(a.y + t * (b.y - a.y)));
        const auto line = static_cast<float>(ha + t * (hb - ha));
        worst = std::max(worst, std::fabs(surface.at(x, y) - line));
    }
    return worst;
}

/// Flat and strong-edge masks of a reference depth map (MeasureOptions).
struct Masks {
    Plane<std::uint8_t> flat;
    Plane<std::uint8_t> edge;
    std::size_t flatCount = 0;
    std::size_t edgeCount = 0;
};

Masks makeMasks(const Plane<float> &reference, const MeasureOptions &o)
{
    const Plane<float> grad = gradientMagnitude(reference);
    const Plane<float> gradAround = maxFilter(grad, o.flatMargin);
    Masks m{Plane<std::uint8_t>(reference.width, reference.height, 0),
            Plane<std::uint8_t>(reference.width, reference.height, 0)};
    for (std::size_t i = 0; i < reference.size(); ++i) {
        if (gradAround.samples[i] < o.flatGradient) {
            m.flat.samples[i] = 1;
            ++m.flatCount;
        }
        if (grad.samples[i] >= o.edgeGradient) {
            m.edge.samples[i] = 1;
            ++m.edgeCount;
        }
    }
    return m;
}

SurfaceMeasures measureWithMasks(const Plane<float> &depth, const Masks &m, const MeasureOptions &o)
{
    SurfaceMeasures s;
    const Plane<float> lap = laplacian(depth);
    double sumSq = 0.0;
    for (std::size_t i = 0; i < depth.size(); ++i)
        if (m.flat.samples[i] != 0)
            sumSq += static_cast<double>(lap.samples[i]) * static_cast<double>(lap.samples[i]);
    s.roughness = m.flatCount == 0 ? 0.0 : std::sqrt(sumSq / static_cast<double>(m.flatCount));

    double contrast = 0.0;
    for (int y = 0; y < depth.height; ++y) {
        for (int x = 0; x < depth.width; ++x) {
            if (m.edge.at(x, y) == 0)
                continue;
            float lo = depth.at(x, y);
            float hi = lo;
            for (int dy = -o.edgeRadius; dy <= o.edgeRadius; ++dy)
                for (int dx = -o.edgeRadius; dx <= o.edgeRadius; ++dx) {
                    const float v = depth.clamped(x + dx, y + dy);
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            contrast += static_cast<double>(hi - lo);
        }
    }
    s.edgeContrast = m.edgeCount == 0 ? 0.0 : contrast / static_cast<double>(m.edgeCount);
    return s;
}

} // namespace

std::vector<PixelPoint> samplePoints(const Plane<float> &filtered, const SamplingOptions &options)
{
    const int w = filtered.width;
    const int h = filtered.height;
    if (w < 2 || h < 2)
        return {};
    const int minBlock = std::max(1, options.minBlock);
    const int maxBlock = std::max(minBlock, options.maxBlock);
    Plane<float> grad;
    if (options.criterion == SamplingCriterion::Gradient)
        grad = gradientMagnitude(filtered);

    Plane<std::uint8_t> used(w, h, 0);
    std::vector<Block> stack;
    for (int y0 = 0; y0 < h - 1; y0 += maxBlock)
        for (int x0 = 0; x0 < w - 1; x0 += maxBlock)
            stack.push_back(
                Block{x0, y0, std::min(x0 + maxBlock, w - 1), std::min(y0 + maxBlock, h - 1)});

    while (!stack.empty()) {
        const Block b = stack.back();
        stack.pop_back();
        const int side = std::max(b.x1 - b.x0, b.y1 - b.y0);
        bool split = false;
        if (side > minBlock) {
            if (options.criterion == SamplingCriterion::LinearError)
                split =
                    exceedsLinearError(filtered, b, options.tolerance,
                                       options.tolerance * std::max(1.0f, options.outlierFactor));
            else
                split = side * blockMean(grad, b) > static_cast<double>(options.tolerance);
        }
        if (!split) {
            used.at(b.x0, b.y0) = 1;
            used.at(b.x1, b.y0) = 1;
            used.at(b.x0, b.y1) = 1;
            used.at(b.x1, b.y1) = 1;
            continue;
        }
        const int xm = (b.x0 + b.x1) / 2;
        const int ym = (b.y0 + b.y1) / 2;
        const bool splitX = b.x1 - b.x0 >= 2;
        const bool splitY = b.y1 - b.y0 >= 2;
        const int xs[3] = {b.x0, splitX ? xm : b.x1, b.x1};
        const int ys[3] = {b.y0, splitY ? ym : b.y1, b.y1};
        for (int j = 0; j < (splitY ? 2 : 1); ++j)
            for (int i = 0; i < (splitX ? 2 : 1); ++i)
                stack.push_back(Block{xs[i], ys[j], xs[i + 1], ys[j + 1]});
    }

    std::vector<PixelPoint> points;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (used.at(x, y) != 0)
                points.push_back(PixelPoint{x, y});
    return points;
}

void smoothHeights(Mesh &mesh, const Plane<float> &surface, const SmoothOptions &options)
{
    const std::size_t n = mesh.vertices.size();
    if (options.iterations <= 0 || n == 0 || mesh.heights.size() != n)
        return;

    // 1-ring neighbours that lie on the same surface (the mesh edge does not cross a depth
    // discontinuity).
    std::vector<std::vector<std::uint32_t>> ring(n);
    for (const auto &t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[static_cast<std::size_t>(k)];
            const std::uint32_t b = t[static_cast<std::size_t>((k + 1) % 3)];
            ring[a].push_back(b);
            ring[b].push_back(a);
        }
    for (std::size_t i = 0; i < n; ++i) {
        auto &r = ring[i];
        std::sort(r.begin(), r.end());
        r.erase(std::unique(r.begin(), r.end()), r.end());
        r.erase(std::remove_if(r.begin(), r.end(),
                               [&](std::uint32_t j) {
                                   return departureAlong(surface, mesh.vertices[i],
                                                         mesh.vertices[j]) > options.edgeThreshold;
                               }),
                r.end());
    }

    const double sigma = options.sigma > 0.0f ? static_cast<double>(options.sigma) : 1.0;
    std::vector<float> next(n);
    for (int pass = 0; pass < options.iterations; ++pass) {
        for (std::size_t i = 0; i < n; ++i) {
            next[i] = mesh.heights[i];
            const auto &r = ring[i];
            if (r.size() < 2)
                continue;
            const PixelPoint p = mesh.vertices[i];
            double meanDist = 0.0;
            for (const std::uint32_t j : r)
                meanDist += std::hypot(mesh.vertices[j].x - p.x, mesh.vertices[j].y - p.y);
            meanDist /= static_cast<double>(r.size());
            // Weighted least-squares plane h = a + b·u + c·v in coordinates scaled by the mean
            // distance.
            double m[3][3] = {{1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
            double rhs[3] = {static_cast<double>(mesh.heights[i]), 0.0, 0.0};
            for (const std::uint32_t j : r) {
                const double u = (mesh.vertices[j].x - p.x) / meanDist;
                const double v = (mesh.vertices[j].y - p.y) / meanDist;
                const double wgt = std::exp(-0.5 * (u * u + v * v) / (sigma * sigma));
                const double hj = static_cast<double>(mesh.heights[j]);
                const double basis[3] = {1.0, u, v};
                for (int a = 0; a < 3; ++a) {
                    for (int b = 0; b < 3; ++b)
                        m[a][b] += wgt * basis[a] * basis[b];
                    rhs[a] += wgt * basis[a] * hj;
                }
            }
            // Cramer's rule for the constant term a (the plane's value at the vertex).
            const auto det3 = [](const double x[3][3]) {
                return x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) -
                       x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
                       x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]);
            };
            const double det = det3(m);
            const double scale = m[0][0] * m[0][0] * m[0][0];
            if (!(std::fabs(det) > 1e-6 * scale))
                continue; // Neighbours (nearly) collinear: no plane, keep the height.
            double mA[3][3];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    mA[a][b] = b == 0 ? rhs[a] : m[a][b];
            next[i] = static_cast<float>(det3(mA) / det);
        }
        mesh.heights.swap(next);
    }
}

Plane<float> renderMesh(const Mesh &mesh, int width, int height, std::size_t *uncovered)
{
    Plane<float> out(std::max(width, 0), std::max(height, 0), 0.0f);
    Plane<std::uint8_t> covered(out.width, out.height, 0);
    for (const auto &t : mesh.triangles) {
        const PixelPoint a = mesh.vertices[t[0]];
        const PixelPoint b = mesh.vertices[t[1]];
        const PixelPoint c = mesh.vertices[t[2]];
        const std::int64_t area = cross(a, b, c);
        if (area == 0)
            continue;
        const double ha = static_cast<double>(mesh.heights[t[0]]);
        const double hb = static_cast<double>(mesh.heights[t[1]]);
        const double hc = static_cast<double>(mesh.heights[t[2]]);
        const int xMin = std::max(0, std::min({a.x, b.x, c.x}));
        const int xMax = std::min(out.width - 1, std::max({a.x, b.x, c.x}));
        const int yMin = std::max(0, std::min({a.y, b.y, c.y}));
        const int yMax = std::min(out.height - 1, std::max({a.y, b.y, c.y}));
        for (int y = yMin; y <= yMax; ++y) {
            for (int x = xMin; x <= xMax; ++x) {
                const PixelPoint p{x, y};
                // Edge functions: exact integers, so shared edges are covered without gaps.
                const std::int64_t wa = cross(b, c, p);
                const std::int64_t wb = cross(c, a, p);
                const std::int64_t wc = cross(a, b, p);
                const bool inside =
                    area > 0 ? (wa >= 0 && wb >= 0 && wc >= 0) : (wa <= 0 && wb <= 0 && wc <= 0);
                if (!inside)
                    continue;
                const double v = (static_cast<double>(wa) * ha + static_cast<double>(wb) * hb +
                                  static_cast<double>(wc) * hc) /
                                 static_cast<double>(area);
                out.at(x, y) = static_cast<float>(v);
                covered.at(x, y) = 1;
            }
        }
    }
    if (uncovered != nullptr) {
        *uncovered = 0;
        for (const std::uint8_t c : covered.samples)
            *uncovered += c == 0 ? 1u : 0u;
    }
    return out;
}

EnhanceOptions EnhanceOptions::forScale(double vmax)
{
    EnhanceOptions o;
    const auto k = static_cast<float>(vmax / 255.0);
    o.sampling.tolerance *= k;
    o.smoothing.edgeThreshold *= k;
    o.measure.flatGradient *= k;
    o.measure.edgeGradient *= k;
    return o;
}

SurfaceMeasures measureSurface(const Plane<float> &reference, const Plane<float> &depth,
                               const MeasureOptions &options, std::size_t *flatPixels,
                               std::size_t *edgePixels)
{
    if (reference.empty() || !reference.sameSize(depth))
        return {};
    const Masks m = makeMasks(reference, options);
    if (flatPixels != nullptr)
        *flatPixels = m.flatCount;
    if (edgePixels != nullptr)
        *edgePixels = m.edgeCount;
    return measureWithMasks(depth, m, options);
}

Result<EnhanceResult> enhance(const Plane<float> &nearness, const EnhanceOptions &options)
{
    if (nearness.width < 2 || nearness.height < 2)
        return unexpected(Errc::InvalidArgument, "Depth map too small to enhance (needs 2x2)");
    const SamplingOptions &s = options.sampling;
    if (!(s.tolerance > 0.0f) || s.minBlock < 1 || s.maxBlock < s.minBlock ||
        options.medianRadius < 0)
        return unexpected(Errc::InvalidArgument, "Invalid depth enhancement options");

    const Plane<float> median = medianFilter(nearness, options.medianRadius);
    const std::vector<PixelPoint> points = samplePoints(median, s);
    auto mesh = triangulate(points, median);
    if (!mesh)
        return unexpected(mesh.error());
    smoothHeights(*mesh, median, options.smoothing);

    EnhanceResult result;
    result.depth = renderMesh(*mesh, nearness.width, nearness.height);

    EnhanceReport &r = result.report;
    r.pixels = nearness.size();
    r.points = mesh->vertices.size();
    r.triangles = mesh->triangles.size();
    std::vector<float> absErr(nearness.size());
    double sum = 0.0;
    double sumSq = 0.0;
    for (std::size_t i = 0; i < absErr.size(); ++i) {
        const float e = std::fabs(result.depth.samples[i] - median.samples[i]);
        absErr[i] = e;
        sum += static_cast<double>(e);
        sumSq += static_cast<double>(e) * static_cast<double>(e);
        r.maxAbsError = std::max(r.maxAbsError, static_cast<double>(e));
    }
    const auto count = static_cast<double>(absErr.size());
    r.meanAbsError = sum / count;
    r.rmsError = std::sqrt(sumSq / count);
    const auto k99 = static_cast<std::size_t>(0.99 * (count - 1.0));
    std::nth_element(absErr.begin(), absErr.begin() + static_cast<std::ptrdiff_t>(k99),
                     absErr.end());
    r.p99AbsError = static_cast<double>(absErr[k99]);

    const Masks masks = makeMasks(median, options.measure);
    r.flatPixels = masks.flatCount;
    r.edgePixels = masks.edgeCount;
    r.input = measureWithMasks(nearness, masks, options.measure);
    r.median = measureWithMasks(median, masks, options.measure);
    r.enhanced = measureWithMasks(result.depth, masks, options.measure);
    return result;
}

} // namespace depthtouch::depth
