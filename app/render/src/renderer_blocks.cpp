#include <GLES3/gl3.h>
#include <EGL/egl.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/renderer.h"
#include "gl_program.h"
#include "renderer_gl.h"

DT_LOG_CATEGORY(Render)

// MeshMode::Blocks in StereoRenderer: the static buffer of every tile at every step (made once per
// depth frame size), the frame's tile steps and runs, and the draw of the surface's triangles.

namespace depthtouch::render {

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
        return b.ranges.holds(mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount);
    };
    std::size_t slot = holds(g.blocks[0])                           ? 0
                       : holds(g.blocks[1])                         ? 1
                       : g.blocks[0].lastUse <= g.blocks[1].lastUse ? 0
                                                                    : 1;
    gl::BlockBuffer &b = g.blocks[slot];
    b.lastUse = ++g.gridUses;
    g.blockSlot = slot;
    if (!holds(b)) {
        // Made once per depth frame size: every tile at every step, then the CPU copy freed.
        const platform::TimePoint t0 = clock_.now();
        b.ranges.build(mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount,
                       b.scratch);
        if (b.buffer == 0)
            glGenBuffers(1, &b.buffer);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffer);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(b.scratch.size() * sizeof(std::uint32_t)),
                     b.scratch.data(), GL_STATIC_DRAW);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        DT_LOG(Render, Info,
               "Blocks index buffer for %dx%d depth (tile %d, %d steps): %.1f MB made and "
               "uploaded in %.1f ms",
               mesh_.columns(), mesh_.rows(), options_.mesh.tileSize, levelCount,
               static_cast<double>(b.scratch.size() * sizeof(std::uint32_t)) / 1e6,
               platform::toSeconds(clock_.now() - t0) * 1e3);
        b.scratch.clear();
        b.scratch.shrink_to_fit();
        const auto tiles = static_cast<std::size_t>(b.ranges.tilesX * b.ranges.tilesY);
        b.first.assign(tiles, 0);
        b.count.assign(tiles, 0);
        b.offsets.assign(tiles, nullptr);
        b.levels.ensure(b.ranges.tilesX, b.ranges.tilesY, GL_R8UI, GL_NEAREST);
        if (g.multiDraw == nullptr && gl::hasExtension("GL_EXT_multi_draw_arrays"))
            g.multiDraw = reinterpret_cast<decltype(g.multiDraw)>(
                eglGetProcAddress("glMultiDrawElementsEXT"));
    }
    const std::vector<std::uint8_t> &level = mesh_.tileLevels();
    gl::uploadRows(b.levels, level.data(), static_cast<std::size_t>(b.ranges.tilesX),
                   b.ranges.tilesX, b.ranges.tilesY, GL_RED_INTEGER, GL_UNSIGNED_BYTE, 1);
    b.runs = b.ranges.runs(level.data(), b.first, b.count);
    for (std::size_t i = 0; i < b.runs; ++i)
        b.offsets[i] = reinterpret_cast<const void *>(static_cast<std::uintptr_t>(b.first[i]) *
                                                      sizeof(std::uint32_t));
    g.blockDraw = true;
    g.tileShift = 0;
    while ((1 << g.tileShift) < options_.mesh.tileSize)
        ++g.tileShift;
    g.drawBuffer = b.buffer;
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
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.buffer);
    const auto n = static_cast<GLsizei>(b.runs);
    if (multiDraw != nullptr) {
        multiDraw(GL_TRIANGLES, b.count.data(), GL_UNSIGNED_INT, b.offsets.data(), n);
        return;
    }
    for (GLsizei i = 0; i < n; ++i)
        glDrawElements(GL_TRIANGLES, b.count[static_cast<std::size_t>(i)], GL_UNSIGNED_INT,
                       b.offsets[static_cast<std::size_t>(i)]);
}

} // namespace depthtouch::render
