#pragma once
/// \file
/// \brief Built-in animated CG scenes rendered with OpenGL ES 3: the color comes from the color
/// buffer and the depth from the Z-buffer, linearised to nearness (paper V.A: "each depth image
/// can be saved by reading the Z-buffer frame by frame"). The built-in content of the encoder
/// (`synthetic:NAME`) and of tests.
///
/// Scenes (listScenes()):
/// - `head`: a lit, textured head (skin with pores and blush, eyes, brows, lips, ears, hair) on a
///   neck and shoulders, in front of a folded cloth curtain, turning (±35°, 4 s period) and nodding
///   (±12°, 2.5 s). At frame 0 it faces the camera, horizontally centred. Camera 0.75 m from the
///   head centre, vertical field of view 28°. Near/far 0.5 m / 1.5 m.
/// - `spheres`: five textured spheres (marble, painted, rubber) moving on independent paths at
///   0.7–2.3 m in a room with a wooden floor and a plastered wall. Camera at (0, 0.12, 0) m
///   looking at (0, −0.05, −1.5) m (x right, y up), vertical field of view 40°. Each sphere's
///   centre follows base + amplitude·sin(ω·t + φ) on each axis (m, rad/s, rad; t = frame / fps):
///
///   | sphere | radius (m) | base (m) | amplitude (m) | ω (rad/s) | φ (rad) |
///   |---|---|---|---|---|---|
///   | marble | 0.10 | −0.35, −0.10, −1.25 | 0.15, 0.06, 0.35 | 0.9, 1.3, 0.7 | 0, 0.5, 1.0 |
///   | paint | 0.08 | 0.30, 0.05, −0.95 | 0.12, 0.10, 0.20 | 1.1, 0.8, 0.9 | 1.2, 0, 2.0 |
///   | marble | 0.14 | 0.15, −0.08, −1.95 | 0.40, 0.08, 0.30 | 0.6, 1.0, 0.5 | 2.0, 1.0, 0.3 |
///   | rubber | 0.07 | −0.10, 0.12, −0.80 | 0.20, 0.05, 0.08 | 1.4, 1.7, 1.2 | 0.7, 2.2, 0 |
///   | paint | 0.12 | −0.60, 0.10, −2.20 | 0.20, 0.12, 0.10 | 0.7, 0.9, 0.8 | 3.0, 0.4, 1.5 |
///
///   Near/far 0.5 m / 3.0 m.
/// - `cut`: shots of `head` and `spheres` alternating every 2 s (a scene cut: the depth jumps
///   between the last frame of a shot and the first of the next). Near/far 0.5 m / 3.0 m.
///
/// Depth: the Z-buffer (32-bit float) of the camera whose clip planes are near()/far() is turned
/// into metric distance Z, then into nearness by docs/architecture.md §3's metric mapping (MPEG 3DV
/// inverse-Z): `v = v_max·(1/Z − 1/far)/(1/near − 1/far)` (0 = far plane, v_max = nearest),
/// computed in 16 bits on the GPU; 8-bit output is the 16-bit value rounded. Write near()/far() to
/// the file's depth_near/depth_far tags (mapping `inverse_z`).
///
/// Requirements: an OpenGL ES 3.0 context current on the calling thread for create(), render()
/// and the destructor (e.g. a headless hal::Display after makeCurrent()). render() renders into its
/// own framebuffer and restores the framebuffer binding and viewport it found.
/// Thread-safety: thread-bound (the thread whose context is current). Not real-time safe.

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::synthetic {

/// Name and one-line description of a built-in scene.
struct SceneInfo {
    const char *name;
    const char *description;
};

/// \return the built-in scenes, in a fixed order.
std::span<const SceneInfo> listScenes() noexcept;

/// \brief One built-in scene, its GL resources and its offscreen framebuffer.
class SyntheticScene {
public:
    /// \brief Compiles the shaders and builds the meshes and framebuffer of scene \a name.
    /// \param[in] name One of listScenes().
    /// \param[in] width,height Frame size in pixels (16..4096).
    /// \param[in] fps Frames per second of the animation (1..1000): frame i shows time i / fps.
    /// \return the scene. Errors: InvalidArgument (unknown name, size or rate out of range),
    /// InvalidState (no GL ES 3 context current), NotSupported (a shader or framebuffer fails).
    static Result<std::unique_ptr<SyntheticScene>> create(std::string_view name, int width,
                                                          int height, double fps);
    ~SyntheticScene();
    SyntheticScene(const SyntheticScene &) = delete;
    SyntheticScene &operator=(const SyntheticScene &) = delete;

    /// \brief Renders frame \a frameIndex and reads it back, top row first.
    /// \param[in] frameIndex Frame number (time frameIndex / fps()).
    /// \param[out] color Rgb24 or Rgba8 image of width()×height() pixels, or an empty view (no
    /// color wanted).
    /// \param[out] nearness Gray8 or Gray16 image of width()×height() samples (nearness, see the
    /// file comment), or an empty view.
    /// \param[out] material Rgb24 image of width()×height() pixels: each point's haptic material
    /// codes (depthtouch/scene/material.h; the material track), or an empty view (the default).
    /// Head: skin (stiffness ×0.84, μs 0.6, μd 0.45), softer cheeks (×0.63) and lips, a firmer
    /// forehead (×1.5), slippery eyes, soft hair, the sweater and the curtain's cloth (×0.66,
    /// μs 0.85, μd 0.65). Spheres: marble, paint, wood, plaster, rubber. An extra pass of the
    /// scene (drawn again with the material codes as colour).
    /// \return nothing. Errors: InvalidArgument (a view has the wrong size or format), Io (a GL
    /// error while drawing or reading).
    Result<void> render(std::uint64_t frameIndex, const hal::ImageView &color,
                        const hal::ImageView &nearness, const hal::ImageView &material = {});

    /// \return true when \a frameIndex is the first frame of a new shot (a scene cut).
    [[nodiscard]] bool isCut(std::uint64_t frameIndex) const noexcept;

    [[nodiscard]] const char *name() const noexcept;
    [[nodiscard]] int width() const noexcept { return width_; }
    [[nodiscard]] int height() const noexcept { return height_; }
    [[nodiscard]] double fps() const noexcept { return fps_; }
    /// \return the near plane of the depth mapping, metres.
    [[nodiscard]] double nearMetres() const noexcept;
    /// \return the far plane of the depth mapping, metres.
    [[nodiscard]] double farMetres() const noexcept;

private:
    struct Impl;
    SyntheticScene(std::unique_ptr<Impl> impl, int width, int height, double fps);

    std::unique_ptr<Impl> impl_;
    int width_;
    int height_;
    double fps_;
};

} // namespace depthtouch::synthetic
