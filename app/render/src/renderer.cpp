#include "depthtouch/render/renderer.h"

#include <GLES3/gl3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "depthtouch/haptics/height_field.h"
#include "depthtouch/render/dmabuf_import.h"
#include "depthtouch/render/render_target.h"
#include "gl_program.h"
#include "osd_font.h"

namespace depthtouch::render {

namespace {

// The surface: vertex k of the W×H grid is sample (k mod W, k div W); no vertex buffer, the height
// comes from the depth texture (vertex texture fetch) and the placement from SurfaceMapping.
constexpr const char *kSurfaceVs = R"(
precision highp float;
precision highp int;
#ifdef DEPTH16
uniform highp usampler2D uDepth;
#else
uniform highp sampler2D uDepth;
#endif
uniform int uColumns;
uniform vec2 uOrigin;
uniform vec2 uStep;
uniform vec2 uZMap;
uniform vec2 uTexScale;
uniform mat4 uViewProj;
out vec2 vTex;
#ifdef POSITION
out vec3 vPos;
#endif
void main() {
    int c = gl_VertexID % uColumns;
    int r = gl_VertexID / uColumns;
#ifdef DEPTH16
    float t = float(texelFetch(uDepth, ivec2(c, r), 0).r) / 65535.0;
#else
    float t = texelFetch(uDepth, ivec2(c, r), 0).r;
#endif
    vec3 p = vec3(uOrigin + vec2(float(c), float(r)) * uStep, uZMap.y + t * uZMap.x);
#ifdef POSITION
    vPos = p;
#endif
    vTex = (vec2(float(c), float(r)) + 0.5) * uTexScale;
    gl_Position = uViewProj * vec4(p, 1.0);
}
)";

// The surface's colour: from R'G'B' converted on the CPU (one texture fetch per fragment), or from
// the three Y'CbCr planes converted here (three fetches and the matrix per fragment).
constexpr const char *kSurfaceFs = R"(
precision highp float;
precision highp int;
#ifdef YUV
uniform sampler2D uY;
uniform sampler2D uU;
uniform sampler2D uV;
uniform mat3 uYuvToRgb;
uniform vec3 uYuvOffset;
#else
uniform sampler2D uRgb;
#endif
#ifdef ROW_PARITY
uniform int uRowParity;
#endif
in vec2 vTex;
#ifdef POSITION
in vec3 vPos;
#endif
out vec4 fragColor;
void main() {
#ifdef ROW_PARITY
    // Only the row-interleaved layout discards: elsewhere the shader has no discard, which lets the
    // rasterizer test depth before shading (early depth test).
    if ((int(gl_FragCoord.y) & 1) != uRowParity)
        discard;
#endif
#if defined(POSITION)
    fragColor = vec4(vPos, 1.0);
#elif defined(YUV)
    vec3 yuv = vec3(texture(uY, vTex).r, texture(uU, vTex).r, texture(uV, vTex).r);
    fragColor = vec4(clamp(uYuvToRgb * (yuv - uYuvOffset), 0.0, 1.0), 1.0);
#else
    fragColor = texture(uRgb, vTex);
#endif
}
)";

constexpr const char *kAvatarVs = R"(
precision highp float;
in vec3 aNormal;
uniform vec3 uCenter;
uniform float uRadius;
uniform mat4 uViewProj;
out vec3 vNormal;
void main() {
    vNormal = aNormal;
    gl_Position = uViewProj * vec4(uCenter + uRadius * aNormal, 1.0);
}
)";

constexpr const char *kAvatarFs = R"(
precision highp float;
precision highp int;
uniform vec4 uColor;
uniform int uRowParity;
in vec3 vNormal;
out vec4 fragColor;
void main() {
    if (uRowParity >= 0 && (int(gl_FragCoord.y) & 1) != uRowParity)
        discard;
    vec3 n = normalize(vNormal);
    vec3 l = normalize(vec3(-0.4, 0.6, 1.0));
    float diffuse = max(dot(n, l), 0.0);
    float specular = pow(max(dot(n, normalize(l + vec3(0.0, 0.0, 1.0))), 0.0), 32.0);
    fragColor = vec4(uColor.rgb * (0.25 + 0.75 * diffuse) + vec3(0.5 * specular), uColor.a);
}
)";

constexpr const char *kOsdVs = R"(
precision highp float;
in vec4 aVertex;
uniform vec2 uViewport;
out vec2 vUv;
void main() {
    vUv = aVertex.zw;
    gl_Position = vec4(aVertex.xy / uViewport * 2.0 - 1.0, 0.0, 1.0);
}
)";

constexpr const char *kOsdFs = R"(
precision highp float;
uniform sampler2D uFont;
uniform vec4 uColor;
uniform int uTextured;
in vec2 vUv;
out vec4 fragColor;
void main() {
    float a = uTextured != 0 ? texture(uFont, vUv).r : 1.0;
    fragColor = vec4(uColor.rgb, uColor.a * a);
}
)";

GLuint linkProgram(const char *vs, const char *fs, const char *defines)
{
    const std::string head = std::string("#version 300 es\n") + defines;
    return gl::linkProgram(head + vs, head + fs);
}

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
        glGenTextures(1, &name);
        glBindTexture(GL_TEXTURE_2D, name);
        glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, minMag);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, minMag);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
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
                GLenum format, GLenum type, int bytesPerSample)
{
    glBindTexture(GL_TEXTURE_2D, tex.name);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (stride % static_cast<std::size_t>(bytesPerSample) == 0) {
        glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(stride / static_cast<std::size_t>(bytesPerSample)));
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, format, type, data);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    } else {
        for (int r = 0; r < h; ++r)
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, r, w, 1, format, type,
                            data + static_cast<std::size_t>(r) * stride);
    }
}

struct SurfaceProgram {
    GLuint program = 0;
    GLint columns = -1, origin = -1, step = -1, zMap = -1, texScale = -1, viewProj = -1;
    GLint yuvToRgb = -1, yuvOffset = -1, rowParity = -1;
};

/// What the surface fragment shader outputs.
enum SurfaceVariant : int { kPositionOut = 0, kRgbOut = 1, kYuvOut = 2 };

/// \return true when GL_RENDERER names a software rasterizer (Mesa llvmpipe, softpipe, swrast),
/// where shading dominates and a CPU colour conversion is far cheaper than the per-fragment one.
bool softwareRasterizer()
{
    const auto *name = reinterpret_cast<const char *>(glGetString(GL_RENDERER));
    if (name == nullptr)
        return false;
    const std::string s(name);
    return s.find("llvmpipe") != std::string::npos || s.find("softpipe") != std::string::npos ||
           s.find("swrast") != std::string::npos;
}

} // namespace

struct StereoRenderer::Gl {
    // [depth16][SurfaceVariant][row parity]
    SurfaceProgram surface[2][3][2];
    GLuint avatarProgram = 0;
    GLint avCenter = -1, avRadius = -1, avViewProj = -1, avColor = -1, avRowParity = -1;
    GLuint osdProgram = 0;
    GLint osdViewport = -1, osdColor = -1, osdTextured = -1;
    GLuint surfaceVao = 0;
    GLuint indexBuffer = 0;
    GLsizei indexCount = 0;
    GLuint sphereVao = 0;
    GLuint sphereVbo = 0;
    GLuint sphereIbo = 0;
    GLsizei sphereIndexCount = 0;
    GLuint osdVao = 0;
    GLuint osdVbo = 0;
    Texture depth;
    Texture y, u, v;
    Texture rgb; ///< The colour frame as RGBA8 when converted on the CPU.
    Texture font;
    YuvConverter converter;
    std::vector<float> osdVertices;

    ~Gl()
    {
        for (auto &plane : surface)
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
        const GLuint buffers[] = {indexBuffer, sphereVbo, sphereIbo, osdVbo};
        glDeleteBuffers(4, buffers);
        depth.release();
        y.release();
        u.release();
        v.release();
        rgb.release();
        font.release();
    }
};

StereoRenderer::StereoRenderer(const RendererOptions &options) : options_(options) {}

StereoRenderer::~StereoRenderer() = default;

Result<std::unique_ptr<StereoRenderer>> StereoRenderer::create(const RendererOptions &options)
{
    if (!(options.box.width > 0.0) || !(options.box.depth > 0.0))
        return unexpected(Errc::InvalidArgument, "scene box sizes must be > 0");
    std::unique_ptr<StereoRenderer> r(new StereoRenderer(options));
    r->gl_ = std::make_unique<Gl>();
    Gl &g = *r->gl_;

    for (int variant = 0; variant < 12; ++variant) {
        {
            const int d16 = variant & 1;
            const int out = (variant >> 1) % 3;
            const int parity = variant / 6;
            std::string defines;
            if (d16 != 0)
                defines += "#define DEPTH16 1\n";
            if (out == kPositionOut)
                defines += "#define POSITION 1\n";
            if (out == kYuvOut)
                defines += "#define YUV 1\n";
            if (parity != 0)
                defines += "#define ROW_PARITY 1\n";
            SurfaceProgram &p = g.surface[d16][out][parity];
            p.program = linkProgram(kSurfaceVs, kSurfaceFs, defines.c_str());
            if (p.program == 0)
                return unexpected(Errc::NotSupported, "surface shader failed to build");
            glUseProgram(p.program);
            glUniform1i(glGetUniformLocation(p.program, "uDepth"), 0);
            glUniform1i(glGetUniformLocation(p.program, "uRgb"), 1);
            glUniform1i(glGetUniformLocation(p.program, "uY"), 1);
            glUniform1i(glGetUniformLocation(p.program, "uU"), 2);
            glUniform1i(glGetUniformLocation(p.program, "uV"), 3);
            p.columns = glGetUniformLocation(p.program, "uColumns");
            p.origin = glGetUniformLocation(p.program, "uOrigin");
            p.step = glGetUniformLocation(p.program, "uStep");
            p.zMap = glGetUniformLocation(p.program, "uZMap");
            p.texScale = glGetUniformLocation(p.program, "uTexScale");
            p.viewProj = glGetUniformLocation(p.program, "uViewProj");
            p.yuvToRgb = glGetUniformLocation(p.program, "uYuvToRgb");
            p.yuvOffset = glGetUniformLocation(p.program, "uYuvOffset");
            p.rowParity = glGetUniformLocation(p.program, "uRowParity");
        }
    }
    g.avatarProgram = linkProgram(kAvatarVs, kAvatarFs, "");
    g.osdProgram = linkProgram(kOsdVs, kOsdFs, "");
    if (g.avatarProgram == 0 || g.osdProgram == 0)
        return unexpected(Errc::NotSupported, "avatar or OSD shader failed to build");
    g.avCenter = glGetUniformLocation(g.avatarProgram, "uCenter");
    g.avRadius = glGetUniformLocation(g.avatarProgram, "uRadius");
    g.avViewProj = glGetUniformLocation(g.avatarProgram, "uViewProj");
    g.avColor = glGetUniformLocation(g.avatarProgram, "uColor");
    g.avRowParity = glGetUniformLocation(g.avatarProgram, "uRowParity");
    glUseProgram(g.osdProgram);
    glUniform1i(glGetUniformLocation(g.osdProgram, "uFont"), 0);
    g.osdViewport = glGetUniformLocation(g.osdProgram, "uViewport");
    g.osdColor = glGetUniformLocation(g.osdProgram, "uColor");
    g.osdTextured = glGetUniformLocation(g.osdProgram, "uTextured");

    // Surface: no attributes (gl_VertexID), one index buffer rewritten per depth frame.
    glGenVertexArrays(1, &g.surfaceVao);
    glGenBuffers(1, &g.indexBuffer);
    glBindVertexArray(g.surfaceVao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indexBuffer);

    // Avatar: a unit UV sphere (positions are the normals).
    {
        constexpr int kSlices = 24;
        constexpr int kStacks = 16;
        std::vector<float> verts;
        std::vector<std::uint16_t> idx;
        for (int i = 0; i <= kStacks; ++i) {
            const double phi = M_PI * i / kStacks;
            for (int j = 0; j <= kSlices; ++j) {
                const double theta = 2.0 * M_PI * j / kSlices;
                verts.push_back(static_cast<float>(std::sin(phi) * std::cos(theta)));
                verts.push_back(static_cast<float>(std::cos(phi)));
                verts.push_back(static_cast<float>(std::sin(phi) * std::sin(theta)));
            }
        }
        for (int i = 0; i < kStacks; ++i)
            for (int j = 0; j < kSlices; ++j) {
                const auto a = static_cast<std::uint16_t>(i * (kSlices + 1) + j);
                const auto b = static_cast<std::uint16_t>(a + kSlices + 1);
                idx.insert(idx.end(), {a, b, static_cast<std::uint16_t>(a + 1), static_cast<std::uint16_t>(a + 1), b,
                                       static_cast<std::uint16_t>(b + 1)});
            }
        g.sphereIndexCount = static_cast<GLsizei>(idx.size());
        glGenVertexArrays(1, &g.sphereVao);
        glGenBuffers(1, &g.sphereVbo);
        glGenBuffers(1, &g.sphereIbo);
        glBindVertexArray(g.sphereVao);
        glBindBuffer(GL_ARRAY_BUFFER, g.sphereVbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(float)), verts.data(),
                     GL_STATIC_DRAW);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.sphereIbo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint16_t)),
                     idx.data(), GL_STATIC_DRAW);
        const GLint loc = glGetAttribLocation(g.avatarProgram, "aNormal");
        glEnableVertexAttribArray(static_cast<GLuint>(loc));
        glVertexAttribPointer(static_cast<GLuint>(loc), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    }

    // OSD: glyph atlas (one row of 6×8 cells) and a stream vertex buffer of (x, y, u, v) quads.
    {
        const int w = detail::kGlyphCount * detail::kCellWidth;
        const int h = detail::kCellHeight;
        std::vector<std::uint8_t> atlas(static_cast<std::size_t>(w * h), 0);
        for (int gi = 0; gi < detail::kGlyphCount; ++gi)
            for (int row = 0; row < 7; ++row)
                for (int col = 0; col < 5; ++col)
                    if ((detail::kFont5x7[gi].rows[row] >> (4 - col)) & 1)
                        atlas[static_cast<std::size_t>(row * w + gi * detail::kCellWidth + col)] = 255;
        g.font.ensure(w, h, GL_R8, GL_NEAREST);
        uploadRows(g.font, atlas.data(), static_cast<std::size_t>(w), w, h, GL_RED, GL_UNSIGNED_BYTE, 1);
        glGenVertexArrays(1, &g.osdVao);
        glGenBuffers(1, &g.osdVbo);
        glBindVertexArray(g.osdVao);
        glBindBuffer(GL_ARRAY_BUFFER, g.osdVbo);
        const GLint loc = glGetAttribLocation(g.osdProgram, "aVertex");
        glEnableVertexAttribArray(static_cast<GLuint>(loc));
        glVertexAttribPointer(static_cast<GLuint>(loc), 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    }
    glBindVertexArray(0);

    // Until a colour frame arrives the surface is a neutral grey.
    const std::uint8_t grey[3] = {180, 128, 128};
    g.y.ensure(1, 1, GL_R8, GL_LINEAR);
    g.u.ensure(1, 1, GL_R8, GL_LINEAR);
    g.v.ensure(1, 1, GL_R8, GL_LINEAR);
    uploadRows(g.y, &grey[0], 1, 1, 1, GL_RED, GL_UNSIGNED_BYTE, 1);
    uploadRows(g.u, &grey[1], 1, 1, 1, GL_RED, GL_UNSIGNED_BYTE, 1);
    uploadRows(g.v, &grey[2], 1, 1, 1, GL_RED, GL_UNSIGNED_BYTE, 1);
    r->colorSpec_ = ColorSpec{YuvMatrix::Bt601, true};
    r->softwareRasterizer_ = softwareRasterizer();
    const std::uint8_t greyRgba[4] = {180, 180, 180, 255};
    g.rgb.ensure(1, 1, GL_RGBA8, GL_LINEAR);
    uploadRows(g.rgb, greyRgba, 4, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, 4);
    r->colorOnCpu_ = r->options_.colorConversion == ColorConversion::Cpu ||
                     (r->options_.colorConversion == ColorConversion::Auto && r->softwareRasterizer_);

    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::NotSupported, "GL error while creating the renderer");
    return r;
}

Result<void> StereoRenderer::setOptions(const RendererOptions &options)
{
    if (!(options.box.width > 0.0) || !(options.box.depth > 0.0))
        return unexpected(Errc::InvalidArgument, "scene box sizes must be > 0");
    if (options.mesh.tileSize < 2 || options.mesh.tolerance < 0.0)
        return unexpected(Errc::InvalidArgument, "mesh options out of range");
    options_ = options;
    return ok();
}

double StereoRenderer::stageEnd(platform::TimePoint start) const noexcept
{
    if (stageTiming_ == StageTiming::Finished)
        glFinish();
    return platform::toSeconds(clock_.now() - start) * 1e3;
}

Result<void> FramePrep::build(const haptics::DepthFrameView &depth, const hal::ImageView *color,
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
    if (auto r = mesh.build(depth, options); !r)
        return r;
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

Result<void> StereoRenderer::setDepth(const haptics::DepthFrameView &depth)
{
    const platform::TimePoint t = clock_.now();
    if (auto r = mesh_.build(depth, options_.mesh); !r)
        return r;
    return uploadDepth(depth, t);
}

void StereoRenderer::finish() const noexcept
{
    glFinish();
}

Result<void> StereoRenderer::setDepth(const haptics::DepthFrameView &depth, FramePrep &prep)
{
    // A mesh made under another block budget is taken: the budget follows the frame times and may
    // lag a frame behind (LodController).
    MeshOptions made = prep.meshOptions;
    made.maxBlocks = options_.mesh.maxBlocks;
    if (!prep.built() || prep.depthData != depth.data || !(made == options_.mesh))
        return setDepth(depth);
    const platform::TimePoint t = clock_.now();
    std::swap(mesh_, prep.mesh);
    return uploadDepth(depth, t);
}

Result<void> StereoRenderer::uploadDepth(const haptics::DepthFrameView &depth, platform::TimePoint start)
{
    platform::TimePoint t = start;
    // The haptic renderer's height field validates the frame and gives the mapping.
    haptics::HeightField field(options_.box);
    if (auto r = field.setFrames(depth, nullptr); !r)
        return r;
    mapping_ = SurfaceMapping::fromHeightField(field);
    depthFormat_ = depth.format;
    stageTimes_.mesh = stageEnd(t);

    t = clock_.now();
    Gl &g = *gl_;
    const bool d16 = depth.format == haptics::SampleFormat::Gray16;
    g.depth.ensure(depth.width, depth.height, d16 ? GL_R16UI : GL_R8, GL_NEAREST);
    uploadRows(g.depth, depth.data, depth.strideBytes, depth.width, depth.height,
               d16 ? GL_RED_INTEGER : GL_RED, d16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE, d16 ? 2 : 1);
    stageTimes_.depthUpload = stageEnd(t);

    t = clock_.now();
    const auto &idx = mesh_.indices();
    glBindVertexArray(g.surfaceVao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indexBuffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)),
                 idx.data(), GL_STREAM_DRAW);
    glBindVertexArray(0);
    g.indexCount = static_cast<GLsizei>(idx.size());
    haveDepth_ = true;
    stageTimes_.indexUpload = stageEnd(t);
    return ok();
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
        uploadRows(g.y, image.planes[0].data, static_cast<std::size_t>(image.planes[0].strideBytes), image.width,
                   image.height, GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.u, image.planes[1].data, static_cast<std::size_t>(image.planes[1].strideBytes), cw, ch,
                   GL_RED, GL_UNSIGNED_BYTE, 1);
        uploadRows(g.v, image.planes[2].data, static_cast<std::size_t>(image.planes[2].strideBytes), cw, ch,
                   GL_RED, GL_UNSIGNED_BYTE, 1);
    } else {
        const std::uint8_t neutral = 128;
        g.y.ensure(image.width, image.height, GL_R8, filter);
        g.u.ensure(1, 1, GL_R8, filter);
        g.v.ensure(1, 1, GL_R8, filter);
        uploadRows(g.y, image.planes[0].data, static_cast<std::size_t>(image.planes[0].strideBytes), image.width,
                   image.height, GL_RED, GL_UNSIGNED_BYTE, 1);
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
    uploadRows(g.rgb, reinterpret_cast<const std::uint8_t *>(rgba), static_cast<std::size_t>(width) * 4, width,
               height, GL_RGBA, GL_UNSIGNED_BYTE, 4);
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

Result<void> StereoRenderer::drawSurface(const EyeView &eye, SurfaceOutput output)
{
    if (!haveDepth_)
        return unexpected(Errc::InvalidState, "no depth frame to draw");
    Gl &g = *gl_;
    const bool d16 = depthFormat_ == haptics::SampleFormat::Gray16;
    const int variant = output == SurfaceOutput::Position ? kPositionOut : colorOnCpu_ || colorFromDmaBuf_ ? kRgbOut : kYuvOut;
    const SurfaceProgram &p = g.surface[d16 ? 1 : 0][variant][eye.rowParity >= 0 ? 1 : 0];
    glViewport(eye.viewport.x, eye.viewport.y, eye.viewport.width, eye.viewport.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(p.program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.depth.name);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, variant == kRgbOut ? (colorFromDmaBuf_ ? dmabuf_->texture() : g.rgb.name) : g.y.name);
    if (variant == kYuvOut) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, g.u.name);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, g.v.name);
    }
    glActiveTexture(GL_TEXTURE0);
    const SurfaceMapping &m = mapping_;
    glUniform1i(p.columns, m.columns);
    glUniform2f(p.origin, static_cast<float>(m.x0), static_cast<float>(m.y0));
    glUniform2f(p.step, static_cast<float>(m.dx), static_cast<float>(m.dy));
    glUniform2f(p.zMap, static_cast<float>(m.dz), static_cast<float>(m.z0));
    glUniform2f(p.texScale, 1.0f / static_cast<float>(m.columns), 1.0f / static_cast<float>(m.rows));
    const glm::mat4 viewProj = eye.projection * eye.view;
    glUniformMatrix4fv(p.viewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    if (variant == kYuvOut) {
        const YuvToRgb conv = yuvToRgb(colorSpec_);
        glUniformMatrix3fv(p.yuvToRgb, 1, GL_FALSE, glm::value_ptr(conv.matrix));
        glUniform3fv(p.yuvOffset, 1, glm::value_ptr(conv.offset));
    }
    if (eye.rowParity >= 0)
        glUniform1i(p.rowParity, eye.rowParity);
    glBindVertexArray(g.surfaceVao);
    glDrawElements(GL_TRIANGLES, g.indexCount, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while drawing the surface");
    return ok();
}

void StereoRenderer::drawAvatar(const EyeView &eye)
{
    if (!avatar_.visible)
        return;
    Gl &g = *gl_;
    glUseProgram(g.avatarProgram);
    const glm::mat4 viewProj = eye.projection * eye.view;
    glUniformMatrix4fv(g.avViewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    glUniform1i(g.avRowParity, eye.rowParity);
    glBindVertexArray(g.sphereVao);
    // The HIP, when it has sunk below the surface away from the proxy: a faint smaller sphere seen
    // through the surface; drawn first so the opaque proxy sphere covers it where they overlap.
    if (glm::length(avatar_.proxy - avatar_.hip) > avatar_.separation) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
        glUniform3f(g.avCenter, static_cast<float>(avatar_.hip.x), static_cast<float>(avatar_.hip.y),
                    static_cast<float>(avatar_.hip.z));
        glUniform1f(g.avRadius, static_cast<float>(0.6 * avatar_.radius));
        glUniform4f(g.avColor, 0.4f, 0.8f, 1.0f, 0.35f);
        glDisable(GL_DEPTH_TEST); // seen through the surface it is under
        glDrawElements(GL_TRIANGLES, g.sphereIndexCount, GL_UNSIGNED_SHORT, nullptr);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
    }
    // The proxy: an opaque lit sphere resting on the surface.
    glUniform3f(g.avCenter, static_cast<float>(avatar_.proxy.x), static_cast<float>(avatar_.proxy.y),
                static_cast<float>(avatar_.proxy.z));
    glUniform1f(g.avRadius, static_cast<float>(avatar_.radius));
    glUniform4f(g.avColor, 0.95f, 0.75f, 0.2f, 1.0f);
    glDrawElements(GL_TRIANGLES, g.sphereIndexCount, GL_UNSIGNED_SHORT, nullptr);
    glBindVertexArray(0);
}

void StereoRenderer::drawOsd(const Viewport &vp)
{
    if (!osd_.visible)
        return;
    Gl &g = *gl_;
    const int scale = std::max(1, vp.height / 240);
    const float cw = static_cast<float>(detail::kCellWidth * scale);
    const float ch = static_cast<float>(detail::kCellHeight * scale);
    const float margin = static_cast<float>(6 * scale);
    const float atlasW = static_cast<float>(detail::kGlyphCount * detail::kCellWidth);
    const float vh = static_cast<float>(vp.height);

    const auto quad = [&](float x0, float y0, float x1, float y1, float u0, float v0, float u1, float v1) {
        const float q[] = {x0, y0, u0, v1, x1, y0, u1, v1, x1, y1, u1, v0,
                           x0, y0, u0, v1, x1, y1, u1, v0, x0, y1, u0, v0};
        g.osdVertices.insert(g.osdVertices.end(), std::begin(q), std::end(q));
    };
    const auto text = [&](const std::string &s, float x, float yTop) {
        for (const char c : s) {
            const float u0 = static_cast<float>(detail::glyphIndex(c) * detail::kCellWidth) / atlasW;
            const float u1 = u0 + static_cast<float>(detail::kCellWidth) / atlasW;
            quad(x, yTop - ch, x + cw, yTop, u0, 0.0f, u1, 1.0f);
            x += cw;
        }
    };
    const auto flush = [&](bool textured, float r, float gr, float b, float a) {
        if (g.osdVertices.empty())
            return;
        glUniform1i(g.osdTextured, textured ? 1 : 0);
        glUniform4f(g.osdColor, r, gr, b, a);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g.osdVertices.size() * sizeof(float)),
                     g.osdVertices.data(), GL_STREAM_DRAW);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(g.osdVertices.size() / 4));
        g.osdVertices.clear();
    };

    glViewport(vp.x, vp.y, vp.width, vp.height);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(g.osdProgram);
    glUniform2f(g.osdViewport, static_cast<float>(vp.width), vh);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.font.name);
    glBindVertexArray(g.osdVao);
    glBindBuffer(GL_ARRAY_BUFFER, g.osdVbo);

    const std::string haptics = osd_.hapticsOn ? "HAPTICS ON" : "HAPTICS OFF";
    const std::size_t chars = std::max(osd_.status.size(), haptics.size());
    const float barW = std::min(static_cast<float>(vp.width) * 0.4f, 12.0f * cw);
    const float panelW = std::max(static_cast<float>(chars) * cw, barW) + 2.0f * margin;
    const float panelH = 3.0f * ch + 3.0f * margin;
    // Translucent panel, then text, then the force bar (frame + fill from green to red).
    quad(margin, vh - margin - panelH, margin + panelW, vh - margin, 0, 0, 0, 0);
    flush(false, 0.0f, 0.0f, 0.0f, 0.5f);
    float y = vh - 2.0f * margin;
    text(osd_.status, 2.0f * margin, y);
    flush(true, 1.0f, 1.0f, 1.0f, 1.0f);
    y -= ch + 0.5f * margin;
    text(haptics, 2.0f * margin, y);
    if (osd_.hapticsOn)
        flush(true, 0.4f, 1.0f, 0.4f, 1.0f);
    else
        flush(true, 0.6f, 0.6f, 0.6f, 1.0f);
    y -= ch + 0.5f * margin;
    const float x0 = 2.0f * margin;
    quad(x0, y - 0.6f * ch, x0 + barW, y, 0, 0, 0, 0);
    flush(false, 0.3f, 0.3f, 0.3f, 0.8f);
    const double frac = osd_.maxForce > 0.0 ? std::clamp(osd_.force / osd_.maxForce, 0.0, 1.0) : 0.0;
    if (frac > 0.0) {
        quad(x0, y - 0.6f * ch, x0 + barW * static_cast<float>(frac), y, 0, 0, 0, 0);
        flush(false, static_cast<float>(frac), static_cast<float>(1.0 - frac), 0.1f, 1.0f);
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

Result<void> StereoRenderer::render(const RenderTarget &target)
{
    if (!haveDepth_)
        return unexpected(Errc::InvalidState, "no depth frame to draw");
    platform::TimePoint t = clock_.now();
    target.bind();
    glViewport(0, 0, target.width(), target.height());
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(options_.background.r, options_.background.g, options_.background.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    stageTimes_.clear = stageEnd(t);
    int count = 0;
    const auto eyes = eyeViews(options_.mode, options_.stereo, target.width(), target.height(),
                               mapping_.width(), mapping_.height(), options_.box.depth, count);
    stageTimes_.eye[1] = 0.0;
    double overlay = 0.0;
    for (int i = 0; i < count; ++i) {
        const EyeView &eye = eyes[static_cast<std::size_t>(i)];
        t = clock_.now();
        if (i > 0 && options_.mode == StereoMode::Anaglyph)
            glClear(GL_DEPTH_BUFFER_BIT);
        glColorMask((eye.colorMask & 1) != 0, (eye.colorMask & 2) != 0, (eye.colorMask & 4) != 0, GL_TRUE);
        if (auto r = drawSurface(eye, SurfaceOutput::Color); !r)
            return r;
        stageTimes_.eye[i] = stageEnd(t);
        t = clock_.now();
        drawAvatar(eye);
        overlay += stageEnd(t);
    }
    t = clock_.now();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (options_.mode == StereoMode::SideBySide || options_.mode == StereoMode::TopAndBottom) {
        for (int i = 0; i < count; ++i)
            drawOsd(eyes[static_cast<std::size_t>(i)].viewport);
    } else {
        drawOsd(Viewport{0, 0, target.width(), target.height()});
    }
    stageTimes_.overlay = overlay + stageEnd(t);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while rendering a frame");
    return ok();
}

} // namespace depthtouch::render
