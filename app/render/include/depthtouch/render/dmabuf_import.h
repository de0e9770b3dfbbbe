#pragma once
/// \file
/// \brief Zero-copy colour frames: decoded frames shared as Linux dma-bufs (DRM PRIME,
/// hal::DmaBufImage) imported into GL with EGL_EXT_image_dma_buf_import, and the fallback that
/// reads them on the CPU when the platform cannot import them.
///
/// Import path: eglCreateImageKHR(EGL_LINUX_DMA_BUF_EXT, dmaBufEglAttribs()) on
/// eglGetCurrentDisplay(), glEGLImageTargetTexture2DOES on a GL_TEXTURE_EXTERNAL_OES texture, drawn
/// once per frame through a samplerExternalOES shader into the RGBA8 texture the surface samples.
/// For YUV fourccs the driver does the Y'CbCr → R'G'B' conversion (colour space and range from the
/// EGL hints of the ColorSpec). The pixels never go through the CPU; the draw is one GPU pass of
/// the frame size (the surface shaders stay the same for every colour source).
///
/// Needs: EGL_EXT_image_dma_buf_import on the current EGL display (plus
/// EGL_EXT_image_dma_buf_import_modifiers for a frame with an explicit, non-linear modifier) and
/// GL_OES_EGL_image_external; checked once. EGLImages are cached per dma-buf (inode of the fd and
/// plane-0 offset, so a reused fd number is never mistaken for its old buffer) and destroyed when
/// the frames change size or format (the decoder's pool changed), when the cache is full, and with
/// the importer.
///
/// Fallback (the import is unavailable or fails; e.g. Mesa llvmpipe on the surfaceless platform has
/// no EGL_EXT_image_dma_buf_import): the frame's CPU planes when it has them, otherwise the
/// dma-bufs mapped read-only (mmap, bracketed by DMA_BUF_IOCTL_SYNC start/end; a plain memory fd
/// without that ioctl, ENOTTY, is read without it) and uploaded like any decoded frame. Only linear
/// layouts (kDrmFormatModLinear, or the implied kDrmFormatModInvalid) can be read that way.
///
/// Thread-safety: DmaBufImporter is thread-bound (the render thread, with its GLES context
/// current); dmaBufEglAttribs() and hasExtension() are pure.

#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/render/color.h"

namespace depthtouch::render {

/// \return true when the space-separated extension string \a list names \a name exactly (not as a
/// prefix of a longer name). A null \a list has no extension.
bool hasExtension(const char *list, const char *name) noexcept;

/// \brief The attribute list of eglCreateImageKHR(EGL_LINUX_DMA_BUF_EXT) for \a image: EGL_WIDTH,
/// EGL_HEIGHT, EGL_LINUX_DRM_FOURCC_EXT, then per plane i EGL_DMA_BUF_PLANEi_FD_EXT, _OFFSET_EXT,
/// _PITCH_EXT and, when \a withModifier, _MODIFIER_LO_EXT / _MODIFIER_HI_EXT (the low and high 32
/// bits of the modifier), then EGL_YUV_COLOR_SPACE_HINT_EXT (BT.601 or BT.709) and
/// EGL_SAMPLE_RANGE_HINT_EXT (narrow or full) from \a spec, closed by EGL_NONE.
/// \return the list (EGLint values). Errors: InvalidArgument for an empty image, more than 4
/// planes, a plane count that does not match a known fourcc, a non-positive size, a negative fd, a
/// zero pitch, an offset or pitch beyond EGLint.
Result<std::vector<std::int32_t>> dmaBufEglAttribs(const hal::DmaBufImage &image, bool withModifier,
                                                   const ColorSpec &spec);

/// \brief What happened to the colour frames that came as dma-bufs (StereoRenderer::dmaBufStats()).
struct DmaBufStats {
    std::uint64_t imported = 0; ///< Frames drawn from an EGLImage of their dma-bufs (zero-copy).
    std::uint64_t uploaded = 0; ///< Frames uploaded instead (CPU planes or mapped dma-bufs).
    bool zeroCopy = false;      ///< The last dma-buf frame was imported (false after a fallback).
};

/// \brief Imports dma-buf frames into a GL texture or maps them for upload (see the file comment).
/// Create and destroy with the GLES context current.
class DmaBufImporter {
public:
    DmaBufImporter();
    ~DmaBufImporter();
    DmaBufImporter(const DmaBufImporter &) = delete;
    DmaBufImporter &operator=(const DmaBufImporter &) = delete;

    /// \brief Draws \a image into texture() (RGBA8, the frame's size), converted by the driver.
    /// \return nothing on success. Errors: NotSupported when the platform cannot import (missing
    /// extension, or the driver refused this frame: the importer then stays off and says why once
    /// in the log); InvalidArgument for a malformed descriptor.
    [[nodiscard]] Result<void> draw(const hal::DmaBufImage &image, const ColorSpec &spec);

    /// \return the GL name of the RGBA8 texture draw() fills (0 before the first success).
    [[nodiscard]] std::uint32_t texture() const noexcept;

    /// \brief Maps the dma-bufs of \a image read-only and describes them as a Yuv420p image (NV12
    /// chroma is de-interleaved into a scratch buffer kept between frames). Valid until unmap().
    /// \return the image. Errors: NotSupported for a non-linear modifier or an unknown fourcc;
    /// InvalidArgument when a plane lies outside its buffer; Io when a buffer cannot be mapped or
    /// synchronised.
    [[nodiscard]] Result<hal::ImageView> map(const hal::DmaBufImage &image);
    /// Ends the CPU access of map() (DMA_BUF_SYNC_END) and unmaps the buffers.
    void unmap() noexcept;

    /// Destroys every cached EGLImage (and its texture).
    void clearCache() noexcept;
    /// \return the number of cached EGLImages.
    [[nodiscard]] std::size_t cachedImages() const noexcept;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::render
