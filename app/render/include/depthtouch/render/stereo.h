#pragma once
/// \file
/// \brief Two shift-sensor eye cameras, and the stereo output layouts.
///
/// Viewer model (scene-box frame, metres, docs/architecture.md §3, docs/playing.md "Picture"): the
/// eyes sit on the line `y = 0, z = viewDistance`, `±eyeSeparation/2` left and right of the z
/// axis, and look along −z at the box. The zero-parallax (screen) plane is `convergence` in front
/// of the eyes, at `zc = viewDistance − convergence`. Each eye is a shift-sensor camera (C. Fehn,
/// "Depth-image-based rendering (DIBR), compression and transmission for a new approach on 3D-TV",
/// SPIE 5291, 2004): it sees the picture straight on (a parallel projection along −z) and shifts a
/// point at depth z by `−eyeX·(z − zc)/convergence` in x. The parallax is thus linear in the
/// nearness, which is linear in 1/Z for the default `inverse_z` mapping: the shift-sensor rig's
/// parallax, `f·b·(1/Z − 1/Zc)`. No point is scaled by its distance, so the mono view (and the
/// zero-parallax plane of each eye) is the source picture pixel for pixel, whatever the source
/// camera's field of view: a near object keeps its size relative to the wall. A point nearer than
/// the screen plane has crossed parallax (its left-eye image lies to the right of its right-eye
/// image); a farther one uncrossed. The window frames the picture (`boxWidth` × `boxHeight`) at the
/// eye viewport's aspect, with `margin`.
///
/// Output layouts of one frame (W×H pixels):
///  - `mono`: one centred camera, full frame;
///  - `sbs`: side-by-side, left eye in the left half, right eye in the right half, each eye W/2×H,
///    squeezed horizontally when frameCompatible (the display stretches each half back);
///  - `tab`: top-and-bottom, left eye in the top half, each eye W×H/2 (squeezed vertically when
///    frameCompatible);
///  - `anaglyph`: red-cyan, left eye into the red channel, right eye into green and blue, full
///  frame;
///  - `interleaved`: row-interleaved, left eye on the even rows counted from the top, right eye on
///  the
///    odd rows, full frame (autostereoscopic panels with line-interleaved polarisers).
///
/// Thread-safety: pure functions and value types.

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include <glm/mat4x4.hpp>

namespace depthtouch::render {

/// \brief How the two eyes share one output frame.
enum class StereoMode : std::uint8_t { Mono, SideBySide, TopAndBottom, Anaglyph, RowInterleaved };

/// \return "mono", "sbs", "tab", "anaglyph" or "interleaved" (static string).
const char *stereoModeName(StereoMode mode) noexcept;
/// \return the mode called \a name (the names above), or nullopt.
std::optional<StereoMode> parseStereoMode(std::string_view name) noexcept;

/// \brief Eye geometry, in scene-box metres (the box is a miniature: 0.10 m wide by default).
struct StereoParams {
    double eyeSeparation = 0.010; ///< Distance between the eyes, m (> 0 for stereo).
    double viewDistance = 0.20;   ///< Eyes to the box centre along z, m (> box depth).
    double convergence = 0.20; ///< Eyes to the zero-parallax plane, m (> 0); default: box centre.
    double margin = 1.0; ///< Window size / picture size (1 fills the eye; > 1 keeps a border).
    /// sbs/tab: true = frame-compatible (each eye squeezed into its half, the display stretches it
    /// back: HDMI half side-by-side/top-and-bottom); false = each half is a full-aspect eye image
    /// (e.g. 1440×486 side-by-side of two 720×486 eyes).
    bool frameCompatible = true;
};

/// \brief A pixel rectangle of the output frame, OpenGL convention (x, y of the lower-left corner).
struct Viewport {
    int x = 0;      ///< pixels from the frame's left edge.
    int y = 0;      ///< pixels from the frame's bottom edge.
    int width = 0;  ///< pixels.
    int height = 0; ///< pixels.
};

/// \brief One camera: view and projection matrices and where it draws.
struct EyeView {
    glm::mat4 view{1.0f};       ///< Scene box → eye frame (with the eye's parallax shift).
    glm::mat4 projection{1.0f}; ///< Eye frame → clip space (parallel projection of the window).
    Viewport viewport{};
    double eyeOffset = 0.0;      ///< Eye x position, m (−sep/2 left, +sep/2 right, 0 mono).
    int rowParity = -1;          ///< RowInterleaved: draw only window rows y with y % 2 == parity.
    std::uint8_t colorMask = 0x7; ///< Bits R=1, G=2, B=4 (Anaglyph: left 0x1, right 0x6).
};

/// \brief The eyes to draw for \a mode in a \a width × \a height frame, left eye first.
/// \param[in] boxWidth, boxHeight x and y extent of the picture in the scene box, m (> 0): the
/// sample grid plus half a sample at each side, SurfaceMapping::pictureWidth() and pictureHeight()
/// \param[in] boxDepth z extent of the box, m (> 0): sets the near and far planes
/// \return 1 view (Mono) or 2 views (left, right); \a count receives the number.
std::array<EyeView, 2> eyeViews(StereoMode mode, const StereoParams &params, int width, int height,
                                double boxWidth, double boxHeight, double boxDepth, int &count);

/// \brief A single shift-sensor camera at eye offset \a eyeX, drawing into \a viewport, whose
/// window has the aspect ratio \a aspect (width/height of the eye image as the viewer sees it).
EyeView eyeView(const StereoParams &params, double eyeX, double aspect, Viewport viewport,
                double boxWidth, double boxHeight, double boxDepth);

/// \brief An orthographic camera straight down the z axis whose frame covers exactly the box's x–y
/// rectangle (pixel centres at the sample positions, to 1/128 pixel, when the frame is W×H): for
/// tests and height read-back.
EyeView topView(int width, int height, double boxWidth, double boxHeight, double boxDepth);

} // namespace depthtouch::render
