#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

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

/// The largest jump between neighbouring samples in each tile (a depth edge): on every other row,
/// to the next sample and to the sample two rows down (so a jump between any two rows is seen),
/// into \a out (tiles row-major). Reads half the rows; the inner loops vectorise.
template <class T>
void tileJumps(const scene::DepthFrameView &d, int tile, int tilesX, float *out) noexcept
{
    const int cellsX = d.width - 1;
    const int cellsY = d.height - 1;
    for (int r = 0; r < cellsY; r += 2) {
        const T *a =
            reinterpret_cast<const T *>(d.data + static_cast<std::size_t>(r) * d.strideBytes);
        const int rd = std::min(r + 2, cellsY);
        const T *b =
            reinterpret_cast<const T *>(d.data + static_cast<std::size_t>(rd) * d.strideBytes);
        float *row = out + static_cast<std::size_t>(r / tile) * static_cast<std::size_t>(tilesX);
        for (int tx = 0; tx < tilesX; ++tx) {
            const int c0 = tx * tile;
            const int c1 = std::min(c0 + tile, cellsX);
            int m = 0;
            for (int c = c0; c < c1; ++c) {
                const int h = std::abs(static_cast<int>(a[c + 1]) - static_cast<int>(a[c]));
                const int v = std::abs(static_cast<int>(b[c]) - static_cast<int>(a[c]));
                m = std::max(m, std::max(h, v));
            }
            row[tx] = std::max(row[tx], static_cast<float>(m));
        }
    }
}

} // namespace

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
    tileJumps<T>(depth, tile_, tilesX_, jump_.data());
    constexpr int kMaxProbes = 256 / kProbePitch;
    int px[kMaxProbes];
    int py[kMaxProbes];
    double errSum = 0.0;
    double samples = 0.0;
    std::size_t leaves = 0;
    for (int ty = 0; ty < tilesY_; ++ty) {
        for (int tx = 0; tx < tilesX_; ++tx) {
            const int c0 = tx * tile_;
            const int r0 = ty * tile_;
            const int c1 = std::min(c0 + tile_, cellsX);
            const int r1 = std::min(r0 + tile_, cellsY);
            const int nx = probesAlong(c0, c1, kProbeX, px, kMaxProbes);
            const int ny = probesAlong(r0, r1, kProbeY, py, kMaxProbes);
            const std::size_t t = static_cast<std::size_t>(ty * tilesX_ + tx);
            float *e = &probeError_[t * lv * 2];
            for (int j = 0; j < ny; ++j) {
                const int r = py[j];
                for (int i = 0; i < nx; ++i) {
                    const int c = px[i];
                    const float z = sampleAt<T>(depth, c, r);
                    for (int l = 1; l < levels; ++l) {
                        const int ca = c0 + ((c - c0) >> l << l);
                        const int ra = r0 + ((r - r0) >> l << l);
                        const int cb = std::min(ca + (1 << l), c1);
                        const int rb = std::min(ra + (1 << l), r1);
                        const float u = static_cast<float>(c - ca) / static_cast<float>(cb - ca);
                        const float v = static_cast<float>(r - ra) / static_cast<float>(rb - ra);
                        const float z00 = sampleAt<T>(depth, ca, ra);
                        const float z11 = sampleAt<T>(depth, cb, rb);
                        // The cell's two triangles, split top-left → bottom-right (§3).
                        const float s = u >= v ? z00 + u * (sampleAt<T>(depth, cb, ra) - z00) +
                                                     v * (z11 - sampleAt<T>(depth, cb, ra))
                                               : z00 + v * (sampleAt<T>(depth, ca, rb) - z00) +
                                                     u * (z11 - sampleAt<T>(depth, ca, rb));
                        const float err = std::fabs(s - z);
                        e[2 * l] += err;
                        e[2 * l + 1] = std::max(e[2 * l + 1], err);
                    }
                }
            }
            const float inv = 1.0f / static_cast<float>(nx * ny);
            for (int l = 1; l < levels; ++l)
                e[2 * l] *= inv;
            const double n = static_cast<double>((c1 - c0) * (r1 - r0));
            samples += n;
            errSum += static_cast<double>(e[2 * top]) * n;
            leaves += static_cast<std::size_t>(cellsAt(c1 - c0, r1 - r0, top));
        }
    }

    // Greedy refinement: the tile whose refinement removes the most error per added cell first
    // (to the finer step that removes most per cell, looking past steps that remove none, as
    // noise does); tiles over the cap first, one step at a time, the coarsest first.
    const auto cap = static_cast<float>(options.maxErrorCap);
    const auto tileCells = [&](std::size_t t, int l) {
        const int tx = static_cast<int>(t) % tilesX_;
        const int ty = static_cast<int>(t) / tilesX_;
        return cellsAt(std::min(tile_, cellsX - tx * tile_), std::min(tile_, cellsY - ty * tile_),
                       l);
    };
    const auto target = [&](std::size_t t, int l, float &priority) {
        const float *e = &probeError_[t * lv * 2];
        // A jump J between neighbouring samples leaves an error of about J/2 at any step ≥ 2.
        if (std::max(e[2 * l + 1], 0.5f * jump_[t]) > cap) {
            priority = kOverCap * static_cast<float>(1 + l);
            return l - 1;
        }
        const int tx = static_cast<int>(t) % tilesX_;
        const int ty = static_cast<int>(t) / tilesX_;
        const auto n = static_cast<float>(std::min(tile_, cellsX - tx * tile_) *
                                          std::min(tile_, cellsY - ty * tile_));
        int best = l - 1;
        priority = 0.0f;
        for (int k = l - 1; k >= 0; --k) {
            const auto added = static_cast<float>(tileCells(t, k) - tileCells(t, l));
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

template void AdaptiveMesh::chooseBlockSteps<std::uint8_t>(const scene::DepthFrameView &,
                                                           const MeshOptions &);
template void AdaptiveMesh::chooseBlockSteps<std::uint16_t>(const scene::DepthFrameView &,
                                                            const MeshOptions &);

} // namespace depthtouch::render
