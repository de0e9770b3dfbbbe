#include "depthtouch/render/adaptive_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include "mesh_cells.h"

// The adaptive mesh's grid: options, the tile-by-tile fixed and adaptive steps, the emission of
// tiles and quadtree blocks as crack-free triangles, and the measured error of a mesh.

namespace depthtouch::render {

namespace {

bool isPowerOfTwo(int v) noexcept
{
    return v > 0 && (v & (v - 1)) == 0;
}

} // namespace

using mesh::cellValue;
using mesh::log2i;

void AdaptiveMesh::emitBlock(int c0, int r0, int s)
{
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    const auto cellsXu = static_cast<std::size_t>(cellsX);
    const int c1 = std::min(c0 + s, cellsX);
    const int r1 = std::min(r0 + s, cellsY);
    const auto w = static_cast<std::uint32_t>(width_);
    const auto index = [w](int c, int r) {
        return static_cast<std::uint32_t>(r) * w + static_cast<std::uint32_t>(c);
    };
    // Size of the leaf block covering cell (x, y); 0 outside the grid.
    const auto sizeAt = [&](int x, int y) -> int {
        if (x < 0 || y < 0 || x >= cellsX || y >= cellsY)
            return 0;
        return 1 << cellBlock_[static_cast<std::size_t>(y) * cellsXu + static_cast<std::size_t>(x)];
    };
    // The boundary, clockwise from the top-left corner (the winding of the two-triangle split),
    // with the corners of every smaller neighbouring block that lie inside a side: blocks are
    // aligned to their size, so walking the cells just outside a side block by block finds them.
    polygon_.clear();
    const auto side = [&](int fixed, int from, int to, bool horizontal, int outside) {
        // Cells outside the side run from..to−1 along it; push the inner vertices in walking order.
        const std::size_t first = polygon_.size();
        for (int p = from; p < to;) {
            const int n = horizontal ? sizeAt(p, outside) : sizeAt(outside, p);
            if (n == 0 || n >= s)
                break; // grid border, or one block at least as large: no vertex inside the side
            const int next = p / n * n + n;
            if (next < to)
                polygon_.push_back(horizontal ? index(next, fixed) : index(fixed, next));
            p = next;
        }
        return polygon_.size() - first;
    };
    polygon_.push_back(index(c0, r0));
    const std::size_t nTop = side(r0, c0, c1, true, r0 - 1);
    polygon_.push_back(index(c1, r0));
    const std::size_t nRight = side(c1, r0, r1, false, c1);
    polygon_.push_back(index(c1, r1));
    const std::size_t bottomStart = polygon_.size();
    const std::size_t nBottom = side(r1, c0, c1, true, r1);
    std::reverse(polygon_.begin() + static_cast<std::ptrdiff_t>(bottomStart), polygon_.end());
    polygon_.push_back(index(c0, r1));
    const std::size_t leftStart = polygon_.size();
    side(c0, r0, r1, false, c0 - 1);
    std::reverse(polygon_.begin() + static_cast<std::ptrdiff_t>(leftStart), polygon_.end());

    const auto triangle = [this](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
        indices_.push_back(i);
        indices_.push_back(j);
        indices_.push_back(k);
    };
    const std::size_t n = polygon_.size();
    if (n == 4) {
        // No neighbour finer than this block: its two triangles, split like the haptic cells.
        triangle(polygon_[0], polygon_[1], polygon_[2]); // haptics TriangleId upper == 0
        triangle(polygon_[0], polygon_[2], polygon_[3]); // upper == 1
        return;
    }
    if (c1 - c0 >= 2 && r1 - r0 >= 2) {
        // A fan around the block's middle sample (the block is convex, so every triangle is
        // positive and they tile it exactly); the neighbours' vertices close every T-junction.
        const std::uint32_t m = index(c0 + (c1 - c0) / 2, r0 + (r1 - r0) / 2);
        for (std::size_t i = 0; i < n; ++i)
            triangle(m, polygon_[i], polygon_[(i + 1) % n]);
        return;
    }
    // A block one cell thin (cut by the grid's last column or row): only its long inner side can
    // hold vertices (the top, or the left), the opposite one being the grid border; fan from a
    // corner of the border side (bottom-left, or top-right).
    const std::size_t apex = nTop > 0 ? 3 + nTop + nRight + nBottom : 1;
    for (std::size_t k = 1; k + 1 < n; ++k)
        triangle(polygon_[apex], polygon_[(apex + k) % n], polygon_[(apex + k + 1) % n]);
}

double AdaptiveMesh::tileError(const scene::DepthFrameView &depth, int tx, int ty, int step,
                               double limit, double &mean) const noexcept
{
    double sum = 0.0;
    long count = 0;
    const int c0 = tx * tile_;
    const int r0 = ty * tile_;
    const int c1 = std::min(c0 + tile_, width_ - 1);
    const int r1 = std::min(r0 + tile_, height_ - 1);
    double worst = 0.0;
    for (int ra = r0; ra < r1; ra += step) {
        const int rb = std::min(ra + step, r1);
        const double invH = 1.0 / (rb - ra);
        for (int ca = c0; ca < c1; ca += step) {
            const int cb = std::min(ca + step, c1);
            const double invW = 1.0 / (cb - ca);
            // Holes: mesh::sampleError(); a cell with a hole corner is not drawn.
            const bool drawn = depth.measured(ca, ra) && depth.measured(cb, ra) &&
                               depth.measured(cb, rb) && depth.measured(ca, rb);
            const double mismatch = step == 1 ? 0.0 : static_cast<double>(mesh::kCoverageError);
            const double z00 = depth.sample(ca, ra);
            const double z10 = depth.sample(cb, ra);
            const double z11 = depth.sample(cb, rb);
            const double z01 = depth.sample(ca, rb);
            for (int r = ra; r <= rb; ++r) {
                const double v = (r - ra) * invH;
                for (int c = ca; c <= cb; ++c) {
                    const double u = (c - ca) * invW;
                    const double g = std::fabs(cellValue(z00, z10, z11, z01, u, v) -
                                               static_cast<double>(depth.sample(c, r)));
                    const bool hole = !depth.measured(c, r);
                    const double e = drawn ? (hole ? mismatch : g) : (hole ? 0.0 : mismatch);
                    sum += drawn && !hole ? g : 0.0;
                    ++count;
                    if (e > worst) {
                        worst = e;
                        if (worst > limit)
                            return worst;
                    }
                }
            }
        }
    }
    mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
    return worst;
}

Result<void> AdaptiveMesh::build(const scene::DepthFrameView &depth, const MeshOptions &options)
{
    if (auto v = depth.validate(); !v)
        return v;
    if (!isPowerOfTwo(options.tileSize) || options.tileSize < 2 || options.tileSize > 256)
        return unexpected(Errc::InvalidArgument, "mesh tile size must be a power of two in 2..256");
    const int fixedStep = options.mode == MeshMode::Fixed ? options.fixedStep : 1;
    if (!isPowerOfTwo(fixedStep) || fixedStep > options.tileSize)
        return unexpected(Errc::InvalidArgument,
                          "mesh step must be a power of two no larger than the tile size");
    if (options.mode != MeshMode::Fixed &&
        (!isPowerOfTwo(options.maxStep) || options.maxStep > options.tileSize))
        return unexpected(Errc::InvalidArgument,
                          "mesh maximum step must be a power of two no larger than the tile size");
    if (!(options.tolerance >= 0.0) || !(options.maxErrorCap >= 0.0))
        return unexpected(Errc::InvalidArgument,
                          "mesh error tolerance and cap must be >= 0 levels");
    if (static_cast<long long>(depth.width) * depth.height > (1LL << 31) || depth.width > 65536 ||
        depth.height > 65536)
        return unexpected(Errc::InvalidArgument,
                          "depth frame too large (over 65536 samples a side or 2^31 in all)");

    width_ = depth.width;
    height_ = depth.height;
    tile_ = options.tileSize;
    tilesX_ = (width_ - 1 + tile_ - 1) / tile_;
    tilesY_ = (height_ - 1 + tile_ - 1) / tile_;
    steps_.assign(static_cast<std::size_t>(tilesX_) * static_cast<std::size_t>(tilesY_), 1);
    stats_ = MeshStats{};
    stats_.tiles = tilesX_ * tilesY_;
    blocksMode_ = options.mode == MeshMode::Blocks;
    if (blocksMode_) {
        if (tile_ < 8)
            return unexpected(Errc::InvalidArgument, "blocks mesh needs a tile size of 8 or more");
        indices_.clear();
        if (depth.format == scene::SampleFormat::Gray8)
            chooseBlockSteps<std::uint8_t>(depth, options);
        else
            chooseBlockSteps<std::uint16_t>(depth, options);
        return ok();
    }
    if (options.mode == MeshMode::Quadtree) {
        const bool budget = options.criterion == ErrorCriterion::Mean;
        if (depth.format == scene::SampleFormat::Gray8) {
            if (budget)
                buildQuadtreeBudget<std::uint8_t>(depth, options);
            else
                buildQuadtree<std::uint8_t>(depth, options);
        } else {
            if (budget)
                buildQuadtreeBudget<std::uint16_t>(depth, options);
            else
                buildQuadtree<std::uint16_t>(depth, options);
        }
        stats_.triangles = indices_.size() / 3;
        return ok();
    }

    for (int ty = 0; ty < tilesY_; ++ty) {
        for (int tx = 0; tx < tilesX_; ++tx) {
            int step = fixedStep;
            if (options.mode == MeshMode::Adaptive) {
                // A tile whose samples span no more than the tolerance is within it at any step:
                // the surface interpolates between its samples.
                const int c0 = tx * tile_;
                const int r0 = ty * tile_;
                const int c1 = std::min(c0 + tile_, width_ - 1);
                const int r1 = std::min(r0 + tile_, height_ - 1);
                std::uint32_t lo = depth.sample(c0, r0);
                std::uint32_t hi = lo;
                for (int r = r0; r <= r1; ++r)
                    for (int c = c0; c <= c1; ++c) {
                        const std::uint32_t v = depth.sample(c, r);
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                step = 1;
                const double cap = options.criterion == ErrorCriterion::Max ? options.tolerance
                                                                            : options.maxErrorCap;
                if (static_cast<double>(hi - lo) <= std::min(cap, options.tolerance)) {
                    step = options.maxStep;
                } else {
                    for (int s = options.maxStep; s >= 2; s /= 2) {
                        double mean = 0.0;
                        if (tileError(depth, tx, ty, s, cap, mean) <= cap &&
                            (options.criterion == ErrorCriterion::Max ||
                             mean <= options.tolerance)) {
                            step = s;
                            break;
                        }
                    }
                }
            }
            steps_[static_cast<std::size_t>(ty * tilesX_ + tx)] = static_cast<std::uint16_t>(step);
            ++stats_.tilesAtStep[log2i(step)];
        }
    }

    indices_.clear();
    for (int ty = 0; ty < tilesY_; ++ty)
        for (int tx = 0; tx < tilesX_; ++tx)
            emitTile(tx, ty, indices_);
    stats_.triangles = indices_.size() / 3;
    return ok();
}

void AdaptiveMesh::drawnIndices(std::vector<std::uint32_t> &out) const
{
    if (!blocksMode_) {
        out = indices_;
        return;
    }
    out.clear();
    for (int ty = 0; ty < tilesY_; ++ty)
        for (int tx = 0; tx < tilesX_; ++tx)
            emitTile(tx, ty, out);
}

void AdaptiveMesh::emitTile(int tx, int ty, std::vector<std::uint32_t> &out) const
{
    const auto stepAt = [this](int x, int y) -> int {
        if (x < 0 || y < 0 || x >= tilesX_ || y >= tilesY_)
            return 0;
        return steps_[static_cast<std::size_t>(y * tilesX_ + x)];
    };
    const int s = stepAt(tx, ty);
    const int top = std::max(s, stepAt(tx, ty - 1));
    const int bottom = std::max(s, stepAt(tx, ty + 1));
    const int left = std::max(s, stepAt(tx - 1, ty));
    const int right = std::max(s, stepAt(tx + 1, ty));
    const int c0 = tx * tile_;
    const int r0 = ty * tile_;
    const int c1 = std::min(c0 + tile_, width_ - 1);
    const int r1 = std::min(r0 + tile_, height_ - 1);
    const auto w = static_cast<std::uint32_t>(width_);

    // Border vertices snap back along the border to the coarser neighbour's vertices; the tile's
    // corners (and its last column/row) are vertices at every step, so they never move.
    const auto vertex = [&](int c, int r) -> std::uint32_t {
        if (r == r0 && top > s && c != c1)
            c = c0 + (c - c0) / top * top;
        else if (r == r1 && bottom > s && c != c1)
            c = c0 + (c - c0) / bottom * bottom;
        if (c == c0 && left > s && r != r1)
            r = r0 + (r - r0) / left * left;
        else if (c == c1 && right > s && r != r1)
            r = r0 + (r - r0) / right * right;
        return static_cast<std::uint32_t>(r) * w + static_cast<std::uint32_t>(c);
    };
    const auto triangle = [&out](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (a == b || b == c || a == c)
            return;
        out.push_back(a);
        out.push_back(b);
        out.push_back(c);
    };

    const auto cell = [&triangle](std::uint32_t a, std::uint32_t b, std::uint32_t c,
                                  std::uint32_t d) {
        triangle(a, b, c); // (c, r), (c+1, r), (c+1, r+1): haptics TriangleId upper == 0
        triangle(a, c, d); // (c, r), (c+1, r+1), (c, r+1): upper == 1
    };
    mesh::forEachCell(c0, r0, c1, r1, s, vertex, cell);
}

MeshError measureMeshError(const scene::DepthFrameView &depth,
                           const std::vector<std::uint32_t> &indices)
{
    MeshError out;
    const int w = depth.width;
    const int h = depth.height;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    std::vector<float> error(n, -1.0f);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        long long cx[3];
        long long cy[3];
        double val[3];
        bool inside = true;
        bool holeCorner = false; // the triangle is not drawn (docs/architecture.md §3 "Holes")
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t i = indices[t + static_cast<std::size_t>(k)];
            if (i >= n) {
                inside = false;
                break;
            }
            cx[k] = i % static_cast<std::uint32_t>(w);
            cy[k] = i / static_cast<std::uint32_t>(w);
            val[k] = depth.sample(static_cast<int>(cx[k]), static_cast<int>(cy[k]));
            holeCorner = holeCorner || val[k] < static_cast<double>(depth.holeBelow);
        }
        if (!inside)
            continue;
        const long long area =
            (cx[1] - cx[0]) * (cy[2] - cy[0]) - (cy[1] - cy[0]) * (cx[2] - cx[0]);
        if (area == 0)
            continue;
        const long long xmin = std::min({cx[0], cx[1], cx[2]});
        const long long xmax = std::max({cx[0], cx[1], cx[2]});
        const long long ymin = std::min({cy[0], cy[1], cy[2]});
        const long long ymax = std::max({cy[0], cy[1], cy[2]});
        for (long long y = ymin; y <= ymax; ++y) {
            for (long long x = xmin; x <= xmax; ++x) {
                // Edge functions (exact in integers): the sample is covered when all have the sign
                // of the area or are zero (on an edge).
                long long e[3];
                for (int k = 0; k < 3; ++k) {
                    const int k1 = (k + 1) % 3;
                    const int k2 = (k + 2) % 3;
                    e[k] = (cx[k2] - cx[k1]) * (y - cy[k1]) - (cy[k2] - cy[k1]) * (x - cx[k1]);
                    if (area < 0)
                        e[k] = -e[k];
                }
                if (e[0] < 0 || e[1] < 0 || e[2] < 0)
                    continue;
                const double a = static_cast<double>(std::llabs(area));
                const double v =
                    (static_cast<double>(e[0]) * val[0] + static_cast<double>(e[1]) * val[1] +
                     static_cast<double>(e[2]) * val[2]) /
                    a;
                const std::size_t idx = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(x);
                const auto sample =
                    static_cast<double>(depth.sample(static_cast<int>(x), static_cast<int>(y)));
                const bool hole = holeCorner || sample < static_cast<double>(depth.holeBelow);
                error[idx] = hole ? 0.0f : static_cast<float>(std::fabs(v - sample));
            }
        }
    }
    double sum = 0.0;
    for (const float e : error) {
        if (e < 0.0f) {
            ++out.uncovered;
            continue;
        }
        sum += static_cast<double>(e);
        out.max = std::max(out.max, static_cast<double>(e));
    }
    out.samples = n;
    const std::size_t covered = n - out.uncovered;
    out.mean = covered > 0 ? sum / static_cast<double>(covered) : 0.0;
    return out;
}

} // namespace depthtouch::render
