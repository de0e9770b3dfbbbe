#pragma once
/// \file
/// \brief The static index buffer of MeshMode::Blocks, private to dt_render: every tile's
/// triangles at every step, unstitched, made once per depth frame size; and the runs of it that a
/// frame's tile steps select.
///
/// Layout: step-major (step 1, 2, 4 … maxStep), tiles row-major inside a step, each tile's cells
/// row-major at that step, two triangles a cell split top-left → bottom-right (the order and
/// orientation of AdaptiveMesh's tiles, docs/architecture.md §3). Consecutive tiles at the same
/// step are consecutive in the buffer, so a row of them is one draw. Indices are vertex numbers of
/// the W×H grid (vertex k = sample (k mod W, k div W)); the renderer's vertex shader does the
/// stitching at tile borders.
/// Size: about 4/3 of the full-resolution list (8.4 MB at 720×486 → 11.2 MB; 3840×2160: 265 MB),
/// or 1/3 of it without step 1 (`step1External`): step 1 is then the step-1 static grid of the same
/// size and tile size (AdaptiveMesh's tiles at step 1: the same triangles in the same order), and
/// its ranges are offsets into that grid's buffer.
/// Thread-safety: plain data; build() allocates, runs() does not once its vectors have grown.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace depthtouch::render::gl {

/// \brief The ranges of the static buffer of one depth frame size, tile size and step count.
struct BlockRanges {
    int width = 0; ///< Depth frame size, samples (0: not built).
    int height = 0;
    int tile = 0;   ///< Cells a tile side.
    int levels = 0; ///< Steps 1 … 2^(levels−1).
    int tilesX = 0;
    int tilesY = 0;
    bool step1External = false; ///< Step 1 is not in the buffer (ranges into the step-1 grid).
    /// With step1External, the indices of the step-1 grid: start[] of the coarser steps is their
    /// offset in the buffer plus this (runs() gives buffer offsets); else 0.
    std::uint32_t coarseBase = 0;
    /// The range of tile t at step 2^l is [start[l·tiles + t], start[l·tiles + t + 1]), indices
    /// (levels·tiles + 1 entries): offsets in the buffer, or with step1External, step 1's in the
    /// step-1 grid and the coarser steps' in the buffer plus coarseBase.
    std::vector<std::uint32_t> start;
    /// Which tiles runs() takes: all of them, those at step 1, or those at the coarser steps.
    enum class Part : std::uint8_t { All, Step1, Coarser };

    [[nodiscard]] bool holds(int w, int h, int tileSize, int levelCount) const noexcept
    {
        return width == w && height == h && tile == tileSize && levels == levelCount;
    }
    /// \brief Lays out the buffer for a \a w × \a h grid, tiles of \a tileSize cells and
    /// \a levelCount steps into \a indices (replaced) and start; without step 1 in \a indices
    /// when \a external1 (step1External).
    /// \pre w, h ≥ 2, tileSize a power of two, levelCount ≥ 1 with 2^(levelCount−1) ≤ tileSize,
    /// the whole buffer under 2^32 indices.
    void build(int w, int h, int tileSize, int levelCount, std::vector<std::uint32_t> &indices,
               bool external1 = false);
    /// \brief The runs that draw the tiles of \a part at steps 2^\a level[t]: consecutive ranges
    /// merged. Fills \a first (offsets, indices) and \a count; \return the runs.
    /// \pre levels[t] < levels; first and count hold a run per tile.
    std::size_t runs(const std::uint8_t *level, std::vector<std::uint32_t> &first,
                     std::vector<std::int32_t> &count, Part part = Part::All) const;
};

} // namespace depthtouch::render::gl
