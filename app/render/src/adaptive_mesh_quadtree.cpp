#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "depthtouch/render/adaptive_mesh.h"
#include "mesh_cells.h"

// The adaptive mesh's quadtree: the two-triangle error of a block, the tile-by-tile split against
// a tolerance, and the greedy refinement against one error budget for the whole frame.

namespace depthtouch::render {

using mesh::cellValue;
using mesh::log2i;

namespace {

template <class T> inline float loadSample(const std::uint8_t *row, int c) noexcept
{
    T v;
    std::memcpy(&v, row + static_cast<std::size_t>(c) * sizeof(T), sizeof v);
    return static_cast<float>(v);
}

/// The two-triangle error of block (c0..c1, r0..r1) (corners only, top-left → bottom-right
/// diagonal) over its samples, borders included: sum and largest |surface − sample|.
struct BlockError {
    float sum = 0.0f;
    float max = 0.0f;
    int count = 0;        ///< Samples of the block, (w + 1)·(h + 1).
    bool stopped = false; ///< The scan stopped early (a limit was passed): sum and max partial.
};

/// Scans block (c0..c1, r0..r1) row by row. Each row is two linear runs (left of the diagonal: the
/// lower triangle; right of it: the upper), so the loops vectorise. Stops after a row whose largest
/// error exceeds \a rowLimit or once the running sum exceeds \a sumLimit.
template <class T>
BlockError scanBlock(const scene::DepthFrameView &depth, int c0, int r0, int c1, int r1,
                     float rowLimit, double sumLimit) noexcept
{
    const auto row = [&](int r) {
        return depth.data + static_cast<std::size_t>(r) * depth.strideBytes;
    };
    const float z00 = loadSample<T>(row(r0), c0);
    const float z10 = loadSample<T>(row(r0), c1);
    const float z11 = loadSample<T>(row(r1), c1);
    const float z01 = loadSample<T>(row(r1), c0);
    const int w = c1 - c0;
    const int h = r1 - r0;
    const float invW = 1.0f / static_cast<float>(w);
    BlockError out;
    out.count = (w + 1) * (h + 1);
    // Holes (mesh::sampleError()): a block with a hole corner is not drawn; its geometric error
    // counts only under a drawn block. Without holes (hole 0) no sample is below hole.
    const auto hole = static_cast<float>(depth.holeBelow);
    const bool drawn = !(z00 < hole || z10 < hole || z11 < hole || z01 < hole);
    const float mismatch = w == 1 && h == 1 ? 0.0f : mesh::kCoverageError;
    double sum = 0.0;
    for (int r = r0; r <= r1; ++r) {
        const int dr = r - r0;
        const float v = static_cast<float>(dr) / static_cast<float>(h);
        // First column on the upper triangle: (c − c0)·h ≥ dr·w.
        const int split = c0 + (dr * w + h - 1) / h;
        const std::uint8_t *p = row(r);
        float rowMax = 0.0f;
        float rowSum = 0.0f;
        // Lower triangle (u < v): z00 + v·(z01 − z00) + u·(z11 − z01).
        float a = z00 + v * (z01 - z00);
        float b = (z11 - z01) * invW;
        for (int c = c0; c < split; ++c) {
            const float z = loadSample<T>(p, c);
            const float g = std::fabs(a + b * static_cast<float>(c - c0) - z);
            rowSum += drawn && z >= hole ? g : 0.0f;
            rowMax = std::max(rowMax, mesh::sampleError(g, z < hole, drawn, mismatch));
        }
        // Upper triangle (u ≥ v): z00 + u·(z10 − z00) + v·(z11 − z10).
        a = z00 + v * (z11 - z10);
        b = (z10 - z00) * invW;
        for (int c = split; c <= c1; ++c) {
            const float z = loadSample<T>(p, c);
            const float g = std::fabs(a + b * static_cast<float>(c - c0) - z);
            rowSum += drawn && z >= hole ? g : 0.0f;
            rowMax = std::max(rowMax, mesh::sampleError(g, z < hole, drawn, mismatch));
        }
        sum += static_cast<double>(rowSum);
        out.max = std::max(out.max, rowMax);
        if (rowMax > rowLimit || sum > sumLimit) {
            out.stopped = true;
            break;
        }
    }
    out.sum = static_cast<float>(sum);
    return out;
}

/// Whether the two triangles of block (c0..c1, r0..r1) are within \a tolerance of every sample of
/// the block (Max), or on average with every sample within \a cap (Mean).
template <class T>
bool blockWithin(const scene::DepthFrameView &depth, int c0, int r0, int c1, int r1,
                 float tolerance, float cap, bool mean) noexcept
{
    const double budget = mean ? static_cast<double>(tolerance) * (c1 - c0 + 1) * (r1 - r0 + 1)
                               : std::numeric_limits<double>::infinity();
    return !scanBlock<T>(depth, c0, r0, c1, r1, mean ? cap : tolerance, budget).stopped;
}

/// The block's error (see scanBlock); stops (with a partial sum) once a row exceeds \a cap.
template <class T>
BlockError blockError(const scene::DepthFrameView &depth, int c0, int r0, int c1, int r1,
                      float cap) noexcept
{
    return scanBlock<T>(depth, c0, r0, c1, r1, cap, std::numeric_limits<double>::infinity());
}

// Priorities of the budgeted refinement: blocks larger than maxStep first (always split), then
// blocks over the cap, the largest first (so under a block budget every depth edge is refined to
// the same size), then the rest by error removed per added triangle (at most 256² · 65535 / 6,
// far below kOverCap).
constexpr float kMust = std::numeric_limits<float>::max();
constexpr float kOverCap = 1e30f;

/// The running totals count each sample once: a block owns its w·h samples (not its bottom and
/// right borders, its neighbours' own), with its error sum scaled to them.
std::pair<double, double> owned(const BlockError &e, int size, int c0, int r0, int cx, int cy)
{
    const int w = std::min(c0 + size, cx) - c0;
    const int h = std::min(r0 + size, cy) - r0;
    const double share = e.count > 0 ? static_cast<double>(w * h) / e.count : 0.0;
    return std::pair<double, double>(static_cast<double>(e.sum) * share,
                                     static_cast<double>(w * h));
}

} // namespace

template <class T>
void AdaptiveMesh::splitBlock(const scene::DepthFrameView &depth, const MeshOptions &options,
                              int c0, int r0, int size, int &finest)
{
    const int c1 = std::min(c0 + size, width_ - 1);
    const int r1 = std::min(r0 + size, height_ - 1);
    const bool mean = options.criterion == ErrorCriterion::Mean;
    if (size == 1 || (size <= options.maxStep &&
                      blockWithin<T>(depth, c0, r0, c1, r1, static_cast<float>(options.tolerance),
                                     static_cast<float>(options.maxErrorCap), mean))) {
        const int l = log2i(size);
        blocks_.push_back({c0, r0, l});
        ++stats_.blocksAtSize[l];
        finest = std::min(finest, size);
        const auto cellsX = static_cast<std::size_t>(width_ - 1);
        for (int r = r0; r < r1; ++r)
            std::fill_n(cellBlock_.begin() +
                            static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) * cellsX +
                                                        static_cast<std::size_t>(c0)),
                        c1 - c0, static_cast<std::uint8_t>(l));
        return;
    }
    const int half = size / 2;
    for (int dy = 0; dy <= half; dy += half)
        for (int dx = 0; dx <= half; dx += half)
            if (c0 + dx < width_ - 1 && r0 + dy < height_ - 1)
                splitBlock<T>(depth, options, c0 + dx, r0 + dy, half, finest);
}

template <class T>
void AdaptiveMesh::buildQuadtree(const scene::DepthFrameView &depth, const MeshOptions &options)
{
    blocks_.clear();
    cellBlock_.resize(static_cast<std::size_t>(width_ - 1) * static_cast<std::size_t>(height_ - 1));
    for (int ty = 0; ty < tilesY_; ++ty) {
        for (int tx = 0; tx < tilesX_; ++tx) {
            int finest = tile_;
            splitBlock<T>(depth, options, tx * tile_, ty * tile_, tile_, finest);
            steps_[static_cast<std::size_t>(ty * tilesX_ + tx)] =
                static_cast<std::uint16_t>(finest);
            ++stats_.tilesAtStep[log2i(finest)];
        }
    }
    stats_.blocks = static_cast<int>(blocks_.size());
    indices_.clear();
    for (const Block &b : blocks_)
        emitBlock(b.c0, b.r0, 1 << b.log2Size);
}

/// \brief The greedy refinement of buildQuadtreeBudget(): the queue of blocks (the nodes stay put
/// in nodes_, a re-queued node keeps its slot, so heap moves are 8 bytes instead of a whole node)
/// and the running error totals over the blocks' samples.
template <class T> struct AdaptiveMesh::BudgetRefinement {
    using Node = QueuedBlock;

    AdaptiveMesh &m;
    const scene::DepthFrameView &depth;
    const MeshOptions &options;
    const float cap;
    const int cellsX;
    const int cellsY;
    double totalSum = 0.0;
    double totalCount = 0.0;

    static bool less(const HeapEntry &a, const HeapEntry &b) { return a.priority < b.priority; }

    /// The error of block (c0, r0) of \a size.
    BlockError measure(int c0, int r0, int size) const
    {
        if (size == 1)
            return BlockError{0.0f, 0.0f, 4}; // a single cell is exact
        return blockError<T>(depth, c0, r0, std::min(c0 + size, cellsX),
                             std::min(r0 + size, cellsY), cap);
    }

    /// Queues block (c0, r0) of \a size with its error \a self (a single cell is a leaf at once).
    void push(int c0, int r0, int size, const BlockError &self)
    {
        if (size == 1) {
            m.blocks_.push_back({c0, r0, 0});
            totalCount += 1.0;
            return;
        }
        Node n{};
        const int log2Size = log2i(size);
        n.priority = size > options.maxStep ? kMust
                     : self.max > cap       ? kOverCap * static_cast<float>(1 + log2Size)
                                            : self.sum;
        n.c0 = c0;
        n.r0 = r0;
        n.log2Size = log2Size;
        n.sum = self.sum;
        n.count = self.count;
        n.looked = false;
        m.nodes_.push_back(n);
        m.heap_.push_back({n.priority, static_cast<std::uint32_t>(m.nodes_.size() - 1)});
        std::push_heap(m.heap_.begin(), m.heap_.end(), less);
        const auto [sum, count] = owned(self, size, c0, r0, cellsX, cellsY);
        totalSum += sum;
        totalCount += count;
    }

    /// Measures the children of queued node \a slot once. \return true when the node went back
    /// into the queue with its true gain; false when it must be split now.
    bool lookInto(std::uint32_t slot)
    {
        Node &n = m.nodes_[slot];
        const int half = 1 << (n.log2Size - 1);
        const bool must = n.priority >= kOverCap;
        if (n.looked)
            return false;
        // Measure the children once; a block that must split is split at once.
        double childSum = 0.0;
        double childCount = 0.0;
        int k = 0;
        for (int dy = 0; dy <= half; dy += half)
            for (int dx = 0; dx <= half; dx += half, ++k) {
                BlockError e{0.0f, 0.0f, 0};
                if (n.c0 + dx < cellsX && n.r0 + dy < cellsY)
                    e = measure(n.c0 + dx, n.r0 + dy, half);
                n.child[k] = {e.sum, e.max, e.count};
                childSum += static_cast<double>(e.sum);
                childCount += e.count;
            }
        n.looked = true;
        if (must)
            return false;
        const double mean = n.count > 0 ? static_cast<double>(n.sum) / n.count : 0.0;
        const double childMean = childCount > 0.0 ? childSum / childCount : 0.0;
        n.priority = static_cast<float>((mean - childMean) * n.count / 6.0);
        m.heap_.push_back({n.priority, slot});
        std::push_heap(m.heap_.begin(), m.heap_.end(), less);
        return true;
    }

    /// Replaces queued node \a slot by its children.
    void split(std::uint32_t slot)
    {
        const int half = 1 << (m.nodes_[slot].log2Size - 1);
        const Node split = m.nodes_[slot]; // push() below may move nodes_
        const auto [ownSum, ownCount] =
            owned(BlockError{split.sum, 0.0f, split.count}, 1 << split.log2Size, split.c0, split.r0,
                  cellsX, cellsY);
        totalSum -= ownSum;
        totalCount -= ownCount;
        int k = 0;
        for (int dy = 0; dy <= half; dy += half)
            for (int dx = 0; dx <= half; dx += half, ++k)
                if (split.c0 + dx < cellsX && split.r0 + dy < cellsY)
                    push(split.c0 + dx, split.r0 + dy, half,
                         BlockError{split.child[k].sum, split.child[k].max, split.child[k].count});
    }

    /// Queues every tile as one block, then splits until the mean error is within the tolerance,
    /// the block budget is spent or the queue is empty; the queue's blocks become leaves.
    void run()
    {
        const std::size_t budget = options.maxBlocks;
        m.nodes_.clear();
        m.heap_.clear();
        m.blocks_.clear();
        for (int ty = 0; ty < m.tilesY_; ++ty)
            for (int tx = 0; tx < m.tilesX_; ++tx)
                push(tx * m.tile_, ty * m.tile_, m.tile_,
                     measure(tx * m.tile_, ty * m.tile_, m.tile_));
        while (!m.heap_.empty()) {
            const float top = m.heap_.front().priority;
            if (top < kOverCap && totalSum <= options.tolerance * totalCount)
                break;
            // A split turns one leaf into four (at most); blocks larger than maxStep split
            // regardless.
            if (budget > 0 && top < kMust && m.heap_.size() + m.blocks_.size() + 3 > budget) {
                m.stats_.budgetLimited = true;
                break;
            }
            std::pop_heap(m.heap_.begin(), m.heap_.end(), less);
            const std::uint32_t slot = m.heap_.back().node;
            m.heap_.pop_back();
            if (lookInto(slot))
                continue;
            split(slot);
        }
        for (const HeapEntry &e : m.heap_) {
            const Node &n = m.nodes_[e.node];
            m.blocks_.push_back({n.c0, n.r0, n.log2Size});
        }
    }
};

template <class T>
void AdaptiveMesh::buildQuadtreeBudget(const scene::DepthFrameView &depth,
                                       const MeshOptions &options)
{
    // Greedy refinement against one error budget for the whole frame: every tile starts as one
    // block; the block whose split removes the most error per added triangle is split next (a
    // block over the cap or larger than maxStep first), until the mean error over the blocks'
    // samples is within the tolerance. Lazy greedy: a block is queued with its own error as an
    // upper bound of its gain; when it comes first, its children are measured, and it is queued
    // again with its true gain (their errors kept for the split). Flat but noisy blocks, whose
    // error a split does not reduce, thus stay whole, and only blocks that reach the top are looked
    // into.
    BudgetRefinement<T> refinement{
        *this, depth, options, static_cast<float>(options.maxErrorCap), width_ - 1, height_ - 1};
    refinement.run();
    orderBlocks();
    markBlocks();
    stats_.blocks = static_cast<int>(blocks_.size());
    indices_.clear();
    for (const Block &b : blocks_)
        emitBlock(b.c0, b.r0, 1 << b.log2Size);
}

void AdaptiveMesh::orderBlocks()
{
    // Emission order: tile by tile, and inside a tile by position, for locality. One integer key
    // per block sorts in about half the time of comparing tuples: tile row and column (16 bits
    // each), row and column inside the tile (8 bits each: tiles are at most 256 cells) and size.
    const int tileShift = log2i(tile_);
    const int inTile = tile_ - 1;
    sortKeys_.clear();
    for (const Block &b : blocks_)
        sortKeys_.push_back(static_cast<std::uint64_t>(b.r0 >> tileShift) << 40 |
                            static_cast<std::uint64_t>(b.c0 >> tileShift) << 24 |
                            static_cast<std::uint64_t>(b.r0 & inTile) << 16 |
                            static_cast<std::uint64_t>(b.c0 & inTile) << 8 |
                            static_cast<std::uint64_t>(b.log2Size));
    std::sort(sortKeys_.begin(), sortKeys_.end());
    for (std::size_t i = 0; i < sortKeys_.size(); ++i) {
        const std::uint64_t k = sortKeys_[i];
        blocks_[i] = {static_cast<int>((k >> 24 & 0xffff) << tileShift | (k >> 8 & 0xff)),
                      static_cast<int>((k >> 40 & 0xffff) << tileShift | (k >> 16 & 0xff)),
                      static_cast<int>(k & 0xff)};
    }
}

void AdaptiveMesh::markBlocks()
{
    const int tileShift = log2i(tile_);
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    cellBlock_.resize(static_cast<std::size_t>(cellsX) * static_cast<std::size_t>(cellsY));
    std::vector<int> &finest = finestScratch_;
    finest.assign(steps_.size(), tile_);
    for (const Block &b : blocks_) {
        const int size = 1 << b.log2Size;
        ++stats_.blocksAtSize[b.log2Size];
        const std::size_t t =
            static_cast<std::size_t>((b.r0 >> tileShift) * tilesX_ + (b.c0 >> tileShift));
        finest[t] = std::min(finest[t], size);
        const int c1 = std::min(b.c0 + size, cellsX);
        const int r1 = std::min(b.r0 + size, cellsY);
        for (int r = b.r0; r < r1; ++r)
            std::fill_n(cellBlock_.begin() +
                            static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) *
                                                            static_cast<std::size_t>(cellsX) +
                                                        static_cast<std::size_t>(b.c0)),
                        c1 - b.c0, static_cast<std::uint8_t>(b.log2Size));
    }
    for (std::size_t t = 0; t < steps_.size(); ++t) {
        steps_[t] = static_cast<std::uint16_t>(finest[t]);
        ++stats_.tilesAtStep[log2i(finest[t])];
    }
}

template void AdaptiveMesh::buildQuadtree<std::uint8_t>(const scene::DepthFrameView &,
                                                        const MeshOptions &);
template void AdaptiveMesh::buildQuadtree<std::uint16_t>(const scene::DepthFrameView &,
                                                         const MeshOptions &);
template void AdaptiveMesh::buildQuadtreeBudget<std::uint8_t>(const scene::DepthFrameView &,
                                                              const MeshOptions &);
template void AdaptiveMesh::buildQuadtreeBudget<std::uint16_t>(const scene::DepthFrameView &,
                                                               const MeshOptions &);

} // namespace depthtouch::render
