#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "depthtouch/render/adaptive_mesh.h"
#include "mesh_cells.h"

// MeshMode::Blocks: a step per tile chosen from the error of each step at a coarse set of probes,
// against the frame's mean error budget and the leaf budget. No triangle list: the renderer draws
// the tiles' precomputed index ranges (block_ranges.h).

namespace depthtouch::render {

using mesh::log2i;

namespace {

// Probes: samples (c0 + 3 + 8i, r0 + 5 + 8j) of each tile. Both offsets are odd, so no probe is a
// vertex at any step ≥ 2 (its error at step 1 is 0); 1/64 of the samples.
constexpr int kProbePitch = 8;
constexpr int kProbeX = 3;
constexpr int kProbeY = 5;
// Refinements of tiles whose largest probe error is over the cap come first, the coarsest first.
constexpr float kOverCap = 1e30f;

template <class T> inline float sampleAt(const scene::DepthFrameView &d, int c, int r) noexcept
{
    T v;
    std::memcpy(&v,
                d.data + static_cast<std::size_t>(r) * d.strideBytes +
                    static_cast<std::size_t>(c) * sizeof(T),
                sizeof v);
    return static_cast<float>(v);
}

/// Cells of a w×h-cell tile at step s.
inline int cellsAt(int w, int h, int level) noexcept
{
    const int s = 1 << level;
    return ((w + s - 1) / s) * ((h + s - 1) / s);
}

/// The probe positions along one side of a tile spanning cells [a0, a1): offset \a first, 8
/// apart; the middle when the tile is too thin for one. \return how many (at most \a cap).
int probesAlong(int a0, int a1, int first, int *out, int cap) noexcept
{
    int n = 0;
    for (int a = a0 + first; a < a1 && n < cap; a += kProbePitch)
        out[n++] = a;
    if (n == 0)
        out[n++] = a0 + (a1 - a0) / 2;
    return n;
}

/// The jump from each sample of row \a a to its right neighbour and to the sample below it in row
/// \a b, the larger of the two, for samples [0, n) into \a out (exact in T: |x - y| of two T
/// values fits a T). Holes (samples below \a hole, docs/architecture.md §3): between two holes the
/// jump is 0, between a hole and a measured sample it is the largest T (a coverage edge, which
/// tileJumps() turns into an error over any cap: no jump between measured samples reaches it when
/// \a hole > 0). Branch-free on unsigned samples, so it vectorises.
template <class T>
inline void rowJumps(const T *__restrict a, const T *__restrict b, int n, T hole,
                     T *__restrict out) noexcept
{
    constexpr T kEdge = std::numeric_limits<T>::max();
    for (int c = 0; c < n; ++c) {
        const T h = static_cast<T>(std::max(a[c + 1], a[c]) - std::min(a[c + 1], a[c]));
        const T v = static_cast<T>(std::max(b[c], a[c]) - std::min(b[c], a[c]));
        const bool ha = a[c] < hole;
        const T hj = ha != (a[c + 1] < hole) ? kEdge : (ha ? T{0} : h);
        const T vj = ha != (b[c] < hole) ? kEdge : (ha ? T{0} : v);
        out[c] = std::max(hj, vj);
    }
}

/// The largest of \a n values.
template <class T> inline T largest(const T *__restrict v, int n) noexcept
{
    T m = 0;
    for (int c = 0; c < n; ++c)
        m = std::max(m, v[c]);
    return m;
}

/// The largest jump between neighbouring samples in each tile (a depth edge): on every other row,
/// to the next sample and to the sample two rows down (so a jump between any two rows is seen),
/// into \a out (tiles row-major). Reads half the rows, a row at a time into \a scratch (at least
/// d.width - 1 T values); the row loops vectorise (this file is built with the vectoriser on).
template <class T>
void tileJumps(const scene::DepthFrameView &d, int tile, int tilesX, T *scratch,
               float *out) noexcept
{
    const int cellsX = d.width - 1;
    const int cellsY = d.height - 1;
    for (int r = 0; r < cellsY; r += 2) {
        const T *a =
            reinterpret_cast<const T *>(d.data + static_cast<std::size_t>(r) * d.strideBytes);
        const int rd = std::min(r + 2, cellsY);
        const T *b =
            reinterpret_cast<const T *>(d.data + static_cast<std::size_t>(rd) * d.strideBytes);
        rowJumps(a, b, cellsX, static_cast<T>(d.holeBelow), scratch);
        float *row = out + static_cast<std::size_t>(r / tile) * static_cast<std::size_t>(tilesX);
        for (int tx = 0; tx < tilesX; ++tx) {
            const int c0 = tx * tile;
            const int c1 = std::min(c0 + tile, cellsX);
            const T j = largest(scratch + c0, c1 - c0);
            // A tile across a hole's border (mesh::kCoverageError): refined to step 1.
            const bool coverage = d.holeBelow > 0 && j == std::numeric_limits<T>::max();
            row[tx] =
                std::max(row[tx], coverage ? 2.0f * mesh::kCoverageError : static_cast<float>(j));
        }
    }
}

/// Steps 2^0 .. 2^8: the tile is at most 256 cells (MeshOptions::tileSize).
constexpr int kMaxLevels = 9;

/// A probe along one axis of a tile: its coordinate and, at each step 2^l, the first and last
/// vertex of the cell it lies in (clipped to the tile) and its fraction between them.
struct ProbeAxis {
    int at;
    int lo[kMaxLevels];
    int hi[kMaxLevels];
    float t[kMaxLevels];
};

/// The probes along one side of a tile spanning cells [a0, a1) (probesAlong()) with their cells
/// at steps 2^1 .. 2^(levels-1), coordinates relative to \a a0. \return how many.
int probeAxes(int a0, int a1, int first, int levels, ProbeAxis *out) noexcept
{
    constexpr int kMaxProbes = 256 / kProbePitch;
    int at[kMaxProbes];
    const int n = probesAlong(a0, a1, first, at, kMaxProbes);
    for (int i = 0; i < n; ++i) {
        ProbeAxis &p = out[i];
        p.at = at[i] - a0;
        for (int l = 1; l < levels; ++l) {
            p.lo[l] = (at[i] - a0) >> l << l;
            p.hi[l] = std::min(p.lo[l] + (1 << l), a1 - a0);
            p.t[l] = static_cast<float>(p.at - p.lo[l]) / static_cast<float>(p.hi[l] - p.lo[l]);
        }
    }
    return n;
}

/// The interpolation error of each step at the probes \a xs (columns relative to \a c0) of the
/// probe row \a y (rows relative to \a r0) of one tile, summed into e[2l] and maxed into e[2l + 1]
/// for steps 2^l, l = 1 .. levels - 1 (nearness levels). The cell's two triangles split
/// top-left → bottom-right (§3), as drawn.
template <class T>
inline void probeRowError(const scene::DepthFrameView &depth, int c0, int r0, const ProbeAxis *xs,
                          int nx, const ProbeAxis &y, int levels, float *e) noexcept
{
    for (int i = 0; i < nx; ++i) {
        const ProbeAxis &x = xs[i];
        // Holes: mesh::sampleError(); a cell with a hole corner is not drawn.
        const float z = sampleAt<T>(depth, c0 + x.at, r0 + y.at);
        const auto hole = static_cast<float>(depth.holeBelow);
        for (int l = 1; l < levels; ++l) {
            const int ca = c0 + x.lo[l];
            const int cb = c0 + x.hi[l];
            const int ra = r0 + y.lo[l];
            const int rb = r0 + y.hi[l];
            const float u = x.t[l];
            const float v = y.t[l];
            const float z00 = sampleAt<T>(depth, ca, ra);
            const float z11 = sampleAt<T>(depth, cb, rb);
            const float s = u >= v ? z00 + u * (sampleAt<T>(depth, cb, ra) - z00) +
                                         v * (z11 - sampleAt<T>(depth, cb, ra))
                                   : z00 + v * (sampleAt<T>(depth, ca, rb) - z00) +
                                         u * (z11 - sampleAt<T>(depth, ca, rb));
            const bool drawn = std::min({z00, z11, sampleAt<T>(depth, cb, ra),
                                         sampleAt<T>(depth, ca, rb)}) >= hole;
            const float g = std::fabs(s - z);
            e[2 * l] += drawn && z >= hole ? g : 0.0f;
            e[2 * l + 1] =
                std::max(e[2 * l + 1], mesh::sampleError(g, z < hole, drawn, mesh::kCoverageError));
        }
    }
}

} // namespace

template <class T>
void AdaptiveMesh::measureBlockProbes(const scene::DepthFrameView &depth, int levels) noexcept
{
    const auto lv = static_cast<std::size_t>(levels);
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    constexpr int kMaxProbes = 256 / kProbePitch;
    // The columns' probes: the same in every whole tile; the last tile may be narrower.
    ProbeAxis full[kMaxProbes];
    ProbeAxis last[kMaxProbes];
    const int nxFull = probeAxes(0, std::min(tile_, cellsX), kProbeX, levels, full);
    const int lastC0 = (tilesX_ - 1) * tile_;
    const int nxLast = probeAxes(lastC0, cellsX, kProbeX, levels, last);
    ProbeAxis ys[kMaxProbes];
    // A row of tiles a probe row at a time, so the rows read stream through the caches; each
    // tile's sums still run over its probes in the same order (rows, then columns).
    for (int ty = 0; ty < tilesY_; ++ty) {
        const int r0 = ty * tile_;
        const int ny = probeAxes(r0, std::min(r0 + tile_, cellsY), kProbeY, levels, ys);
        float *row = &probeError_[static_cast<std::size_t>(ty * tilesX_) * lv * 2];
        for (int j = 0; j < ny; ++j) {
            for (int tx = 0; tx + 1 < tilesX_; ++tx)
                probeRowError<T>(depth, tx * tile_, r0, full, nxFull, ys[j], levels,
                                 row + static_cast<std::size_t>(tx) * lv * 2);
            probeRowError<T>(depth, lastC0, r0, last, nxLast, ys[j], levels,
                             row + static_cast<std::size_t>(tilesX_ - 1) * lv * 2);
        }
        for (int tx = 0; tx < tilesX_; ++tx) {
            float *e = row + static_cast<std::size_t>(tx) * lv * 2;
            const float inv = 1.0f / static_cast<float>((tx + 1 < tilesX_ ? nxFull : nxLast) * ny);
            for (int l = 1; l < levels; ++l)
                e[2 * l] *= inv;
        }
    }
}

template <class T>
void AdaptiveMesh::chooseBlockSteps(const scene::DepthFrameView &depth, const MeshOptions &options)
{
    const int top = log2i(options.maxStep);
    const int levels = top + 1;
    const auto lv = static_cast<std::size_t>(levels);
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    const std::size_t nt = steps_.size();
    probeError_.assign(nt * lv * 2, 0.0f); // [tile][level]{mean, max}; level 0 is exact
    tileLevel_.assign(nt, static_cast<std::uint8_t>(top));
    jump_.assign(nt, 0.0f);
    jumpRow_.resize((static_cast<std::size_t>(cellsX) * sizeof(T) + 1) / 2);
    tileJumps<T>(depth, tile_, tilesX_, reinterpret_cast<T *>(jumpRow_.data()), jump_.data());
    measureBlockProbes<T>(depth, levels);
    double errSum = 0.0;
    double samples = 0.0;
    std::size_t leaves = 0;
    for (int ty = 0; ty < tilesY_; ++ty) {
        for (int tx = 0; tx < tilesX_; ++tx) {
            const int w = std::min(tile_, cellsX - tx * tile_);
            const int h = std::min(tile_, cellsY - ty * tile_);
            const std::size_t t = static_cast<std::size_t>(ty * tilesX_ + tx);
            const double n = static_cast<double>(w * h);
            samples += n;
            errSum +=
                static_cast<double>(probeError_[t * lv * 2 + 2 * static_cast<std::size_t>(top)]) *
                n;
            leaves += static_cast<std::size_t>(cellsAt(w, h, top));
        }
    }
    refineBlockSteps(options, top, samples, errSum, leaves);
}

void AdaptiveMesh::refineBlockSteps(const MeshOptions &options, int top, double samples,
                                    double errSum, std::size_t leaves)
{
    const auto lv = static_cast<std::size_t>(top + 1);
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    const std::size_t nt = steps_.size();
    // Greedy refinement: the tile whose refinement removes the most error per added cell first
    // (to the finer step that removes most per cell, looking past steps that remove none, as
    // noise does); tiles over the cap first, one step at a time, the coarsest first.
    const auto cap = static_cast<float>(options.maxErrorCap);
    /// The tile's width and height in cells.
    const auto tileSize = [&](std::size_t t) {
        const int tx = static_cast<int>(t) % tilesX_;
        const int ty = static_cast<int>(t) / tilesX_;
        return std::pair{std::min(tile_, cellsX - tx * tile_),
                         std::min(tile_, cellsY - ty * tile_)};
    };
    const auto tileCells = [&](std::size_t t, int l) {
        const auto [w, h] = tileSize(t);
        return cellsAt(w, h, l);
    };
    const auto target = [&](std::size_t t, int l, float &priority) {
        const float *e = &probeError_[t * lv * 2];
        // A jump J between neighbouring samples leaves an error of about J/2 at any step ≥ 2.
        if (std::max(e[2 * l + 1], 0.5f * jump_[t]) > cap) {
            priority = kOverCap * static_cast<float>(1 + l);
            return l - 1;
        }
        const auto [w, h] = tileSize(t);
        const auto n = static_cast<float>(w * h);
        const int cells = cellsAt(w, h, l);
        int best = l - 1;
        priority = 0.0f;
        for (int k = l - 1; k >= 0; --k) {
            const auto added = static_cast<float>(cellsAt(w, h, k) - cells);
            const float gain = (e[2 * l] - e[2 * k]) * n / added;
            if (gain > priority) {
                priority = gain;
                best = k;
            }
        }
        return best;
    };
    const auto less = [](const HeapEntry &a, const HeapEntry &b) {
        return a.priority < b.priority;
    };
    heap_.clear();
    for (std::size_t t = 0; t < nt && top > 0; ++t) {
        float p = 0.0f;
        (void)target(t, top, p);
        heap_.push_back({p, static_cast<std::uint32_t>(t)});
    }
    std::make_heap(heap_.begin(), heap_.end(), less);
    const double budgetError = options.tolerance * samples;
    while (!heap_.empty()) {
        const float best = heap_.front().priority;
        if ((best < kOverCap && errSum <= budgetError) || !(best > 0.0f))
            break;
        const std::size_t t = heap_.front().node;
        const int l = tileLevel_[t];
        float p = 0.0f;
        const int k = target(t, l, p);
        const auto added = static_cast<std::size_t>(tileCells(t, k) - tileCells(t, l));
        if (options.maxBlocks > 0 && leaves + added > options.maxBlocks) {
            stats_.budgetLimited = true;
            break;
        }
        std::pop_heap(heap_.begin(), heap_.end(), less);
        heap_.pop_back();
        const int tx = static_cast<int>(t) % tilesX_;
        const int ty = static_cast<int>(t) / tilesX_;
        const double n = static_cast<double>(std::min(tile_, cellsX - tx * tile_) *
                                             std::min(tile_, cellsY - ty * tile_));
        const float *e = &probeError_[t * lv * 2];
        errSum += static_cast<double>(e[2 * k] - e[2 * l]) * n;
        leaves += added;
        tileLevel_[t] = static_cast<std::uint8_t>(k);
        if (k > 0) {
            (void)target(t, k, p);
            heap_.push_back({p, static_cast<std::uint32_t>(t)});
            std::push_heap(heap_.begin(), heap_.end(), less);
        }
    }

    for (std::size_t t = 0; t < nt; ++t) {
        const int l = tileLevel_[t];
        steps_[t] = static_cast<std::uint16_t>(1 << l);
        ++stats_.tilesAtStep[l];
        stats_.blocksAtSize[l] += tileCells(t, l);
    }
    stats_.blocks = static_cast<int>(leaves);
    stats_.triangles = 2 * leaves;
    stats_.estimatedError = samples > 0.0 ? std::max(0.0, errSum) / samples : 0.0;
}

template void AdaptiveMesh::measureBlockProbes<std::uint8_t>(const scene::DepthFrameView &,
                                                             int) noexcept;
template void AdaptiveMesh::measureBlockProbes<std::uint16_t>(const scene::DepthFrameView &,
                                                              int) noexcept;
template void AdaptiveMesh::chooseBlockSteps<std::uint8_t>(const scene::DepthFrameView &,
                                                           const MeshOptions &);
template void AdaptiveMesh::chooseBlockSteps<std::uint16_t>(const scene::DepthFrameView &,
                                                            const MeshOptions &);

} // namespace depthtouch::render
