#pragma once
/// \file
/// \brief StereoRenderer: the graphic renderer of the 3D video player (paper §V.D): the depth frame
/// as geometry (a grid mesh displaced in the vertex shader by the depth texture), the decoded
/// colour planes as its texture (Y'CbCr → RGB in the fragment shader), drawn from two eye cameras
/// into one of the stereo output layouts, with the haptic avatar (proxy sphere, HIP marker) and a
/// small on-screen display.
///
/// Geometry: vertex (c, r) of the W×H grid is placed by SurfaceMapping, computed by the scene layer
/// from the scene box and the frame size (scene::SurfaceMapping::of, the mapping the haptic
/// renderer's HeightField uses: docs/architecture.md §3), and the cells are split along the same
/// diagonal: at mesh step 1 the drawn surface is the touched surface. A fixed step draws a static
/// grid (its index buffer made once per frame size); MeshMode::Blocks draws ranges of a static
/// buffer of every tile at every step, chosen per frame by AdaptiveMesh, the vertex shader
/// stitching tile borders; Adaptive and Quadtree upload AdaptiveMesh's list each frame
/// (adaptive_mesh.h).
///
/// Holes (docs/architecture.md §3 "Holes"): in a frame with DepthFrameView::holeBelow > 0, a
/// triangle with a vertex below it is not drawn in any mesh mode (the vertex shader flags hole
/// vertices, the fragment shader discards what a flagged vertex touches; these program variants
/// are built at the first such frame), so the clear colour (RendererOptions::background) shows
/// there. Frames without holes draw with the programs they always did, without a discard.
///
/// Textures are allocated once per frame size and format (immutable storage) and refreshed with
/// glTexSubImage2D. On a software rasterizer the colour frame is converted to R'G'B' once on the
/// CPU (ColorConversion::Auto): the surface then fetches one texture per fragment in each eye
/// instead of three planes and a matrix, which on llvmpipe costs far more than the conversion.
/// Requires a current OpenGL ES 3.0 context with vertex texture fetch.
/// Thread-safety: thread-bound (the render thread that owns the context). Not real-time safe.

#include <cstdint>
#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "depthtouch/scene/depth_frame.h"
#include "depthtouch/hal/types.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/render/adaptive_mesh.h"
#include "depthtouch/render/color.h"
#include "depthtouch/render/dmabuf_import.h"
#include "depthtouch/render/stereo.h"
#include "depthtouch/render/surface_mapping.h"

namespace depthtouch::render {

class RenderTarget;

/// \brief Renderer settings; may be changed between frames with setOptions().
struct RendererOptions {
    scene::SceneBox box{};                    ///< The scene box, m (same as the haptic renderer's).
    StereoMode mode = StereoMode::SideBySide; ///< Output layout.
    StereoParams stereo{};                    ///< Eye cameras.
    MeshOptions mesh{};                       ///< Level of detail.
    ColorConversion colorConversion =
        ColorConversion::Auto;                   ///< Where Y'CbCr becomes R'G'B' (setColor()).
    ColorFilter colorFilter = ColorFilter::Auto; ///< How the colour texture is sampled.
    glm::vec3 background{0.0f, 0.0f, 0.0f};      ///< Clear colour, linear RGB in [0, 1].
};

/// \brief The haptic avatar, scene-box frame (m).
struct AvatarState {
    bool visible = false;
    glm::dvec3 proxy{0.0};  ///< Proxy (god-object) position: where the lit sphere is drawn.
    glm::dvec3 hip{0.0};    ///< Haptic interface point: a faint marker when apart from the proxy.
    double radius = 0.0025; ///< Sphere radius, m.
    double separation = 0.0005; ///< HIP marker shown when |proxy − HIP| exceeds this, m.
};

/// \brief The on-screen display (drawn at zero parallax in each eye).
struct OsdState {
    bool visible = false;
    std::string status; ///< Player state, e.g. "PLAYING" (upper case letters, digits, . : - / %).
    bool hapticsOn = false; ///< Shows "HAPTICS ON" or "HAPTICS OFF".
    /// The haptic device answers; false shows "HAPTICS: NO DEVICE" instead of "HAPTICS ON" (lost,
    /// or not yet plugged in where the player waits for it).
    bool deviceConnected = true;
    /// The remote's input device is there, or the player has no remote; false (a remote waited
    /// for and not plugged in, or lost) adds a line "REMOTE: NO DEVICE" under the haptics line.
    bool remoteConnected = true;
    double force = 0.0;    ///< Current force magnitude, N (bar length).
    double maxForce = 8.5; ///< Full-scale force of the bar, N (> 0).
    /// The stiffness the finger feels, N/m: a line "STIFFNESS 900 N/M" under the haptics line
    /// (what the remote's CH+ and CH− change); 0 or less: no such line.
    double stiffness = 0.0;
};

/// \brief What drawSurface() writes.
enum class SurfaceOutput : std::uint8_t {
    Color,    ///< The textured surface.
    Position, ///< Scene-box position (x, y, z, 1) of the surface point under each pixel, m (float
              ///< target).
};

/// \brief Wall time of the stages of the last setDepth(), setColor() and render() calls, ms.
///
/// The time the calling thread spends in each stage. On a deferred rasterizer (Mesa llvmpipe bins
/// the triangles when they are drawn and shades them at the next flush, e.g. the glFinish of a
/// display's present()) a drawing stage holds vertex processing and binning only; with
/// StageTiming::Finished each stage ends with glFinish, so its time includes the rasterization it
/// caused (the frame as a whole is then slower: for a breakdown, not for playback).
struct StageTimes {
    double depthUpload = 0.0; ///< setDepth(): depth texture upload.
    double mesh = 0.0; ///< setDepth(): frame check, level-of-detail choice, index list (CPU).
    double indexUpload = 0.0; ///< setDepth(): index buffer upload (0 when the list was unchanged).
    double colorUpload = 0.0; ///< setColor(): plane upload and conversion.
    double clear = 0.0;       ///< render(): clearing the target.
    double eye[2] = {};       ///< render(): surface of the left and right eye (Mono: eye[0] only).
    double overlay = 0.0;     ///< render(): avatar in every eye and the on-screen display.
};

/// \brief Whether stage times include the GPU work of each stage (see StageTimes).
enum class StageTiming : std::uint8_t {
    Cpu,      ///< No extra synchronisation (default): what the calling thread spends.
    Finished, ///< glFinish after each stage: the stage's full cost, serialised.
};

/// \brief The CPU half of showing a frame: its mesh (AdaptiveMesh::build()) and, on the CPU colour
/// path, its R'G'B' conversion (YuvConverter), made ahead of time on any thread so that the render
/// thread only uploads and draws (StereoRenderer::setDepth(depth, prep), setColor(prep)). On a
/// 2-core machine with llvmpipe this overlaps the next frame's CPU work with the rasterizer threads
/// of the current one.
/// Thread-safety: an object is used by one thread at a time; objects are independent (no GL).
struct FramePrep {
    /// \brief Builds the mesh of \a depth with \a mesh and, when \a color is not null, converts
    /// it (Yuv420p or Gray8) with \a spec.
    /// \return InvalidArgument (malformed depth frame or mesh options, or an empty colour view),
    /// NotSupported (colour format); the object is then not usable (built() is false).
    [[nodiscard]] Result<void> build(const scene::DepthFrameView &depth,
                                     const hal::ImageView *color, const ColorSpec &spec,
                                     const MeshOptions &mesh);

    [[nodiscard]] bool built() const noexcept { return built_; }

    AdaptiveMesh mesh;               ///< The depth frame's mesh.
    MeshOptions meshOptions{};       ///< What it was built with.
    const void *depthData = nullptr; ///< The depth frame's first sample (identifies the frame).
    bool hasRgba = false;            ///< A colour frame was converted.
    int colorWidth = 0;              ///< Its size, pixels.
    int colorHeight = 0;
    const std::vector<std::uint32_t> *rgba = nullptr; ///< colorWidth × colorHeight RGBA8 words.

private:
    YuvConverter converter_;
    bool built_ = false;
};

namespace gl {
struct BlockBuffer; ///< MeshMode::Blocks' index buffer and runs (renderer_gl.h, private).
} // namespace gl

class StereoRenderer {
public:
    /// \brief Compiles the shaders and creates the GL objects. \pre a current GLES 3 context.
    /// \return Errc::NotSupported when a shader does not compile or link (logged with the GL info
    /// log), Errc::InvalidArgument for a non-positive box.
    static Result<std::unique_ptr<StereoRenderer>> create(const RendererOptions &options);
    ~StereoRenderer();
    StereoRenderer(const StereoRenderer &) = delete;
    StereoRenderer &operator=(const StereoRenderer &) = delete;

    /// \brief Changes the options for the next frames. Mode, cameras and background apply at the
    /// next render(); mesh and box at the next setDepth() (which fully checks the mesh options).
    /// \return Errc::InvalidArgument for a non-positive box or bad mesh options (nothing changes).
    [[nodiscard]] Result<void> setOptions(const RendererOptions &options);
    [[nodiscard]] const RendererOptions &options() const noexcept { return options_; }

    /// \brief Uploads depth frame \a depth (Gray8 → R8, Gray16 → R16UI texture) and rebuilds the
    /// mesh. The pixels are copied; \a depth need not outlive the call.
    /// \return Errc::InvalidArgument for a malformed frame (the previous frame stays).
    [[nodiscard]] Result<void> setDepth(const scene::DepthFrameView &depth);

    /// \brief Uploads a decoded colour frame: Yuv420p or Gray8 (luma only). Converted to R'G'B' on
    /// the CPU into one RGBA8 texture, or uploaded as three R8 planes that the fragment shader
    /// converts, as options().colorConversion says. Its size may differ from the depth frame's: it
    /// is stretched over the same box.
    /// \return Errc::NotSupported for other formats, Errc::InvalidArgument for an empty view.
    [[nodiscard]] Result<void> setColor(const hal::ImageView &image, const ColorSpec &spec);

    /// \brief setDepth() with the mesh made ahead in \a prep (built from this \a depth frame with
    /// options().mesh, whatever its block budget; else the mesh is built here as setDepth() does).
    /// The mesh is moved out of \a prep (it gets the previous one's buffers back). \return as
    /// setDepth().
    [[nodiscard]] Result<void> setDepth(const scene::DepthFrameView &depth, FramePrep &prep);
    /// \brief setColor() with the colour converted ahead in \a prep (its R'G'B' words are
    /// uploaded). \return InvalidArgument when \a prep holds no converted colour.
    [[nodiscard]] Result<void> setColor(const FramePrep &prep);
    /// \return whether setColor() converts colour on the CPU with the current options (then a
    /// FramePrep should convert it too).
    [[nodiscard]] bool convertsColorOnCpu() const noexcept
    {
        return options_.colorConversion == ColorConversion::Cpu ||
               (options_.colorConversion == ColorConversion::Auto && softwareRasterizer_);
    }
    /// \brief Sets the colour of a decoded frame that may carry dma-bufs (hal::Frame::dmabuf):
    /// without one, exactly setColor(\a image). With one, imported without a copy when the
    /// platform can (dmabuf_import.h); otherwise uploaded from \a image's CPU planes, or from the
    /// dma-bufs mapped read-only when \a image has none (each fallback logged once). The fds are
    /// borrowed: the caller keeps the frame (its FrameRef) until the frame has been drawn and
    /// presented, and a cached EGLImage of a buffer is reused when the decoder lends it again.
    /// \return the errors of setColor(); InvalidArgument for a malformed descriptor; NotSupported
    /// for a tiled dma-buf that could not be imported; Io when a dma-buf cannot be mapped.
    [[nodiscard]] Result<void> setColorFrame(const hal::ImageView &image,
                                             const hal::DmaBufImage &dmabuf, const ColorSpec &spec);
    /// \return how the dma-buf colour frames were taken (imported or uploaded).
    [[nodiscard]] const DmaBufStats &dmaBufStats() const noexcept { return dmaBufStats_; }

    void setAvatar(const AvatarState &avatar) noexcept { avatar_ = avatar; }
    void setOsd(const OsdState &osd) { osd_ = osd; }

    /// \brief Draws one output frame into \a target in the current mode: clear, both eyes' surface
    /// and avatar, then the on-screen display. \pre setDepth() succeeded once.
    /// \return Errc::InvalidState without a depth frame.
    [[nodiscard]] Result<void> render(const RenderTarget &target);

    /// \brief Draws only the surface from \a eye into the bound framebuffer (no clear): tests and
    /// height read-back. \pre setDepth() succeeded once.
    [[nodiscard]] Result<void> drawSurface(const EyeView &eye, SurfaceOutput output);

    /// \brief Selects what stageTimes() measures (default StageTiming::Cpu).
    void setStageTiming(StageTiming timing) noexcept { stageTiming_ = timing; }
    /// \return the stage times of the last setDepth(), setColor() and render() calls.
    [[nodiscard]] const StageTimes &stageTimes() const noexcept { return stageTimes_; }

    /// \return the mapping of the current depth frame (scene::SurfaceMapping::of its size and the
    /// scene box).
    [[nodiscard]] const SurfaceMapping &mapping() const noexcept { return mapping_; }
    /// \return the mesh drawn for the current depth frame (with a fixed step, the static grid of
    /// its size: the same object from frame to frame).
    [[nodiscard]] const AdaptiveMesh &mesh() const noexcept { return *drawnMesh_; }
    /// \return true when the context renders in software (llvmpipe, softpipe, swrast): the
    /// rasterizer then shares the CPU with everything else.
    [[nodiscard]] bool rendersInSoftware() const noexcept { return softwareRasterizer_; }
    /// \brief Waits until everything submitted is drawn (glFinish). For timing a frame's whole
    /// draw on a software rasterizer, whose present would wait for it anyway; on a GPU it would
    /// only stall the pipeline.
    void finish() const noexcept;
    /// \return true when the last colour frame was converted on the CPU (see ColorConversion).
    [[nodiscard]] bool colorConvertedOnCpu() const noexcept { return colorOnCpu_; }

private:
    struct Gl;
    explicit StereoRenderer(const RendererOptions &options);
    void drawAvatar(const EyeView &eye);
    void drawOsd(const Viewport &vp);
    /// Ends a stage: \return the milliseconds since \a start (after glFinish when Finished).
    double stageEnd(platform::TimePoint start) const noexcept;
    /// setDepth() with a fixed step: the static grid of the frame's size (made and uploaded at
    /// the first frame of that size and step), then uploadDepth().
    Result<void> setStaticDepth(const scene::DepthFrameView &depth, platform::TimePoint start);
    /// setDepth()'s upload half: the mapping and the depth texture, then the index buffer drawn:
    /// static grid \a gridSlot (Gl::grids), or mesh_ uploaded into a dynamic buffer (-1).
    Result<void> uploadDepth(const scene::DepthFrameView &depth, platform::TimePoint start,
                             int gridSlot);
    /// Uploads a per-frame triangle list into the next dynamic index buffer (no reallocation
    /// unless it outgrows it).
    void uploadIndices(const std::vector<std::uint32_t> &indices);
    /// MeshMode::Blocks: the static buffer of every tile at every step for mesh_'s size (made and
    /// uploaded at the first frame of that size), then mesh_'s tile steps and the runs to draw.
    void uploadBlockSteps();
    /// Makes and uploads the Blocks index buffer of the current mesh's size (renderer_blocks.cpp).
    void makeBlockBuffer(gl::BlockBuffer &b, int levelCount);
    /// setColor()'s upload of converted R'G'B' words.
    void uploadRgba(const std::uint32_t *rgba, int width, int height);

    RendererOptions options_;
    AvatarState avatar_{};
    OsdState osd_{};
    SurfaceMapping mapping_{};
    AdaptiveMesh mesh_;                      ///< The mesh made per frame (not Fixed).
    const AdaptiveMesh *drawnMesh_ = &mesh_; ///< mesh_ or the static grid drawn.
    scene::SampleFormat depthFormat_ = scene::SampleFormat::Gray8;
    std::uint32_t holeBelow_ = 0; ///< The drawn frame's DepthFrameView::holeBelow.
    bool haveDepth_ = false;
    ColorSpec colorSpec_{};
    bool softwareRasterizer_ = false;
    bool colorOnCpu_ = false;
    StageTiming stageTiming_ = StageTiming::Cpu;
    StageTimes stageTimes_{};
    platform::SteadyClock clock_;
    std::unique_ptr<Gl> gl_;
    std::unique_ptr<DmaBufImporter> dmabuf_; ///< Made at the first dma-buf frame.
    bool colorFromDmaBuf_ = false;           ///< The colour is dmabuf_->texture() (RGBA8).
    DmaBufStats dmaBufStats_{};
};

} // namespace depthtouch::render
