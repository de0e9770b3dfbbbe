#pragma once
/// \file
/// \brief The grid mesh drawn for a depth frame: full resolution, a fixed decimation, or an
/// adaptive mesh whose level of detail is chosen per tile and per frame from the depth variation
/// inside the tile, with crack-free tile borders. CPU only (no GL): it produces the triangle list
/// (indices of full-resolution grid vertices, vertex k = sample (k mod W, k div W)) that the
/// renderer draws with the heights fetched from the depth texture.
///
/// Tiles and levels: the W−1 × H−1 cells are cut into tiles of T×T cells (T = tileSize, a power of
/// two; the last row and column of tiles may be smaller). A tile at step s (1, 2, 4, … ≤ T) keeps
/// the vertices whose column and row offsets inside the tile are multiples of s, plus the tile's
/// last column and row, and splits each cell by its diagonal from the top-left to the bottom-right
/// corner, the orientation of docs/architecture.md §3 (so step 1 is exactly the haptic renderer's
/// triangulation).
///
/// Level choice (adaptive): the coarsest step whose piecewise-linear surface is within `tolerance`
/// nearness levels of the tile's samples, borders included: every sample (ErrorCriterion::Max, as
/// in error-bounded terrain LOD: Lindstrom et al., "Real-time, continuous level of detail rendering
/// of height fields", SIGGRAPH 1996, here with whole tiles instead of single vertices), or on
/// average with a cap on the largest error (ErrorCriterion::Mean, the default: real depth carries
/// sensor and quantisation noise of about a level, which a max bound would follow down to full
/// resolution).
///
/// Quadtree: a tile is one block; a block that does not meet the criterion as two
/// triangles (its four corners, split by the same diagonal), or is larger than `maxStep`, is split
/// into four, down to single cells. With ErrorCriterion::Max every block's largest error is bounded
/// by the tolerance. With ErrorCriterion::Mean the tolerance is one budget for the whole frame: the
/// block whose split removes the most error per added triangle is split first (blocks over the cap
/// always), until the mean error over the blocks' samples is within it (greedy rate-distortion
/// refinement with one level of look-ahead), so the triangles go where they reduce error most. On
/// the 7-Scenes kitchen it draws about a quarter fewer triangles than the per-tile choice at the
/// same mean error; its choice costs more CPU time, but the fewer triangles win on llvmpipe, so it
/// is the default. Flat and planar regions (a plane in the scene is a plane in nearness, which is
/// affine in 1/Z) become a few large triangles and only the blocks along depth edges go fine, where
/// a per-tile step must refine the whole tile. A restricted-quadtree LOD without the restriction:
/// Pajarola, "Large scale terrain visualization using the restricted quadtree triangulation", IEEE
/// Visualization 1998, with the cracks closed by snapping as below.
///
/// Crack-free borders: where a tile meets a coarser neighbour, its border vertices are moved along
/// the border to the neighbour's vertex at or before them (stitching by vertex snapping); triangles
/// that collapse are dropped. Both tiles then share the same border vertices (no T-junction), so
/// the surface is watertight for any step ratio. The stitching strip of the finer tile interpolates
/// between the coarse border and its own first inner row; its error is measured, not bounded.
///
/// In quadtree mode the same holds per leaf block: a block's corner on the side of a larger
/// neighbouring block snaps back along that side to the neighbour's corner.
///
/// Blocks (MeshMode::Blocks): one step per tile (block) as in Adaptive, but no triangle list per
/// frame. Each tile's triangles at each step, unstitched, are made once per depth frame size into
/// one static index buffer (BlockRanges, block_ranges.h); a frame only chooses a step per tile and
/// the renderer draws the chosen ranges, its vertex shader snapping border vertices to the coarser
/// neighbour's step (the rule of Adaptive above, so the drawn surface is the list that
/// drawnIndices() gives, collapsed triangles aside). The step is chosen from the error of each step
/// at a coarse set of probes (samples at odd offsets 8 apart: 1/64 of the samples, none of them a
/// vertex of any step ≥ 2) against the frame's mean error budget and the leaf budget, greedily
/// (error removed per added cell, tiles over the cap first), so the CPU work per frame is
/// proportional to the probes and the tiles, not to the triangles.
///
/// Holes (docs/architecture.md §3 "Holes", DepthFrameView::holeBelow): a triangle with a hole
/// vertex is not drawn. The error measures leave holes out: a hole's code is no depth, so the jump
/// from it to a measured neighbour is no geometric error, and a hole under a block whose corners
/// are holes counts nothing. Coverage does count: a block that would draw a surface over a hole
/// sample, or leave out a measured sample under a triangle with a hole corner, is refined like a
/// block across a depth edge (over any cap), down to single cells, so the outline of a hole is
/// drawn at full resolution in every mode (Blocks sees it on every other row and at its probes).
/// measureMeshError() counts holes and undrawn triangles as no error.
///
/// Thread-safety: thread-bound (one object per render thread); build() reuses its buffers and does
/// not allocate once they have grown to the largest mesh.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "depthtouch/scene/depth_frame.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::render {

/// \brief How the mesh is chosen.
enum class MeshMode : std::uint8_t {
    Fixed,    ///< Every tile at `fixedStep` (1 = full resolution, the haptic triangulation).
    Adaptive, ///< Per-tile step from the error tolerance.
    Quadtree, ///< Per-block: each tile split as a quadtree; each leaf block is two triangles.
    Blocks,   ///< Per-tile step from probes and a frame budget, drawn from precomputed ranges
              ///< (tileSize ≥ 16; see the file comment). The mesh holds no triangle list.
};

/// \brief What the adaptive tolerance bounds in each tile.
enum class ErrorCriterion : std::uint8_t {
    Max,  ///< The largest |surface − sample| of the tile ≤ tolerance.
    Mean, ///< The tile's mean |surface − sample| ≤ tolerance (Quadtree: the frame's mean), and its
          ///< largest ≤ maxErrorCap (so depth edges stay sharp while sensor noise does not force
          ///< full resolution).
};

/// \brief Mesh options.
/// The default is the budgeted quadtree with a mean error of half a nearness level: on the 7-Scenes
/// kitchen at 720×486 it draws about 36 000 triangles (the per-tile choice needs about 58 000 at
/// tolerance 1.2 for a mean error of 0.43), and with colour sampled nearest on llvmpipe the fewer
/// triangles outweigh its dearer choice (`depthtouch bench render`).
struct MeshOptions {
    MeshMode mode = MeshMode::Quadtree;
    int tileSize = 32; ///< Cells per tile side T: a power of two, 2..256 (Quadtree: root block).
    int fixedStep = 1;        ///< Fixed mode: step in samples, a power of two ≤ tileSize.
    double tolerance = 0.5;   ///< Error bound (see criterion), nearness levels (≥ 0): per tile
                              ///< (Adaptive), per block (Quadtree, Max) or the frame's mean error
                              ///< budget (Quadtree, Mean).
    int maxStep = 32;         ///< Adaptive/Quadtree: coarsest step (block size) allowed, a power of
                              ///< two ≤ tileSize.
    ErrorCriterion criterion = ErrorCriterion::Mean; ///< Adaptive/Quadtree: what tolerance bounds.
    double maxErrorCap =
        16.0; ///< Mean criterion: largest error allowed in a tile or block, levels.
    std::size_t maxBlocks =
        0; ///< Quadtree, Mean criterion: most leaf blocks (0: no budget); Blocks:
           ///< most cells at the tiles' steps (a tile of T×T cells at step s
           ///< counts (T/s)², two triangles each). Quadtree: each
           ///< leaf is two triangles, more where the corners of finer
           ///< neighbours close T-junctions (about 2.3 a block on the 7-Scenes
           ///< kitchen). When the budget is reached the refinement stops before
           ///< the tolerance and the cap are met (MeshStats::budgetLimited);
           ///< blocks over the cap are then refined breadth first (the largest
           ///< first), so every depth edge gets the same detail. The player's
           ///< level-of-detail controller (LodController) sets it per frame.

    bool operator==(const MeshOptions &) const = default;
};

/// \brief Counts of one build.
struct MeshStats {
    std::size_t triangles = 0; ///< Triangles in the list (collapsed ones excluded).
    int tiles = 0;             ///< Tiles in the frame.
    int tilesAtStep[9] = {};   ///< Tiles per step: index log2(step) (1, 2, 4 … 256); Quadtree: the
                               ///< step of the tile's finest leaf block.
    int blocks = 0;            ///< Quadtree: leaf blocks (0 in the other modes).
    int blocksAtSize[9] = {};  ///< Quadtree: leaf blocks per size, index log2(cells a side).
    bool budgetLimited = false;  ///< Quadtree, Blocks: MeshOptions::maxBlocks stopped the
                                 ///< refinement.
    double estimatedError = 0.0; ///< Blocks: the frame's mean error estimated from the probes,
                                 ///< nearness levels (an overestimate at step 2: the probes are
                                 ///< cell centres).
};

/// \brief Geometric error of a mesh against the samples it approximates.
struct MeshError {
    double mean = 0.0;             ///< Mean |surface − sample| over the samples, nearness levels.
    double max = 0.0;              ///< Largest |surface − sample|, nearness levels.
    std::size_t uncovered = 0; ///< Samples no triangle covers (a crack or hole): 0 when watertight.
    std::size_t samples = 0;       ///< Samples measured (W·H).
};

/// \brief Builds and holds the triangle list of a depth frame.
class AdaptiveMesh {
public:
    /// \brief Chooses the tile steps for \a depth and fills indices().
    /// \return Errc::InvalidArgument for a malformed frame or options (tile size or step not a
    /// power of two in range, negative tolerance); the previous mesh stays.
    [[nodiscard]] Result<void> build(const scene::DepthFrameView &depth,
                                     const MeshOptions &options);

    /// \return the triangle list: 3 indices per triangle into the W×H vertex grid (row-major).
    /// Empty in MeshMode::Blocks (see drawnIndices()).
    [[nodiscard]] const std::vector<std::uint32_t> &indices() const noexcept { return indices_; }
    /// \brief The triangles drawn into \a out: indices(), or in MeshMode::Blocks the tiles at their
    /// steps with the border vertices snapped as the renderer's vertex shader does (collapsed
    /// triangles left out). For tests and error measures: O(triangles), may allocate.
    void drawnIndices(std::vector<std::uint32_t> &out) const;
    /// \return true when the last build was MeshMode::Blocks (tileSteps() says what to draw).
    [[nodiscard]] bool blockSteps() const noexcept { return blocksMode_; }
    /// \return MeshMode::Blocks: log2 of each tile's step, row-major over tilesX()×tilesY().
    [[nodiscard]] const std::vector<std::uint8_t> &tileLevels() const noexcept
    {
        return tileLevel_;
    }
    /// \return the step chosen for each tile, row-major over tilesX()×tilesY() (Quadtree: the step
    /// of the tile's finest leaf block).
    [[nodiscard]] const std::vector<std::uint16_t> &tileSteps() const noexcept { return steps_; }
    [[nodiscard]] int tilesX() const noexcept { return tilesX_; }
    [[nodiscard]] int tilesY() const noexcept { return tilesY_; }
    [[nodiscard]] int columns() const noexcept { return width_; } ///< W of the last build
    [[nodiscard]] int rows() const noexcept { return height_; }   ///< H of the last build
    [[nodiscard]] const MeshStats &stats() const noexcept { return stats_; }

private:
    double tileError(const scene::DepthFrameView &depth, int tx, int ty, int step, double limit,
                     double &mean) const noexcept;
    void emitTile(int tx, int ty, std::vector<std::uint32_t> &out) const;
    template <class T>
    void chooseBlockSteps(const scene::DepthFrameView &depth, const MeshOptions &options);
    /// Blocks: each tile's mean and largest probe error at steps 2^1 .. 2^(levels-1).
    template <class T>
    void measureBlockProbes(const scene::DepthFrameView &depth, int levels) noexcept;
    /// Blocks: the greedy refinement from every tile at 2^top against the budgets.
    void refineBlockSteps(const MeshOptions &options, int top, double samples, double errSum,
                          std::size_t leaves);
    template <class T>
    void buildQuadtree(const scene::DepthFrameView &depth, const MeshOptions &options);
    template <class T>
    void splitBlock(const scene::DepthFrameView &depth, const MeshOptions &options, int c0, int r0,
                    int size, int &finest);
    template <class T>
    void buildQuadtreeBudget(const scene::DepthFrameView &depth, const MeshOptions &options);
    /// The greedy refinement of buildQuadtreeBudget() (adaptive_mesh_quadtree.cpp).
    template <class T> struct BudgetRefinement;
    /// Sorts blocks_ into emission order: tile by tile, inside a tile by position.
    void orderBlocks();
    /// Marks each cell with its block's size and each tile with its finest step (and the stats).
    void markBlocks();
    void emitBlock(int c0, int r0, int size);

    /// A quadtree leaf: top-left cell and log2 of its size.
    struct Block {
        int c0;
        int r0;
        int log2Size;
    };

    std::vector<std::uint32_t> indices_;
    std::vector<std::uint16_t> steps_;
    std::vector<Block> blocks_;           ///< Quadtree leaves in emission order.
    std::vector<std::uint8_t> cellBlock_; ///< Per cell (W−1 × H−1): log2 size of its leaf block.
    std::vector<std::uint32_t> polygon_;  ///< Scratch: one block's boundary vertices.
    /// Scratch of the budgeted quadtree: queued blocks (priority, corner, log2 size, error).
    struct QueuedBlock {
        float priority; ///< Error removed per added triangle (an upper bound until looked).
        int c0, r0, log2Size;
        float sum;      ///< Its own error sum, levels.
        int count;      ///< Its samples.
        bool looked;    ///< child[] measured.
        struct {
            float sum, max;
            int count;
        } child[4];
    };
    /// A heap entry: a queued block's priority and its slot in nodes_.
    struct HeapEntry {
        float priority;
        std::uint32_t node;
    };
    std::vector<QueuedBlock> nodes_;
    std::vector<HeapEntry> heap_;
    std::vector<std::uint64_t> sortKeys_; ///< Scratch: the emission-order keys of the leaves.
    std::vector<int> finestScratch_;
    std::vector<float> probeError_;       ///< Scratch of Blocks: per tile and step, mean and max.
    std::vector<std::uint8_t> tileLevel_; ///< Blocks: log2 step per tile.
    std::vector<float> jump_;             ///< Scratch of Blocks: largest neighbour jump per tile.
    std::vector<std::uint16_t> jumpRow_;  ///< Scratch of Blocks: one row's jumps (8- or 16-bit).
    MeshStats stats_{};
    bool blocksMode_ = false;
    int width_ = 0;
    int height_ = 0;
    int tile_ = 16;
    int tilesX_ = 0;
    int tilesY_ = 0;
};

/// \brief The tile size of MeshMode::Blocks for a \a width × \a height depth frame: the smallest
/// power of two ≥ 8 that makes at most 8192 tiles (720×486: 8, 1920×1080: 16, 3840×2160: 32), so
/// that the per-frame work and the draw runs stay bounded by the tiles while small frames get fine
/// tiles (fewer triangles for the same error). Pure.
inline int blockTileFor(int width, int height) noexcept
{
    int t = 8;
    while (t < 256 &&
           static_cast<long long>((width - 1 + t - 1) / t) * ((height - 1 + t - 1) / t) > 8192)
        t *= 2;
    return t;
}

/// \brief Measures \a indices (a triangle list over the W×H grid of \a depth) against the samples:
/// each sample's value on the covering triangle (linear interpolation, docs/architecture.md §3)
/// minus its own. Reentrant; allocates a W×H scratch plane.
MeshError measureMeshError(const scene::DepthFrameView &depth,
                           const std::vector<std::uint32_t> &indices);

} // namespace depthtouch::render
