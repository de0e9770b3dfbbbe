#pragma once
/// \file
/// \brief The GL objects of StereoRenderer, private to dt_render: textures, the surface program
/// variants, the avatar and OSD programs and buffers. The renderer's members live in three files:
/// renderer.cpp (shaders and creation), renderer_upload.cpp (depth and colour uploads) and
/// renderer_draw.cpp (the surface, avatar and OSD passes).
/// Needs a current GLES context. Thread-safety: the GL thread only.

#include <GLES3/gl3.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "depthtouch/render/adaptive_mesh.h"
#include "depthtouch/render/color.h"
#include "depthtouch/render/gl_program.h"
#include "depthtouch/render/renderer.h"
#include "block_ranges.h"

namespace depthtouch::render {

namespace gl {

/// A texture with immutable storage, reallocated only when its size or format changes.
struct Texture {
    GLuint name = 0;
    int width = 0;
    int height = 0;
    GLenum internalFormat = 0;
    GLint filter = 0;

    void ensure(int w, int h, GLenum format, GLint minMag)
    {
        if (name != 0 && w == width && h == height && format == internalFormat) {
            if (minMag != filter) {
                glBindTexture(GL_TEXTURE_2D, name);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, minMag);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, minMag);
                filter = minMag;
            }
            return;
        }
        if (name != 0)
            glDeleteTextures(1, &name);
        name = createTexture2D(format, w, h, minMag);
        width = w;
        height = h;
        internalFormat = format;
        filter = minMag;
    }
    void release() noexcept
    {
        if (name != 0)
            glDeleteTextures(1, &name);
        name = 0;
        width = height = 0;
    }
};

/// Uploads \a h rows of \a rowSamples samples of \a bytesPerSample bytes, \a stride bytes apart.
void uploadRows(const Texture &tex, const std::uint8_t *data, std::size_t stride, int w, int h,
                GLenum format, GLenum type, int bytesPerSample);

/// \brief A triangle list uploaded once: the static grid of a fixed step (full resolution or a
/// decimation) for one depth frame size, drawn as is for every frame of that size. The CPU copy
/// (mesh) stays for StereoRenderer::mesh() (its stats and its indices).
struct StaticGrid {
    GLuint buffer = 0;
    GLsizei count = 0; ///< Indices in buffer.
    int width = 0;     ///< Depth frame size it was made for, samples.
    int height = 0;
    int step = 0;     ///< MeshOptions::fixedStep (0: the slot is free).
    int tileSize = 0; ///< MeshOptions::tileSize (the emission order).
    std::uint64_t lastUse = 0;
    std::uint64_t made = 0; ///< Which making of the grids this is (Gl::gridsMade when made).
    AdaptiveMesh mesh;

    [[nodiscard]] bool holds(int w, int h, const MeshOptions &m) const noexcept
    {
        return step != 0 && w == width && h == height && m.fixedStep == step &&
               m.tileSize == tileSize;
    }
};

/// \brief The index buffers of meshes made per frame (quadtree, adaptive): two, used in turn so
/// that an upload never waits for the draws of the frame before, each grown (glBufferData) only
/// when a list outgrows it and otherwise refreshed with glBufferSubData (no reallocation).
struct DynamicIndices {
    GLuint buffer[2] = {0, 0};
    std::size_t capacity[2] = {0, 0}; ///< Indices each buffer holds.
    int next = 0;                     ///< The buffer the next upload writes.
};

/// \brief MeshMode::Blocks: the static buffer of every tile at every step (BlockRanges), made and
/// uploaded at the first frame of a size; per frame the tile steps (an R8UI texture, one texel a
/// tile, that the vertex shader stitches with) and the runs drawn, in vectors grown once.
struct BlockBuffer {
    GLuint buffer = 0;
    BlockRanges ranges;
    /// With ranges.step1External: the static grid slot whose buffer holds step 1, and its making
    /// (StaticGrid::made) when this buffer was made; -1 when step 1 is in buffer.
    int step1Grid = -1;
    std::uint64_t step1Made = 0;
    std::vector<std::uint32_t> first1;  ///< The step-1 tiles' runs in the grid's buffer, indices.
    std::vector<std::int32_t> count1;   ///< Indices a step-1 run.
    std::vector<const void *> offsets1; ///< Their byte offsets.
    std::size_t runs1 = 0;              ///< Step-1 runs of the current frame (step1External).
    Texture levels;                     ///< tilesX × tilesY, R8UI: log2 step per tile.
    std::vector<std::uint32_t> first;   ///< Scratch of BlockRanges::runs(), indices.
    std::vector<std::int32_t> count;    ///< Indices a run (GLsizei).
    std::vector<const void *> offsets;  ///< The runs' byte offsets (glMultiDrawElementsEXT).
    std::size_t runs = 0;               ///< Runs of the current frame.
    std::vector<std::uint32_t> scratch; ///< The buffer's indices while it is made (then freed).
    std::uint64_t lastUse = 0;
};

/// \brief One surface program and its uniform locations.
struct SurfaceProgram {
    GLuint program = 0;
    GLint columns = -1, origin = -1, step = -1, zMap = -1, texScale = -1, viewProj = -1;
    GLint yuvToRgb = -1, yuvOffset = -1, rowParity = -1;
    GLint tileShift = -1, last = -1;
    GLint holeBelow = -1; ///< The hole variant's threshold (sample units), else -1.
};

/// What the surface fragment shader outputs.
enum SurfaceVariant : int { kPositionOut = 0, kRgbOut = 1, kYuvOut = 2 };

} // namespace gl

/// \brief Every GL object the renderer owns; released with it.
struct StereoRenderer::Gl {
    // [holes][depth16][SurfaceVariant][row parity]; the hole variants (a triangle with a hole
    // vertex discarded, docs/architecture.md §3 "Holes") are built at the first frame with holes.
    gl::SurfaceProgram surface[2][2][3][2];
    GLuint avatarProgram = 0;
    GLint avCenter = -1, avRadius = -1, avViewProj = -1, avColor = -1, avRowParity = -1;
    GLuint osdProgram = 0;
    GLint osdViewport = -1, osdColor = -1, osdTextured = -1;
    GLuint surfaceVao = 0;
    GLuint drawBuffer = 0;  ///< The index buffer the surface draws (a static grid's or dynamic).
    GLsizei indexCount = 0; ///< Indices in drawBuffer to draw.
    gl::DynamicIndices dynamic;
    /// Two sizes or tile sizes kept at once (a benchmark alternating settings), the least recently
    /// used one replaced.
    std::array<gl::BlockBuffer, 2> blocks;
    std::size_t blockSlot = 0; ///< The slot blockDraw draws.
    bool blockDraw = false;    ///< The surface draws blocks' runs (else drawBuffer, indexCount).
    int tileShift = 0;         ///< log2 tile size of blockDraw.
    /// glMultiDrawElementsEXT (GL_EXT_multi_draw_arrays) when the context has it, else null (a
    /// glDrawElements a run).
    void(GL_APIENTRY *multiDraw)(GLenum, const GLsizei *, GLenum, const void *const *,
                                 GLsizei) = nullptr;
    static constexpr std::size_t kStaticGrids = 4; ///< Fixed steps kept at once (1, 2, 4, 8).
    std::array<gl::StaticGrid, kStaticGrids> grids;
    std::uint64_t gridUses = 0;
    std::uint64_t gridsMade = 0; ///< Static grids made so far (StaticGrid::made).
    GLuint sphereVao = 0;
    GLuint sphereVbo = 0;
    GLuint sphereIbo = 0;
    GLsizei sphereIndexCount = 0;
    GLuint osdVao = 0;
    GLuint osdVbo = 0;
    gl::Texture depth;
    gl::Texture y, u, v;
    gl::Texture rgb; ///< The colour frame as RGBA8 when converted on the CPU.
    gl::Texture font;
    YuvConverter converter;
    std::vector<float> osdVertices;

    ~Gl()
    {
        for (auto &kind : surface)
            for (auto &plane : kind)
                for (auto &row : plane)
                    for (auto &p : row)
                        if (p.program != 0)
                            glDeleteProgram(p.program);
        if (avatarProgram != 0)
            glDeleteProgram(avatarProgram);
        if (osdProgram != 0)
            glDeleteProgram(osdProgram);
        const GLuint vaos[] = {surfaceVao, sphereVao, osdVao};
        glDeleteVertexArrays(3, vaos);
        const GLuint buffers[] = {dynamic.buffer[0], dynamic.buffer[1], sphereVbo, sphereIbo,
                                  osdVbo};
        glDeleteBuffers(5, buffers);
        for (const gl::StaticGrid &grid : grids)
            if (grid.buffer != 0)
                glDeleteBuffers(1, &grid.buffer);
        for (gl::BlockBuffer &b : blocks) {
            if (b.buffer != 0)
                glDeleteBuffers(1, &b.buffer);
            b.levels.release();
        }
        depth.release();
        y.release();
        u.release();
        v.release();
        rgb.release();
        font.release();
    }

    /// Builds the twelve surface programs (depth format × output × row parity), with or without
    /// \a holes (the hole test and its discard).
    Result<void> buildSurfacePrograms(bool holes);
    /// Builds the avatar and OSD programs and looks up their uniforms.
    Result<void> buildOverlayPrograms();
    /// Makes the avatar's unit UV sphere (positions are the normals) and its vertex array.
    void buildSphere();
    /// Makes the OSD glyph atlas and its stream vertex array.
    void buildOsd();
    /// Draws the surface's triangles with the bound program and vertex array: the blocks' runs
    /// (tile steps on texture unit 4) or drawBuffer.
    void drawTriangles(const gl::SurfaceProgram &p);
};

} // namespace depthtouch::render
