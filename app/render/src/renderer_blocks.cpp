#include <GLES3/gl3.h>
#include <EGL/egl.h>

#include <cstdint>
#include <array>
#include <cstring>
#include <vector>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/gl_program.h"
#include "renderer_gl.h"

DT_LOG_CATEGORY(Render)

// MeshMode::Blocks in StereoRenderer: the static buffer of every tile at every step (made once per
// depth frame size), the frame's tile steps and runs, and the draw of the surface's triangles.

namespace depthtouch::render {

namespace {

/// The static grid slot holding step 1 of a \a w × \a h frame in tiles of \a tile cells (a GPU's
/// full-resolution mesh), or -1.
template <std::size_t N>
int step1GridOf(const std::array<gl::StaticGrid, N> &grids, int w, int h, int tile)
{
    MeshOptions m;
    m.mode = MeshMode::Fixed;
    m.fixedStep = 1;
    m.tileSize = tile;
    for (std::size_t i = 0; i < grids.size(); ++i)
        if (grids[i].holds(w, h, m))
            return static_cast<int>(i);
    return -1;
}

} // namespace

void StereoRenderer::uploadBlockSteps()
{
    Gl &g = *gl_;
    const int levelCount = [&] {
        int l = 0;
        while ((2 << l) <= options_.mesh.maxStep)
            ++l;
        return l + 1;
    }();
    const auto holds = [&](const gl::BlockBuffer &b) {
        if (!b.ranges.holds(mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount))
            return false;
        // Step 1 drawn from a static grid that is no longer the one it was made with: remade.
        if (!b.ranges.step1External)
            return true;
        const auto &grid = g.grids[static_cast<std::size_t>(b.step1Grid)];
        return grid.made == b.step1Made &&
               step1GridOf(g.grids, b.ranges.width, b.ranges.height, b.ranges.tile) == b.step1Grid;
    };
    std::size_t slot = holds(g.blocks[0])                           ? 0
                       : holds(g.blocks[1])                         ? 1
                       : g.blocks[0].lastUse <= g.blocks[1].lastUse ? 0
                                                                    : 1;
    gl::BlockBuffer &b = g.blocks[slot];
    b.lastUse = ++g.gridUses;
    g.blockSlot = slot;
    if (!holds(b))
        makeBlockBuffer(b, levelCount);
    const std::vector<std::uint8_t> &level = mesh_.tileLevels();
    gl::uploadRows(b.levels, level.data(), static_cast<std::size_t>(b.ranges.tilesX),
                   b.ranges.tilesX, b.ranges.tilesY, GL_RED_INTEGER, GL_UNSIGNED_BYTE, 1);
    const auto offsetsOf = [](const std::vector<std::uint32_t> &first, std::size_t runs,
                              std::vector<const void *> &offsets) {
        for (std::size_t i = 0; i < runs; ++i)
            offsets[i] = reinterpret_cast<const void *>(static_cast<std::uintptr_t>(first[i]) *
                                                        sizeof(std::uint32_t));
    };
    if (b.ranges.step1External) {
        b.runs1 = b.ranges.runs(level.data(), b.first1, b.count1, gl::BlockRanges::Part::Step1);
        offsetsOf(b.first1, b.runs1, b.offsets1);
        b.runs = b.ranges.runs(level.data(), b.first, b.count, gl::BlockRanges::Part::Coarser);
        // The grid holding step 1 stays while it is drawn from.
        g.grids[static_cast<std::size_t>(b.step1Grid)].lastUse = b.lastUse;
    } else {
        b.runs1 = 0;
        b.runs = b.ranges.runs(level.data(), b.first, b.count);
    }
    offsetsOf(b.first, b.runs, b.offsets);
    g.blockDraw = true;
    g.tileShift = 0;
    while ((1 << g.tileShift) < options_.mesh.tileSize)
        ++g.tileShift;
    g.drawBuffer = b.buffer;
}

void StereoRenderer::makeBlockBuffer(gl::BlockBuffer &b, int levelCount)
{
    // Made once per depth frame size: every tile at every step, then the CPU copy freed. Step 1
    // comes from the full-resolution static grid when the renderer holds one of this size and
    // tile size (a GPU's, before the level of detail took over): the same triangles in the same
    // order, so the buffer holds only the coarser steps (a quarter of the indices).
    Gl &g = *gl_;
    const platform::TimePoint t0 = clock_.now();
    b.step1Grid = step1GridOf(g.grids, mesh_.columns(), mesh_.rows(), options_.mesh.tileSize);
    const bool external = b.step1Grid >= 0;
    b.step1Made = external ? g.grids[static_cast<std::size_t>(b.step1Grid)].made : 0;
    b.ranges.build(mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount, b.scratch,
                   external);
    if (b.buffer == 0)
        glGenBuffers(1, &b.buffer);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(b.scratch.size() * sizeof(std::uint32_t)),
                 b.scratch.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    DT_LOG(Render, Info,
           "Blocks index buffer for %dx%d depth (tile %d, %d steps%s): %.1f MB made and "
           "uploaded in %.1f ms",
           mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount,
           external ? ", step 1 from the full-resolution grid" : "",
           static_cast<double>(b.scratch.size() * sizeof(std::uint32_t)) / 1e6,
           platform::toSeconds(clock_.now() - t0) * 1e3);
    b.scratch.clear();
    b.scratch.shrink_to_fit();
    const auto tiles = static_cast<std::size_t>(b.ranges.tilesX * b.ranges.tilesY);
    b.first.assign(tiles, 0);
    b.count.assign(tiles, 0);
    b.offsets.assign(tiles, nullptr);
    b.first1.assign(tiles, 0);
    b.count1.assign(tiles, 0);
    b.offsets1.assign(tiles, nullptr);
    b.levels.ensure(b.ranges.tilesX, b.ranges.tilesY, GL_R8UI, GL_NEAREST);
    if (g.multiDraw == nullptr && gl::hasExtension("GL_EXT_multi_draw_arrays"))
        g.multiDraw =
            reinterpret_cast<decltype(g.multiDraw)>(eglGetProcAddress("glMultiDrawElementsEXT"));
}

void StereoRenderer::Gl::drawTriangles(const gl::SurfaceProgram &p)
{
    glUniform1i(p.tileShift, blockDraw ? tileShift : 0);
    if (!blockDraw) {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, drawBuffer);
        glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
        return;
    }
    const gl::BlockBuffer &b = blocks[blockSlot];
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_2D, b.levels.name);
    glActiveTexture(GL_TEXTURE0);
    const auto drawRuns = [this](GLuint buffer, const std::vector<std::int32_t> &count,
                                 const std::vector<const void *> &offsets, std::size_t runs) {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffer);
        const auto n = static_cast<GLsizei>(runs);
        if (multiDraw != nullptr) {
            multiDraw(GL_TRIANGLES, count.data(), GL_UNSIGNED_INT, offsets.data(), n);
            return;
        }
        for (GLsizei i = 0; i < n; ++i)
            glDrawElements(GL_TRIANGLES, count[static_cast<std::size_t>(i)], GL_UNSIGNED_INT,
                           offsets[static_cast<std::size_t>(i)]);
    };
    if (b.runs1 > 0)
        drawRuns(grids[static_cast<std::size_t>(b.step1Grid)].buffer, b.count1, b.offsets1,
                 b.runs1);
    drawRuns(b.buffer, b.count, b.offsets, b.runs);
}

} // namespace depthtouch::render
