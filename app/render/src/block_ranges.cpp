#include "block_ranges.h"

#include <algorithm>

#include "mesh_cells.h"

// The static index buffer of MeshMode::Blocks and the runs a frame draws of it.

namespace depthtouch::render::gl {

void BlockRanges::build(int w, int h, int tileSize, int levelCount,
                        std::vector<std::uint32_t> &indices, bool external1)
{
    width = w;
    height = h;
    tile = tileSize;
    levels = levelCount;
    step1External = external1;
    const int cellsX = w - 1;
    const int cellsY = h - 1;
    tilesX = (cellsX + tile - 1) / tile;
    tilesY = (cellsY + tile - 1) / tile;
    const std::size_t tiles = static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY);
    start.assign(static_cast<std::size_t>(levels) * tiles + 1, 0);
    std::size_t total = 0;
    for (int l = external1 ? 1 : 0; l < levels; ++l) {
        const int s = 1 << l;
        for (int ty = 0; ty < tilesY; ++ty)
            for (int tx = 0; tx < tilesX; ++tx) {
                const int cw = std::min(tile, cellsX - tx * tile);
                const int ch = std::min(tile, cellsY - ty * tile);
                total += 6 * static_cast<std::size_t>((cw + s - 1) / s) *
                         static_cast<std::size_t>((ch + s - 1) / s);
            }
    }
    indices.clear();
    indices.shrink_to_fit();
    indices.reserve(total);
    const auto uw = static_cast<std::uint32_t>(w);
    const auto vertex = [uw](int c, int r) {
        return static_cast<std::uint32_t>(r) * uw + static_cast<std::uint32_t>(c);
    };
    std::size_t k = 0;
    if (external1) {
        // Step 1's ranges in the step-1 grid: its tiles' cells in the same order.
        std::uint32_t at = 0;
        for (int ty = 0; ty < tilesY; ++ty)
            for (int tx = 0; tx < tilesX; ++tx) {
                start[k++] = at;
                at += static_cast<std::uint32_t>(6 * std::min(tile, cellsX - tx * tile) *
                                                 std::min(tile, cellsY - ty * tile));
            }
        coarseBase = at;
    } else {
        coarseBase = 0;
    }
    for (int l = external1 ? 1 : 0; l < levels; ++l) {
        const int s = 1 << l;
        for (int ty = 0; ty < tilesY; ++ty)
            for (int tx = 0; tx < tilesX; ++tx) {
                start[k++] = coarseBase + static_cast<std::uint32_t>(indices.size());
                const int c0 = tx * tile;
                const int r0 = ty * tile;
                const int c1 = std::min(c0 + tile, cellsX);
                const int r1 = std::min(r0 + tile, cellsY);
                mesh::forEachCell(
                    c0, r0, c1, r1, s, vertex,
                    [&indices](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
                        indices.insert(indices.end(), {a, b, c, a, c, d});
                    });
            }
    }
    start[k] = coarseBase + static_cast<std::uint32_t>(indices.size());
}

std::size_t BlockRanges::runs(const std::uint8_t *level, std::vector<std::uint32_t> &first,
                              std::vector<std::int32_t> &count, Part part) const
{
    const std::size_t tiles = static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY);
    if (first.size() < tiles) {
        first.resize(tiles);
        count.resize(tiles);
    }
    std::size_t n = 0;
    std::uint32_t end = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
        if ((part == Part::Step1 && level[t] != 0) || (part == Part::Coarser && level[t] == 0))
            continue;
        const std::size_t i = static_cast<std::size_t>(level[t]) * tiles + t;
        const std::uint32_t a = start[i];
        const std::uint32_t b = start[i + 1];
        if (n > 0 && a == end) {
            count[n - 1] += static_cast<std::int32_t>(b - a);
        } else {
            first[n] = level[t] == 0 ? a : a - coarseBase;
            count[n] = static_cast<std::int32_t>(b - a);
            ++n;
        }
        end = b;
    }
    return n;
}

} // namespace depthtouch::render::gl
