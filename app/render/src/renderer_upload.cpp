#include <GLES3/gl3.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/renderer.h"
#include "renderer_gl.h"

DT_LOG_CATEGORY(Render)

// StereoRenderer's uploads: the depth frame (mesh, texture, index buffer) and the colour frame
// (Y'CbCr planes, or RGBA converted on the CPU), with their stage times.

namespace depthtouch::render {

using gl::uploadRows;

double StereoRenderer::stageEnd(platform::TimePoint start) const noexcept
{
    if (stageTiming_ == StageTiming::Finished)
        glFinish();
    return platform::toSeconds(clock_.now() - start) * 1e3;
}

Result<void> FramePrep::build(const scene::DepthFrameView &depth, const hal::ImageView *color,
                              const ColorSpec &spec, const MeshOptions &options)
{
    built_ = false;
    hasRgba = false;
    rgba = nullptr;
    if (color != nullptr) {
        if (color->empty() || color->width <= 0 || color->height <= 0)
            return unexpected(Errc::InvalidArgument, "colour frame is empty");
        if (color->format != hal::PixelFormat::Yuv420p && color->format != hal::PixelFormat::Gray8)
            return unexpected(Errc::NotSupported, "colour frames must be yuv420p or gray8");
    }
    // A fixed step draws the renderer's static grid: nothing to make per frame.
    if (options.mode == MeshMode::Fixed) {
        if (auto v = depth.validate(); !v)
            return v;
    } else if (auto r = mesh.build(depth, options); !r) {
        return r;
    }
    meshOptions = options;
    depthData = depth.data;
    if (color != nullptr) {
        rgba = &converter_.convert(*color, spec);
        colorWidth = color->width;
        colorHeight = color->height;
        hasRgba = true;
    }
    built_ = true;
    return ok();
}

Result<void> StereoRenderer::setDepth(const scene::DepthFrameView &depth)
{
    const platform::TimePoint t = clock_.now();
    if (options_.mesh.mode == MeshMode::Fixed)
        return setStaticDepth(depth, t);
    if (auto r = mesh_.build(depth, options_.mesh); !r)
        return r;
    return uploadDepth(depth, t, -1);
}

void StereoRenderer::finish() const noexcept
{
    glFinish();
}

Result<void> StereoRenderer::setDepth(const scene::DepthFrameView &depth, FramePrep &prep)
{
    if (options_.mesh.mode == MeshMode::Fixed)
        return setStaticDepth(depth, clock_.now());
    // A mesh made under another block budget is taken: the budget follows the frame times and may
    // lag a frame behind (LodController).
    MeshOptions made = prep.meshOptions;
    made.maxBlocks = options_.mesh.maxBlocks;
    if (!prep.built() || prep.depthData != depth.data || !(made == options_.mesh))
        return setDepth(depth);
    const platform::TimePoint t = clock_.now();
    std::swap(mesh_, prep.mesh);
    return uploadDepth(depth, t, -1);
}

Result<void> StereoRenderer::setStaticDepth(const scene::DepthFrameView &depth,
                                            platform::TimePoint start)
{
    // The grid of this size and step is made and uploaded once (its slot kept while frames of
    // that size and step come); a frame only refreshes the depth texture.
    if (auto v = depth.validate(); !v)
        return v;
    Gl &g = *gl_;
    const MeshOptions &m = options_.mesh;
    std::size_t slot = 0;
    for (std::size_t i = 0; i < g.grids.size(); ++i) {
        if (g.grids[i].holds(depth.width, depth.height, m)) {
            slot = i;
            break;
        }
        if (g.grids[i].lastUse < g.grids[slot].lastUse)
            slot = i; // else the least recently used one is replaced
    }
    gl::StaticGrid &grid = g.grids[slot];
    if (!grid.holds(depth.width, depth.height, m)) {
        const platform::TimePoint t0 = clock_.now();
        if (auto r = grid.mesh.build(depth, m); !r)
            return r;
        if (grid.buffer == 0)
            glGenBuffers(1, &grid.buffer);
        const auto &idx = grid.mesh.indices();
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, grid.buffer);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(),
                     GL_STATIC_DRAW);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        grid.count = static_cast<GLsizei>(idx.size());
        grid.width = depth.width;
        grid.height = depth.height;
        grid.step = m.fixedStep;
        grid.tileSize = m.tileSize;
        grid.made = ++g.gridsMade;
        DT_LOG(Render, Info,
               "Static grid for %dx%d depth at step %d: %.1f MB made and uploaded in %.1f ms",
               depth.width, depth.height, m.fixedStep,
               static_cast<double>(idx.size() * sizeof(std::uint32_t)) / 1e6,
               platform::toSeconds(clock_.now() - t0) * 1e3);
    }
    grid.lastUse = ++g.gridUses;
    return uploadDepth(depth, start, static_cast<int>(slot));
}

Result<void> StereoRenderer::uploadDepth(const scene::DepthFrameView &depth,
                                         platform::TimePoint start, int gridSlot)
{
    platform::TimePoint t = start;
    // The scene layer validates the frame and gives the mapping (the haptic renderer's, to the
    // bit).
    auto mapping = SurfaceMapping::of(options_.box, depth);
    if (!mapping)
        return unexpected(mapping.error());
    mapping_ = *mapping;
    depthFormat_ = depth.format;
    holeBelow_ = depth.holeBelow;
    if (holeBelow_ > 0 && gl_->surface[1][0][0][0].program == 0)
        DT_TRY(gl_->buildSurfacePrograms(true));
    stageTimes_.mesh = stageEnd(t);

    t = clock_.now();
    Gl &g = *gl_;
    const bool d16 = depth.format == scene::SampleFormat::Gray16;
    g.depth.ensure(depth.width, depth.height, d16 ? GL_R16UI : GL_R8, GL_NEAREST);
    uploadRows(g.depth, depth.data, depth.strideBytes, depth.width, depth.height,
               d16 ? GL_RED_INTEGER : GL_RED, d16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE,
               d16 ? 2 : 1);
    stageTimes_.depthUpload = stageEnd(t);

    t = clock_.now();
    g.blockDraw = false;
    if (gridSlot >= 0) {
        const gl::StaticGrid &grid = g.grids[static_cast<std::size_t>(gridSlot)];
        g.drawBuffer = grid.buffer;
        g.indexCount = grid.count;
        drawnMesh_ = &grid.mesh;
    } else if (mesh_.blockSteps()) {
        uploadBlockSteps();
        drawnMesh_ = &mesh_;
    } else {
        uploadIndices(mesh_.indices());
        drawnMesh_ = &mesh_;
    }
    haveDepth_ = true;
    stageTimes_.indexUpload = stageEnd(t);
    return ok();
}

void StereoRenderer::uploadIndices(const std::vector<std::uint32_t> &idx)
{
    Gl &g = *gl_;
    gl::DynamicIndices &d = g.dynamic;
    const auto k = static_cast<std::size_t>(d.next);
    d.next = 1 - d.next;
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d.buffer[k]);
    const auto bytes = [](std::size_t n) {
        return static_cast<GLsizeiptr>(n * sizeof(std::uint32_t));
    };
    if (idx.size() > d.capacity[k]) {
        // Grown with headroom, so a mesh that varies a little from frame to frame does not
        // reallocate again.
        d.capacity[k] = idx.size() + idx.size() / 4;
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, bytes(d.capacity[k]), nullptr, GL_DYNAMIC_DRAW);
    }
    if (!idx.empty())
        glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, bytes(idx.size()), idx.data());
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    g.drawBuffer = d.buffer[k];
    g.indexCount = static_cast<GLsizei>(idx.size());
}

Result<void> StereoRenderer::setColor(const hal::ImageView &image, const ColorSpec &spec)
{
    if (image.empty() || image.width <= 0 || image.height <= 0)
        return unexpected(Errc::InvalidArgument, "colour frame is empty");
    if (image.format != hal::PixelFormat::Yuv420p && image.format != hal::PixelFormat::Gray8)
        return unexpected(Errc::NotSupported, "colour frames must be yuv420p or gray8");
    const platform::TimePoint t = clock_.now();
    Gl &g = *gl_;
    const bool onCpu = options_.colorConversion == ColorConversion::Cpu ||
                       (options_.colorConversion == ColorConversion::Auto && softwareRasterizer_);
    const bool nearest = options_.colorFilter == ColorFilter::Nearest ||
                         (options_.colorFilter == ColorFilter::Auto && softwareRasterizer_);
    const GLint filter = nearest ? GL_NEAREST : GL_LINEAR;
    if (onCpu) {
        uploadRgba(g.converter.convert(image, spec).data(), image.width, image.height);
    } else if (image.format == hal::PixelFormat::Yuv420p) {
        const int cw = (image.width + 1) / 2;
        const int ch = (image.height + 1) / 2;
        g.y.ensure(image.width, image.height, GL_R8, filter);
        g.u.ensure(cw, ch, GL_R8, filter);
        g.v.ensure(cw, ch, GL_R8, filter);
        uploadRows(g.y, image.planes[0].data, static_cast<std::size_t>(image.planes[0].strideBytes),
                   image.width, image.height, GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.u, image.planes[1].data, static_cast<std::size_t>(image.planes[1].strideBytes),
                   cw, ch, GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.v, image.planes[2].data, static_cast<std::size_t>(image.planes[2].strideBytes),
                   cw, ch, GL_RED, GL_UNSIGNED_BYTE, 1);
    } else {
        const std::uint8_t neutral = 128;
        g.y.ensure(image.width, image.height, GL_R8, filter);
        g.u.ensure(1, 1, GL_R8, filter);
        g.v.ensure(1, 1, GL_R8, filter);
        uploadRows(g.y, image.planes[0].data, static_cast<std::size_t>(image.planes[0].strideBytes),
                   image.width, image.height, GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.u, &neutral, 1, 1, 1, GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.v, &neutral, 1, 1, 1, GL_RED, GL_UNSIGNED_BYTE, 1);
    }
    colorOnCpu_ = onCpu;
    colorFromDmaBuf_ = false;
    colorSpec_ = spec;
    stageTimes_.colorUpload = stageEnd(t);
    return ok();
}

void StereoRenderer::uploadRgba(const std::uint32_t *rgba, int width, int height)
{
    const bool nearest = options_.colorFilter == ColorFilter::Nearest ||
                         (options_.colorFilter == ColorFilter::Auto && softwareRasterizer_);
    Gl &g = *gl_;
    g.rgb.ensure(width, height, GL_RGBA8, nearest ? GL_NEAREST : GL_LINEAR);
    uploadRows(g.rgb, reinterpret_cast<const std::uint8_t *>(rgba),
               static_cast<std::size_t>(width) * 4, width, height, GL_RGBA, GL_UNSIGNED_BYTE, 4);
}

Result<void> StereoRenderer::setColor(const FramePrep &prep)
{
    if (!prep.built() || !prep.hasRgba || prep.rgba == nullptr)
        return unexpected(Errc::InvalidArgument, "the prepared frame holds no converted colour");
    const platform::TimePoint t = clock_.now();
    uploadRgba(prep.rgba->data(), prep.colorWidth, prep.colorHeight);
    colorOnCpu_ = true;
    stageTimes_.colorUpload = stageEnd(t);
    return ok();
}

} // namespace depthtouch::render
