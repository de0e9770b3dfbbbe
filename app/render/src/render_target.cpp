#include "depthtouch/render/render_target.h"

#include <GLES3/gl3.h>

#include <cstring>
#include <utility>
#include <vector>

namespace depthtouch::render {

namespace {

/// Reads the whole colour buffer of \a target, which must be of format \a format, as RGBA
/// samples of \a type into \a raw (GL's rows: bottom-up), packed at \a alignment bytes.
/// \return Errc::InvalidState with \a wrongFormat when it is not such a target, Errc::Io with
/// \a readFailed when glReadPixels fails (both static strings).
template <class T>
Result<void> readRgbaRows(const RenderTarget &target, TargetFormat format, const char *wrongFormat,
                          GLenum type, GLint alignment, const char *readFailed, std::vector<T> &raw)
{
    if (target.framebuffer() == 0 || target.format() != format)
        return unexpected(Errc::InvalidState, wrongFormat);
    const auto w = static_cast<std::size_t>(target.width());
    const auto h = static_cast<std::size_t>(target.height());
    raw.assign(w * h * 4, T{});
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.framebuffer());
    glPixelStorei(GL_PACK_ALIGNMENT, alignment);
    glReadPixels(0, 0, target.width(), target.height(), GL_RGBA, type, raw.data());
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, readFailed);
    return ok();
}

} // namespace

Result<RenderTarget> RenderTarget::create(int width, int height, TargetFormat format)
{
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (width <= 0 || height <= 0 || width > maxSize || height > maxSize)
        return unexpected(Errc::InvalidArgument, "render target size out of range");
    RenderTarget t;
    t.width_ = width;
    t.height_ = height;
    t.format_ = format;
    glGenFramebuffers(1, &t.fbo_);
    glGenRenderbuffers(1, &t.color_);
    glGenRenderbuffers(1, &t.depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, t.color_);
    glRenderbufferStorage(GL_RENDERBUFFER, format == TargetFormat::Rgba8 ? GL_RGBA8 : GL_RGBA32F,
                          width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, t.depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.color_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t.depth_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR)
        return unexpected(Errc::NotSupported, "render target framebuffer is incomplete");
    return t;
}

RenderTarget::RenderTarget(RenderTarget &&other) noexcept
    : fbo_(std::exchange(other.fbo_, 0)), color_(std::exchange(other.color_, 0)),
      depth_(std::exchange(other.depth_, 0)), width_(other.width_), height_(other.height_),
      format_(other.format_)
{
}

RenderTarget &RenderTarget::operator=(RenderTarget &&other) noexcept
{
    if (this != &other) {
        release();
        fbo_ = std::exchange(other.fbo_, 0);
        color_ = std::exchange(other.color_, 0);
        depth_ = std::exchange(other.depth_, 0);
        width_ = other.width_;
        height_ = other.height_;
        format_ = other.format_;
    }
    return *this;
}

RenderTarget::~RenderTarget()
{
    release();
}

void RenderTarget::release() noexcept
{
    if (fbo_ != 0)
        glDeleteFramebuffers(1, &fbo_);
    if (color_ != 0)
        glDeleteRenderbuffers(1, &color_);
    if (depth_ != 0)
        glDeleteRenderbuffers(1, &depth_);
    fbo_ = color_ = depth_ = 0;
}

void RenderTarget::bind() const noexcept
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
}

Result<void> RenderTarget::readRgb(std::vector<std::uint8_t> &rgb) const
{
    std::vector<std::uint8_t> rgba;
    DT_TRY(readRgbaRows(*this, TargetFormat::Rgba8, "render target is not an RGBA8 target",
                        GL_UNSIGNED_BYTE, 1, "glReadPixels failed", rgba));
    const auto w = static_cast<std::size_t>(width_);
    const auto h = static_cast<std::size_t>(height_);
    rgb.resize(w * h * 3);
    // GL rows run bottom-up; images top-down.
    for (std::size_t y = 0; y < h; ++y) {
        const std::uint8_t *src = rgba.data() + (h - 1 - y) * w * 4;
        std::uint8_t *dst = rgb.data() + y * w * 3;
        for (std::size_t x = 0; x < w; ++x) {
            dst[3 * x] = src[4 * x];
            dst[3 * x + 1] = src[4 * x + 1];
            dst[3 * x + 2] = src[4 * x + 2];
        }
    }
    return ok();
}

Result<void> RenderTarget::readRgbaFloat(std::vector<float> &rgba) const
{
    std::vector<float> raw;
    DT_TRY(readRgbaRows(*this, TargetFormat::Rgba32F, "render target is not a float target",
                        GL_FLOAT, 4, "glReadPixels (float) failed", raw));
    const auto w = static_cast<std::size_t>(width_);
    const auto h = static_cast<std::size_t>(height_);
    rgba.resize(w * h * 4);
    for (std::size_t y = 0; y < h; ++y)
        std::memcpy(rgba.data() + y * w * 4, raw.data() + (h - 1 - y) * w * 4,
                    w * 4 * sizeof(float));
    return ok();
}

Result<void> RenderTarget::blitTo(std::uint32_t dst, int dstWidth, int dstHeight) const
{
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, dst);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return unexpected(Errc::NotSupported, "destination framebuffer is not complete");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    // At the same size filtering changes nothing, and GL_NEAREST lets the driver copy the pixels
    // instead of drawing a textured quad (Mesa: a plain copy only for unfiltered blits).
    const bool sameSize = dstWidth == width_ && dstHeight == height_;
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, dstWidth, dstHeight, GL_COLOR_BUFFER_BIT,
                      sameSize ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "glBlitFramebuffer failed");
    return ok();
}

} // namespace depthtouch::render
