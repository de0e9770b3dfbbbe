#include "depthtouch/render/dmabuf_import.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <GLES2/gl2ext.h>
#include <linux/dma-buf.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <string>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/gl_program.h"
#include "depthtouch/render/renderer.h"

DT_LOG_CATEGORY(DmaBuf)

namespace depthtouch::render {

namespace {

constexpr EGLint kPlaneAttribs[hal::DmaBufImage::kMaxPlanes][5] = {
    {EGL_DMA_BUF_PLANE0_FD_EXT, EGL_DMA_BUF_PLANE0_OFFSET_EXT, EGL_DMA_BUF_PLANE0_PITCH_EXT,
     EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT, EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT},
    {EGL_DMA_BUF_PLANE1_FD_EXT, EGL_DMA_BUF_PLANE1_OFFSET_EXT, EGL_DMA_BUF_PLANE1_PITCH_EXT,
     EGL_DMA_BUF_PLANE1_MODIFIER_LO_EXT, EGL_DMA_BUF_PLANE1_MODIFIER_HI_EXT},
    {EGL_DMA_BUF_PLANE2_FD_EXT, EGL_DMA_BUF_PLANE2_OFFSET_EXT, EGL_DMA_BUF_PLANE2_PITCH_EXT,
     EGL_DMA_BUF_PLANE2_MODIFIER_LO_EXT, EGL_DMA_BUF_PLANE2_MODIFIER_HI_EXT},
    {EGL_DMA_BUF_PLANE3_FD_EXT, EGL_DMA_BUF_PLANE3_OFFSET_EXT, EGL_DMA_BUF_PLANE3_PITCH_EXT,
     EGL_DMA_BUF_PLANE3_MODIFIER_LO_EXT, EGL_DMA_BUF_PLANE3_MODIFIER_HI_EXT},
};

/// EGLImages kept at most: a decoder pool (24 by default) plus margin. More means the buffers
/// changed, so everything is dropped.
constexpr std::size_t kMaxCachedImages = 40;

// ESSL 1.00: GL_OES_EGL_image_external is the extension every importer has (its essl3 variant is
// optional); a GLES 3 context runs it.
constexpr const char *kBlitVs = R"(#version 100
attribute vec2 aPos;
varying vec2 vTex;
void main() {
    vTex = aPos * 0.5 + 0.5;
    gl_Position = vec4(aPos, 0.0, 1.0);
}
)";
constexpr const char *kBlitFs = R"(#version 100
#extension GL_OES_EGL_image_external : require
precision mediump float;
uniform samplerExternalOES uImage;
varying vec2 vTex;
void main() {
    gl_FragColor = vec4(texture2D(uImage, vTex).rgb, 1.0);
}
)";

/// Bytes per row and rows of plane \a p of a \a fourcc image.
void planeExtent(std::uint32_t fourcc, int p, int w, int h, std::size_t &rowBytes,
                 std::size_t &rows)
{
    const auto cw = static_cast<std::size_t>((w + 1) / 2);
    const auto ch = static_cast<std::size_t>((h + 1) / 2);
    if (p == 0) {
        rowBytes = static_cast<std::size_t>(w);
        rows = static_cast<std::size_t>(h);
    } else {
        rowBytes = fourcc == hal::kDrmFormatNv12 ? 2 * cw : cw;
        rows = ch;
    }
}

} // namespace

bool hasExtension(const char *list, const char *name) noexcept
{
    if (list == nullptr || name == nullptr || *name == '\0')
        return false;
    const std::size_t n = std::strlen(name);
    for (const char *p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
        const bool startOk = p == list || p[-1] == ' ';
        const bool endOk = p[n] == '\0' || p[n] == ' ';
        if (startOk && endOk)
            return true;
    }
    return false;
}

Result<std::vector<std::int32_t>> dmaBufEglAttribs(const hal::DmaBufImage &image, bool withModifier,
                                                   const ColorSpec &spec)
{
    if (image.empty() || image.planeCount > hal::DmaBufImage::kMaxPlanes || image.planeCount < 0)
        return unexpected(Errc::InvalidArgument,
                          "dma-buf image without planes or with more than 4");
    if (hal::drmPlaneCount(image.fourcc) != image.planeCount)
        return unexpected(Errc::InvalidArgument, "dma-buf plane count does not match its fourcc");
    if (image.width <= 0 || image.height <= 0)
        return unexpected(Errc::InvalidArgument, "dma-buf image of non-positive size");
    constexpr auto kMax = static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max());
    std::vector<std::int32_t> a;
    a.reserve(7 + 10 * static_cast<std::size_t>(image.planeCount) + 5);
    a.insert(a.end(), {EGL_WIDTH, image.width, EGL_HEIGHT, image.height, EGL_LINUX_DRM_FOURCC_EXT,
                       static_cast<std::int32_t>(image.fourcc)});
    for (int i = 0; i < image.planeCount; ++i) {
        const hal::DmaBufPlane &p = image.planes[static_cast<std::size_t>(i)];
        if (p.fd < 0 || p.pitch == 0 || p.pitch > kMax || p.offset > kMax)
            return unexpected(Errc::InvalidArgument,
                              "dma-buf plane with a bad fd, offset or pitch");
        const EGLint *names = kPlaneAttribs[i];
        a.insert(a.end(), {names[0], p.fd, names[1], static_cast<std::int32_t>(p.offset), names[2],
                           static_cast<std::int32_t>(p.pitch)});
        if (withModifier)
            a.insert(a.end(),
                     {names[3], static_cast<std::int32_t>(image.modifier & 0xffffffffu), names[4],
                      static_cast<std::int32_t>(image.modifier >> 32)});
    }
    a.insert(a.end(),
             {EGL_YUV_COLOR_SPACE_HINT_EXT,
              spec.matrix == YuvMatrix::Bt709 ? EGL_ITU_REC709_EXT : EGL_ITU_REC601_EXT,
              EGL_SAMPLE_RANGE_HINT_EXT,
              spec.fullRange ? EGL_YUV_FULL_RANGE_EXT : EGL_YUV_NARROW_RANGE_EXT, EGL_NONE});
    return a;
}

struct DmaBufImporter::Impl {
    struct Cached {
        int fd = -1;
        ino_t inode = 0;
        dev_t device = 0;
        std::uint32_t offset = 0;
        EGLImageKHR image = EGL_NO_IMAGE_KHR;
        GLuint texture = 0;
    };
    struct Mapping {
        int fd = -1;
        void *base = MAP_FAILED;
        std::size_t size = 0;
        bool synced = false;
    };

    bool checked = false;
    bool available = false;
    bool modifiers = false;
    EGLDisplay display = EGL_NO_DISPLAY;
    PFNEGLCREATEIMAGEKHRPROC createImage = nullptr;
    PFNEGLDESTROYIMAGEKHRPROC destroyImage = nullptr;
    PFNGLEGLIMAGETARGETTEXTURE2DOESPROC targetTexture = nullptr;
    GLuint program = 0;
    GLuint vbo = 0;
    GLuint vao = 0;
    GLuint fbo = 0;
    GLuint target = 0; ///< RGBA8 texture the frames are drawn into.
    int targetWidth = 0;
    int targetHeight = 0;
    std::uint32_t cachedFourcc = 0;
    int cachedWidth = 0;
    int cachedHeight = 0;
    std::vector<Cached> cache;
    Mapping mappings[hal::DmaBufImage::kMaxPlanes];
    int mappingCount = 0;
    std::vector<std::uint8_t> chroma; ///< De-interleaved NV12 chroma (U then V).

    /// Checks the extensions and builds the shader once. \return why it is unavailable, or "".
    std::string setUp();
    Result<GLuint> textureOf(const hal::DmaBufImage &image, const ColorSpec &spec);
};

std::string DmaBufImporter::Impl::setUp()
{
    display = eglGetCurrentDisplay();
    if (display == EGL_NO_DISPLAY)
        return "no current EGL display";
    const char *egl = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(egl, "EGL_EXT_image_dma_buf_import"))
        return "EGL_EXT_image_dma_buf_import missing";
    modifiers = hasExtension(egl, "EGL_EXT_image_dma_buf_import_modifiers");
    if (!gl::hasExtension("GL_OES_EGL_image_external"))
        return "GL_OES_EGL_image_external missing";
    createImage =
        reinterpret_cast<PFNEGLCREATEIMAGEKHRPROC>(eglGetProcAddress("eglCreateImageKHR"));
    destroyImage =
        reinterpret_cast<PFNEGLDESTROYIMAGEKHRPROC>(eglGetProcAddress("eglDestroyImageKHR"));
    targetTexture = reinterpret_cast<PFNGLEGLIMAGETARGETTEXTURE2DOESPROC>(
        eglGetProcAddress("glEGLImageTargetTexture2DOES"));
    if (createImage == nullptr || destroyImage == nullptr || targetTexture == nullptr)
        return "eglCreateImageKHR or glEGLImageTargetTexture2DOES missing";
    program = gl::linkProgram(kBlitVs, kBlitFs, "aPos", /*optional=*/true);
    if (program == 0)
        return "the samplerExternalOES shader does not build";
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "uImage"), 0);
    const float triangle[] = {-1.0f, -1.0f, 3.0f, -1.0f, -1.0f, 3.0f}; // covers the viewport
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof triangle, triangle, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
    glGenFramebuffers(1, &fbo);
    return "";
}

Result<GLuint> DmaBufImporter::Impl::textureOf(const hal::DmaBufImage &image, const ColorSpec &spec)
{
    struct stat st {};
    if (fstat(image.planes[0].fd, &st) != 0)
        return unexpected(Errc::InvalidArgument, "dma-buf fd is not open", errno);
    // Another size or format: the decoder's buffers changed; their old images are of no use.
    if (image.fourcc != cachedFourcc || image.width != cachedWidth ||
        image.height != cachedHeight || cache.size() >= kMaxCachedImages) {
        for (Cached &c : cache) {
            glDeleteTextures(1, &c.texture);
            destroyImage(display, c.image);
        }
        cache.clear();
        cachedFourcc = image.fourcc;
        cachedWidth = image.width;
        cachedHeight = image.height;
    }
    for (const Cached &c : cache)
        if (c.fd == image.planes[0].fd && c.inode == st.st_ino && c.device == st.st_dev &&
            c.offset == image.planes[0].offset)
            return c.texture;

    const bool linear = image.modifier == hal::kDrmFormatModLinear ||
                        image.modifier == hal::kDrmFormatModInvalid;
    if (!linear && !modifiers)
        return unexpected(Errc::NotSupported,
                          "EGL_EXT_image_dma_buf_import_modifiers missing for a tiled dma-buf");
    auto attribs = dmaBufEglAttribs(image, modifiers && image.modifier != hal::kDrmFormatModInvalid,
                                    spec);
    if (!attribs)
        return unexpected(attribs.error());
    EGLImageKHR img = createImage(display, EGL_NO_CONTEXT, EGL_LINUX_DMA_BUF_EXT, nullptr,
                                  attribs->data());
    if (img == EGL_NO_IMAGE_KHR) {
        DT_LOG(DmaBuf, Warning, "Failed to import a dma-buf (EGL error 0x%x)",
               static_cast<unsigned>(eglGetError()));
        return unexpected(Errc::NotSupported, "The EGL driver refused the dma-buf");
    }
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_EXTERNAL_OES, tex);
    glTexParameteri(GL_TEXTURE_EXTERNAL_OES, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_EXTERNAL_OES, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_EXTERNAL_OES, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_EXTERNAL_OES, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    targetTexture(GL_TEXTURE_EXTERNAL_OES, static_cast<GLeglImageOES>(img));
    glBindTexture(GL_TEXTURE_EXTERNAL_OES, 0);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        destroyImage(display, img);
        return unexpected(Errc::NotSupported, "GL refused the EGLImage of a dma-buf");
    }
    cache.push_back({image.planes[0].fd, st.st_ino, st.st_dev, image.planes[0].offset, img, tex});
    return tex;
}

DmaBufImporter::DmaBufImporter() : impl_(std::make_unique<Impl>()) {}

DmaBufImporter::~DmaBufImporter()
{
    unmap();
    clearCache();
    Impl &d = *impl_;
    if (d.program != 0)
        glDeleteProgram(d.program);
    if (d.vao != 0)
        glDeleteVertexArrays(1, &d.vao);
    if (d.vbo != 0)
        glDeleteBuffers(1, &d.vbo);
    if (d.fbo != 0)
        glDeleteFramebuffers(1, &d.fbo);
    if (d.target != 0)
        glDeleteTextures(1, &d.target);
}

std::uint32_t DmaBufImporter::texture() const noexcept
{
    return impl_->target;
}

std::size_t DmaBufImporter::cachedImages() const noexcept
{
    return impl_->cache.size();
}

void DmaBufImporter::clearCache() noexcept
{
    Impl &d = *impl_;
    for (Impl::Cached &c : d.cache) {
        glDeleteTextures(1, &c.texture);
        if (d.destroyImage != nullptr)
            d.destroyImage(d.display, c.image);
    }
    d.cache.clear();
}

Result<void> DmaBufImporter::draw(const hal::DmaBufImage &image, const ColorSpec &spec)
{
    Impl &d = *impl_;
    if (!d.checked) {
        d.checked = true;
        const std::string why = d.setUp();
        d.available = why.empty();
        if (!d.available)
            DT_LOG(DmaBuf, Warning,
                   "Zero-copy import of dma-buf frames unavailable (%s): uploading "
                   "them instead",
                   why.c_str());
    }
    if (!d.available)
        return unexpected(Errc::NotSupported, "dma-buf import unavailable on this EGL display");
    auto tex = d.textureOf(image, spec);
    if (!tex) {
        if (tex.error().code == Errc::NotSupported) {
            d.available = false; // the driver cannot import these frames: stop trying
            DT_LOG(DmaBuf, Warning, "Zero-copy import of dma-buf frames failed (%s): uploading "
                                    "them instead", tex.error().what);
        }
        return unexpected(tex.error());
    }
    if (d.target == 0 || d.targetWidth != image.width || d.targetHeight != image.height) {
        if (d.target != 0)
            glDeleteTextures(1, &d.target);
        d.target = gl::createTexture2D(GL_RGBA8, image.width, image.height, GL_LINEAR);
        d.targetWidth = image.width;
        d.targetHeight = image.height;
    }
    // One pass of the frame's size into the RGBA8 target; the caller's framebuffer and viewport
    // are restored.
    GLint previousFbo = 0;
    GLint viewport[4] = {};
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previousFbo);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, d.fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, d.target, 0);
    glViewport(0, 0, image.width, image.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(d.program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_EXTERNAL_OES, *tex);
    glBindVertexArray(d.vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_EXTERNAL_OES, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previousFbo));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while drawing a dma-buf frame");
    return ok();
}

Result<hal::ImageView> DmaBufImporter::map(const hal::DmaBufImage &image)
{
    Impl &d = *impl_;
    unmap();
    if (image.empty() || image.planeCount > hal::DmaBufImage::kMaxPlanes ||
        hal::drmPlaneCount(image.fourcc) != image.planeCount || image.width <= 0 ||
        image.height <= 0)
        return unexpected(Errc::NotSupported, "dma-buf frame of an unknown layout");
    if (image.modifier != hal::kDrmFormatModLinear && image.modifier != hal::kDrmFormatModInvalid)
        return unexpected(Errc::NotSupported, "A tiled dma-buf cannot be read on the CPU");
    const std::uint8_t *planeData[hal::DmaBufImage::kMaxPlanes] = {};
    for (int i = 0; i < image.planeCount; ++i) {
        const hal::DmaBufPlane &p = image.planes[static_cast<std::size_t>(i)];
        Impl::Mapping *m = nullptr;
        for (int k = 0; k < d.mappingCount; ++k)
            if (d.mappings[k].fd == p.fd)
                m = &d.mappings[k];
        if (m == nullptr) {
            const off_t end = lseek(p.fd, 0, SEEK_END);
            if (end <= 0) {
                unmap();
                return unexpected(Errc::Io, "Failed to size a dma-buf", errno);
            }
            void *base =
                mmap(nullptr, static_cast<std::size_t>(end), PROT_READ, MAP_SHARED, p.fd, 0);
            if (base == MAP_FAILED) {
                unmap();
                return unexpected(Errc::Io, "Failed to map a dma-buf", errno);
            }
            m = &d.mappings[d.mappingCount++];
            *m = {p.fd, base, static_cast<std::size_t>(end), false};
            dma_buf_sync sync{};
            sync.flags = DMA_BUF_SYNC_START | DMA_BUF_SYNC_READ;
            int r = 0;
            do
                r = ioctl(p.fd, DMA_BUF_IOCTL_SYNC, &sync);
            while (r != 0 && (errno == EINTR || errno == EAGAIN));
            if (r == 0) {
                m->synced = true;
            } else if (errno != ENOTTY && errno != ENOSYS) {
                // ENOTTY: plain memory (memfd), nothing to synchronise; ENOSYS: the same ioctl
                // under an emulator that does not know it (qemu-user).
                const int err = errno;
                unmap();
                return unexpected(Errc::Io, "Failed to start CPU access to a dma-buf", err);
            }
        }
        std::size_t rowBytes = 0;
        std::size_t rows = 0;
        planeExtent(image.fourcc, i, image.width, image.height, rowBytes, rows);
        const std::size_t end = static_cast<std::size_t>(p.offset) +
                                static_cast<std::size_t>(p.pitch) * (rows - 1) + rowBytes;
        if (p.pitch < rowBytes || end > m->size) {
            unmap();
            return unexpected(Errc::InvalidArgument, "dma-buf plane outside its buffer");
        }
        planeData[i] = static_cast<const std::uint8_t *>(m->base) + p.offset;
    }
    hal::ImageView v;
    v.width = image.width;
    v.height = image.height;
    v.format = hal::PixelFormat::Yuv420p;
    // Read-only memory behind a view type with mutable pointers: the renderer only reads it.
    v.planes[0] = {const_cast<std::uint8_t *>(planeData[0]),
                   static_cast<int>(image.planes[0].pitch)};
    const int cw = (image.width + 1) / 2;
    const int ch = (image.height + 1) / 2;
    if (image.fourcc == hal::kDrmFormatYuv420) {
        for (std::size_t i = 1; i < 3; ++i)
            v.planes[i] = {const_cast<std::uint8_t *>(planeData[i]),
                           static_cast<int>(image.planes[i].pitch)};
    } else { // NV12: CbCr pairs to two planes
        const auto n = static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch);
        d.chroma.resize(2 * n);
        std::uint8_t *u = d.chroma.data();
        std::uint8_t *vv = u + n;
        for (int y = 0; y < ch; ++y) {
            const std::uint8_t *src =
                planeData[1] + static_cast<std::size_t>(y) * image.planes[1].pitch;
            for (int x = 0; x < cw; ++x) {
                u[static_cast<std::size_t>(y * cw + x)] = src[2 * x];
                vv[static_cast<std::size_t>(y * cw + x)] = src[2 * x + 1];
            }
        }
        v.planes[1] = {u, cw};
        v.planes[2] = {vv, cw};
    }
    return v;
}

void DmaBufImporter::unmap() noexcept
{
    Impl &d = *impl_;
    for (int k = 0; k < d.mappingCount; ++k) {
        Impl::Mapping &m = d.mappings[k];
        if (m.synced) {
            dma_buf_sync sync{};
            sync.flags = DMA_BUF_SYNC_END | DMA_BUF_SYNC_READ;
            while (ioctl(m.fd, DMA_BUF_IOCTL_SYNC, &sync) != 0 &&
                   (errno == EINTR || errno == EAGAIN)) {
            }
        }
        munmap(m.base, m.size);
        m = {};
    }
    d.mappingCount = 0;
}

// StereoRenderer's dma-buf entry points live here, beside the importer, so the renderer core keeps
// one hook (the texture drawSurface() samples).

Result<void> StereoRenderer::setColorFrame(const hal::ImageView &image,
                                           const hal::DmaBufImage &dmabuf, const ColorSpec &spec)
{
    if (dmabuf.empty())
        return setColor(image, spec);
    const platform::TimePoint t = clock_.now();
    if (!dmabuf_)
        dmabuf_ = std::make_unique<DmaBufImporter>();
    if (auto drawn = dmabuf_->draw(dmabuf, spec); drawn) {
        colorFromDmaBuf_ = true;
        colorSpec_ = spec;
        ++dmaBufStats_.imported;
        dmaBufStats_.zeroCopy = true;
        stageTimes_.colorUpload = stageEnd(t);
        return ok();
    } else if (drawn.error().code == Errc::InvalidArgument) {
        return drawn;
    }
    // Fallback: upload, from the CPU planes when the frame has them, else from the mapped dma-bufs.
    dmaBufStats_.zeroCopy = false;
    Result<void> r = ok();
    if (!image.empty()) {
        r = setColor(image, spec);
    } else {
        auto mapped = dmabuf_->map(dmabuf);
        if (!mapped) {
            DT_LOG_ONCE(DmaBuf, Warning, "Failed to read a dma-buf frame: %s", mapped.error().what);
            return unexpected(mapped.error());
        }
        r = setColor(*mapped, spec);
        dmabuf_->unmap();
    }
    if (r) {
        ++dmaBufStats_.uploaded;
        stageTimes_.colorUpload = stageEnd(t);
    }
    return r;
}

} // namespace depthtouch::render
