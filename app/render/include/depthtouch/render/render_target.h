#pragma once
/// \file
/// \brief RenderTarget: an offscreen OpenGL ES framebuffer (colour + depth renderbuffers) that the
/// stereo renderer draws into, and its read-back.
///
/// Needs a current OpenGL ES 3 context on the calling thread (from a hal::Display after
/// makeCurrent(), or a surfaceless test context). Thread-safety: thread-bound (the GL thread).

#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/platform/result.h"

namespace depthtouch::render {

/// \brief Colour buffer format.
enum class TargetFormat : std::uint8_t {
    Rgba8,   ///< What is shown.
    Rgba32F, ///< Float colour (needs EXT_color_buffer_float): for the surface position read-back.
};

/// \brief An FBO with a colour and a 24-bit depth renderbuffer. Move-only; frees its GL objects.
class RenderTarget {
public:
    /// \brief Creates a \a width × \a height target. \pre a current GLES 3 context.
    /// \return Errc::InvalidArgument for a size ≤ 0 or above GL_MAX_RENDERBUFFER_SIZE,
    /// Errc::NotSupported when the framebuffer is incomplete (e.g. no float colour buffers).
    static Result<RenderTarget> create(int width, int height,
                                       TargetFormat format = TargetFormat::Rgba8);

    RenderTarget() = default;
    RenderTarget(RenderTarget &&other) noexcept;
    RenderTarget &operator=(RenderTarget &&other) noexcept;
    RenderTarget(const RenderTarget &) = delete;
    RenderTarget &operator=(const RenderTarget &) = delete;
    ~RenderTarget();

    [[nodiscard]] int width() const noexcept { return width_; }   ///< Pixels.
    [[nodiscard]] int height() const noexcept { return height_; } ///< Pixels.
    [[nodiscard]] std::uint32_t framebuffer() const noexcept { return fbo_; } ///< GL name.
    [[nodiscard]] TargetFormat format() const noexcept { return format_; }

    /// Binds the FBO for drawing and reading.
    void bind() const noexcept;

    /// \brief Reads the colour buffer as RGB bytes, top row first (image order), 3·W·H bytes.
    /// Waits for rendering to finish. \pre format() == Rgba8.
    [[nodiscard]] Result<void> readRgb(std::vector<std::uint8_t> &rgb) const;
    /// \brief Reads the colour buffer as RGBA floats, top row first, 4·W·H values.
    /// \pre format() == Rgba32F.
    [[nodiscard]] Result<void> readRgbaFloat(std::vector<float> &rgba) const;

    /// \brief Copies the colour buffer to framebuffer \a dst (e.g. a display's default
    /// framebuffer), scaled to \a dstWidth × \a dstHeight. \return Errc::NotSupported when \a dst
    /// is not complete.
    [[nodiscard]] Result<void> blitTo(std::uint32_t dst, int dstWidth, int dstHeight) const;

private:
    void release() noexcept;
    std::uint32_t fbo_ = 0;
    std::uint32_t color_ = 0;
    std::uint32_t depth_ = 0;
    int width_ = 0;
    int height_ = 0;
    TargetFormat format_ = TargetFormat::Rgba8;
};

} // namespace depthtouch::render
