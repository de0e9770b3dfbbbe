#include "depthtouch/render/adaptive_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <tuple>
#include <utility>

namespace depthtouch::render {

namespace {

bool isPowerOfTwo(int v) noexcept
{
    return v > 0 && (v & (v - 1)) == 0;
}

int log2i(int v) noexcept
{
    int l = 0;
    while ((1 << (l + 1)) <= v)
        ++l;
    return l;
}

/// Value at (c, r) of the linear triangle surface of the cell (ca..cb, ra..rb) split by its
/// top-left → bottom-right diagonal (DESIGN.md §3).
inline double cellValue(double z00, double z10, double z11, double z01, double u, double v) noexcept
{
    if (u >= v)
        return z00 + u * (z10 - z00) + v * (z11 - z10);
    return z00 + v * (z01 - z00) + u * (z11 - z01);
}

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
BlockError scanBlock(const haptics::DepthFrameView &depth, int c0, int r0, int c1, int r1,
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
            const float e = std::fabs(a + b * static_cast<float>(c - c0) - loadSample<T>(p, c));
            rowSum += e;
            rowMax = std::max(rowMax, e);
        }
        // Upper triangle (u ≥ v): z00 + u·(z10 − z00) + v·(z11 − z10).
        a = z00 + v * (z11 - z10);
        b = (z10 - z00) * invW;
        for (int c = split; c <= c1; ++c) {
            const float e = std::fabs(a + b * static_cast<float>(c - c0) - loadSample<T>(p, c));
            rowSum += e;
            rowMax = std::max(rowMax, e);
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
bool blockWithin(const haptics::DepthFrameView &depth, int c0, int r0, int c1, int r1, float tolerance,
                 float cap, bool mean) noexcept
{
    const double budget = mean ? static_cast<double>(tolerance) * (c1 - c0 + 1) * (r1 - r0 + 1)
                               : std::numeric_limits<double>::infinity();
    return !scanBlock<T>(depth, c0, r0, c1, r1, mean ? cap : tolerance, budget).stopped;
}

/// The block's error (see scanBlock); stops (with a partial sum) once a row exceeds \a cap.
template <class T>
BlockError blockError(const haptics::DepthFrameView &depth, int c0, int r0, int c1, int r1, float cap) noexcept
{
    return scanBlock<T>(depth, c0, r0, c1, r1, cap, std::numeric_limits<double>::infinity());
}

} // namespace

template <class T>
void AdaptiveMesh::splitBlock(const haptics::DepthFrameView &depth, const MeshOptions &options, int c0,
                              int r0, int size, int &finest)
{
    const int c1 = std::min(c0 + size, width_ - 1);
    const int r1 = std::min(r0 + size, height_ - 1);
    const bool mean = options.criterion == ErrorCriterion::Mean;
    if (size == 1 ||
        (size <= options.maxStep &&
         blockWithin<T>(depth, c0, r0, c1, r1, static_cast<float>(options.tolerance),
                        static_cast<float>(options.maxErrorCap), mean))) {
        const int l = log2i(size);
        blocks_.push_back({c0, r0, l});
        ++stats_.blocksAtSize[l];
        finest = std::min(finest, size);
        const auto cellsX = static_cast<std::size_t>(width_ - 1);
        for (int r = r0; r < r1; ++r)
            std::fill_n(cellBlock_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) * cellsX +
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
void AdaptiveMesh::buildQuadtree(const haptics::DepthFrameView &depth, const MeshOptions &options)
{
    blocks_.clear();
    cellBlock_.resize(static_cast<std::size_t>(width_ - 1) * static_cast<std::size_t>(height_ - 1));
    for (int ty = 0; ty < tilesY_; ++ty) {
        for (int tx = 0; tx < tilesX_; ++tx) {
            int finest = tile_;
            splitBlock<T>(depth, options, tx * tile_, ty * tile_, tile_, finest);
            steps_[static_cast<std::size_t>(ty * tilesX_ + tx)] = static_cast<std::uint16_t>(finest);
            ++stats_.tilesAtStep[log2i(finest)];
        }
    }
    stats_.blocks = static_cast<int>(blocks_.size());
    indices_.clear();
    for (const Block &b : blocks_)
        emitBlock(b.c0, b.r0, 1 << b.log2Size);
}

template <class T>
void AdaptiveMesh::buildQuadtreeBudget(const haptics::DepthFrameView &depth, const MeshOptions &options)
{
    // Greedy refinement against one error budget for the whole frame: every tile starts as one
    // block; the block whose split removes the most error per added triangle is split next (a
    // block over the cap or larger than maxStep first), until the mean error over the blocks'
    // samples is within the tolerance. Lazy greedy: a block is queued with its own error as an upper
    // bound of its gain; when it comes first, its children are measured, and it is queued again with
    // its true gain (their errors kept for the split). Flat but noisy blocks, whose error a split
    // does not reduce, thus stay whole, and only blocks that reach the top are looked into.
    const auto cap = static_cast<float>(options.maxErrorCap);
    const int cellsX = width_ - 1;
    const int cellsY = height_ - 1;
    using Node = QueuedBlock;
    // The heap holds (priority, node) pairs; the nodes stay put in nodes_ (a re-queued node keeps
    // its slot), so heap moves are 8 bytes instead of a whole node.
    const auto less = [](const HeapEntry &a, const HeapEntry &b) { return a.priority < b.priority; };
    nodes_.clear();
    // Priorities: blocks larger than maxStep first (always split), then blocks over the cap, the
    // largest first (so under a block budget every depth edge is refined to the same size), then
    // the rest by error removed per added triangle (at most 256² · 65535 / 6, far below kOverCap).
    constexpr float kMust = std::numeric_limits<float>::max();
    constexpr float kOverCap = 1e30f;
    const std::size_t budget = options.maxBlocks;
    heap_.clear();
    blocks_.clear();
    double totalSum = 0.0;
    double totalCount = 0.0;
    const auto measure = [&](int c0, int r0, int size) {
        if (size == 1)
            return BlockError{0.0f, 0.0f, 4}; // a single cell is exact
        return blockError<T>(depth, c0, r0, std::min(c0 + size, cellsX), std::min(r0 + size, cellsY), cap);
    };
    // The running totals count each sample once: a block owns its w·h samples (not its bottom
    // and right borders, its neighbours' own), with its error sum scaled to them.
    const auto owned = [](const BlockError &e, int size, int c0, int r0, int cx, int cy) {
        const int w = std::min(c0 + size, cx) - c0;
        const int h = std::min(r0 + size, cy) - r0;
        const double share = e.count > 0 ? static_cast<double>(w * h) / e.count : 0.0;
        return std::pair<double, double>(static_cast<double>(e.sum) * share, static_cast<double>(w * h));
    };
    const auto push = [&](int c0, int r0, int size, const BlockError &self) {
        if (size == 1) {
            blocks_.push_back({c0, r0, 0});
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
        nodes_.push_back(n);
        heap_.push_back({n.priority, static_cast<std::uint32_t>(nodes_.size() - 1)});
        std::push_heap(heap_.begin(), heap_.end(), less);
        const auto [sum, count] = owned(self, size, c0, r0, cellsX, cellsY);
        totalSum += sum;
        totalCount += count;
    };
    for (int ty = 0; ty < tilesY_; ++ty)
        for (int tx = 0; tx < tilesX_; ++tx)
            push(tx * tile_, ty * tile_, tile_, measure(tx * tile_, ty * tile_, tile_));
    while (!heap_.empty()) {
        const float top = heap_.front().priority;
        if (top < kOverCap && totalSum <= options.tolerance * totalCount)
            break;
        // A split turns one leaf into four (at most); blocks larger than maxStep split regardless.
        if (budget > 0 && top < kMust && heap_.size() + blocks_.size() + 3 > budget) {
            stats_.budgetLimited = true;
            break;
        }
        std::pop_heap(heap_.begin(), heap_.end(), less);
        const std::uint32_t slot = heap_.back().node;
        heap_.pop_back();
        Node &n = nodes_[slot];
        const int half = 1 << (n.log2Size - 1);
        const bool must = n.priority >= kOverCap;
        if (!n.looked) {
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
            if (!must) {
                const double mean = n.count > 0 ? static_cast<double>(n.sum) / n.count : 0.0;
                const double childMean = childCount > 0.0 ? childSum / childCount : 0.0;
                n.priority = static_cast<float>((mean - childMean) * n.count / 6.0);
                heap_.push_back({n.priority, slot});
                std::push_heap(heap_.begin(), heap_.end(), less);
                continue;
            }
        }
        const Node split = n; // push() below may move nodes_
        const auto [ownSum, ownCount] = owned(BlockError{split.sum, 0.0f, split.count}, 1 << split.log2Size,
                                              split.c0, split.r0, cellsX, cellsY);
        totalSum -= ownSum;
        totalCount -= ownCount;
        int k = 0;
        for (int dy = 0; dy <= half; dy += half)
            for (int dx = 0; dx <= half; dx += half, ++k)
                if (split.c0 + dx < cellsX && split.r0 + dy < cellsY)
                    push(split.c0 + dx, split.r0 + dy, half,
                         BlockError{split.child[k].sum, split.child[k].max, split.child[k].count});
    }
    for (const HeapEntry &e : heap_) {
        const Node &n = nodes_[e.node];
        blocks_.push_back({n.c0, n.r0, n.log2Size});
    }
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
    cellBlock_.resize(static_cast<std::size_t>(cellsX) * static_cast<std::size_t>(cellsY));
    std::vector<int> &finest = finestScratch_;
    finest.assign(steps_.size(), tile_);
    for (const Block &b : blocks_) {
        const int size = 1 << b.log2Size;
        ++stats_.blocksAtSize[b.log2Size];
        const std::size_t t = static_cast<std::size_t>((b.r0 >> tileShift) * tilesX_ + (b.c0 >> tileShift));
        finest[t] = std::min(finest[t], size);
        const int c1 = std::min(b.c0 + size, cellsX);
        const int r1 = std::min(b.r0 + size, cellsY);
        for (int r = b.r0; r < r1; ++r)
            std::fill_n(cellBlock_.begin() +
                            static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) * static_cast<std::size_t>(cellsX) +
                                                        static_cast<std::size_t>(b.c0)),
                        c1 - b.c0, static_cast<std::uint8_t>(b.log2Size));
    }
    for (std::size_t t = 0; t < steps_.size(); ++t) {
        steps_[t] = static_cast<std::uint16_t>(finest[t]);
        ++stats_.tilesAtStep[log2i(finest[t])];
    }
    stats_.blocks = static_cast<int>(blocks_.size());
    indices_.clear();
    for (const Block &b : blocks_)
        emitBlock(b.c0, b.r0, 1 << b.log2Size);
}

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

double AdaptiveMesh::tileError(const haptics::DepthFrameView &depth, int tx, int ty, int step,
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
            const double z00 = depth.sample(ca, ra);
            const double z10 = depth.sample(cb, ra);
            const double z11 = depth.sample(cb, rb);
            const double z01 = depth.sample(ca, rb);
            for (int r = ra; r <= rb; ++r) {
                const double v = (r - ra) * invH;
                for (int c = ca; c <= cb; ++c) {
                    const double u = (c - ca) * invW;
                    const double e = std::fabs(cellValue(z00, z10, z11, z01, u, v) -
                                               static_cast<double>(depth.sample(c, r)));
                    sum += e;
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

Result<void> AdaptiveMesh::build(const haptics::DepthFrameView &depth, const MeshOptions &options)
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
        return unexpected(Errc::InvalidArgument, "mesh error tolerance and cap must be >= 0 levels");
    if (static_cast<long long>(depth.width) * depth.height > (1LL << 31) || depth.width > 65536 ||
        depth.height > 65536)
        return unexpected(Errc::InvalidArgument, "depth frame too large (over 65536 samples a side or 2^31 in all)");

    width_ = depth.width;
    height_ = depth.height;
    tile_ = options.tileSize;
    tilesX_ = (width_ - 1 + tile_ - 1) / tile_;
    tilesY_ = (height_ - 1 + tile_ - 1) / tile_;
    steps_.assign(static_cast<std::size_t>(tilesX_) * static_cast<std::size_t>(tilesY_), 1);
    stats_ = MeshStats{};
    stats_.tiles = tilesX_ * tilesY_;
    if (options.mode == MeshMode::Quadtree) {
        const bool budget = options.criterion == ErrorCriterion::Mean;
        if (depth.format == haptics::SampleFormat::Gray8) {
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
                            (options.criterion == ErrorCriterion::Max || mean <= options.tolerance)) {
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
            emitTile(tx, ty);
    stats_.triangles = indices_.size() / 3;
    return ok();
}

void AdaptiveMesh::emitTile(int tx, int ty)
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
    const auto triangle = [this](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (a == b || b == c || a == c)
            return;
        indices_.push_back(a);
        indices_.push_back(b);
        indices_.push_back(c);
    };

    for (int ra = r0; ra < r1; ra += s) {
        const int rb = std::min(ra + s, r1);
        for (int ca = c0; ca < c1; ca += s) {
            const int cb = std::min(ca + s, c1);
            const std::uint32_t a = vertex(ca, ra);
            const std::uint32_t b = vertex(cb, ra);
            const std::uint32_t c = vertex(cb, rb);
            const std::uint32_t d = vertex(ca, rb);
            triangle(a, b, c); // (c, r), (c+1, r), (c+1, r+1): haptics TriangleId upper == 0
            triangle(a, c, d); // (c, r), (c+1, r+1), (c, r+1): upper == 1
        }
    }
}

MeshError measureMeshError(const haptics::DepthFrameView &depth,
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
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t i = indices[t + static_cast<std::size_t>(k)];
            if (i >= n) {
                inside = false;
                break;
            }
            cx[k] = i % static_cast<std::uint32_t>(w);
            cy[k] = i / static_cast<std::uint32_t>(w);
            val[k] = depth.sample(static_cast<int>(cx[k]), static_cast<int>(cy[k]));
        }
        if (!inside)
            continue;
        const long long area = (cx[1] - cx[0]) * (cy[2] - cy[0]) - (cy[1] - cy[0]) * (cx[2] - cx[0]);
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
                const double v = (static_cast<double>(e[0]) * val[0] +
                                  static_cast<double>(e[1]) * val[1] +
                                  static_cast<double>(e[2]) * val[2]) /
                                 a;
                const std::size_t idx = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(x);
                error[idx] = static_cast<float>(
                    std::fabs(v - depth.sample(static_cast<int>(x), static_cast<int>(y))));
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
