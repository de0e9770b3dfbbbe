#include "depthtouch/render/renderer.h"

#include <GLES3/gl3.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/render/gl_program.h"
#include "osd_font.h"
#include "renderer_gl.h"

// StereoRenderer's shaders and creation: the programs, the avatar sphere, the OSD atlas and the
// neutral colour shown until a frame arrives.

namespace depthtouch::render {

using gl::kPositionOut;
using gl::kYuvOut;
using gl::uploadRows;

namespace {

// The surface: vertex k of the W×H grid is sample (k mod W, k div W); no vertex buffer, the height
// comes from the depth texture (vertex texture fetch) and the placement from SurfaceMapping.
// With per-tile steps (MeshMode::Blocks, uTileShift > 0) a vertex on the border between two tiles
// (not a tile corner, not the grid's last row or column) snaps back along the border to the step of
// the coarser of the two (uTileLevel: log2 step per tile), as AdaptiveMesh's stitching does: the
// finer tile's triangles there collapse or fan to the coarse vertices, and no crack opens.
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
uniform int uTileShift;
uniform ivec2 uLast;
uniform highp usampler2D uTileLevel;
out vec2 vTex;
#ifdef POSITION
out vec3 vPos;
#endif
#ifdef HOLES
uniform float uHoleBelow;
out float vHole;
#endif
void main() {
    int c = gl_VertexID % uColumns;
    int r = gl_VertexID / uColumns;
    if (uTileShift > 0) {
        int mask = (1 << uTileShift) - 1;
        bool vertical = (c & mask) == 0 && c > 0 && c < uLast.x && r < uLast.y;
        bool horizontal = (r & mask) == 0 && r > 0 && r < uLast.y && c < uLast.x;
        if (vertical != horizontal) {
            ivec2 tile = ivec2(c, r) >> uTileShift;
            ivec2 other = vertical ? tile - ivec2(1, 0) : tile - ivec2(0, 1);
            int l = int(max(texelFetch(uTileLevel, tile, 0).r, texelFetch(uTileLevel, other, 0).r));
            if (vertical)
                r = (r >> l) << l;
            else
                c = (c >> l) << l;
        }
    }
#ifdef DEPTH16
    float t = float(texelFetch(uDepth, ivec2(c, r), 0).r) / 65535.0;
#else
    float t = texelFetch(uDepth, ivec2(c, r), 0).r;
#endif
#ifdef HOLES
    // 1 at a hole vertex (a sample below DepthFrameView::holeBelow), 0 elsewhere: any fragment of
    // a triangle with a hole vertex interpolates above 0 and is discarded.
#ifdef DEPTH16
    float raw = float(texelFetch(uDepth, ivec2(c, r), 0).r);
#else
    float raw = t * 255.0;
#endif
    vHole = raw < uHoleBelow - 0.5 ? 1.0 : 0.0;
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
#ifdef HOLES
in float vHole;
#endif
out vec4 fragColor;
void main() {
#ifdef HOLES
    if (vHole > 0.0)
        discard;
#endif
#ifdef ROW_PARITY
    // Only the row-interleaved layout (and a frame with holes) discards: elsewhere the shader has
    // no discard, which lets the rasterizer test depth before shading (early depth test).
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

void gl::uploadRows(const Texture &tex, const std::uint8_t *data, std::size_t stride, int w, int h,
                    GLenum format, GLenum type, int bytesPerSample)
{
    glBindTexture(GL_TEXTURE_2D, tex.name);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (stride % static_cast<std::size_t>(bytesPerSample) == 0) {
        glPixelStorei(GL_UNPACK_ROW_LENGTH,
                      static_cast<GLint>(stride / static_cast<std::size_t>(bytesPerSample)));
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, format, type, data);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    } else {
        for (int r = 0; r < h; ++r)
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, r, w, 1, format, type,
                            data + static_cast<std::size_t>(r) * stride);
    }
}

Result<void> StereoRenderer::Gl::buildSurfacePrograms(bool holes)
{
    for (int variant = 0; variant < 12; ++variant) {
        const int d16 = variant & 1;
        const int out = (variant >> 1) % 3;
        const int parity = variant / 6;
        std::string defines = holes ? "#define HOLES 1\n" : "";
        if (d16 != 0)
            defines += "#define DEPTH16 1\n";
        if (out == kPositionOut)
            defines += "#define POSITION 1\n";
        if (out == kYuvOut)
            defines += "#define YUV 1\n";
        if (parity != 0)
            defines += "#define ROW_PARITY 1\n";
        gl::SurfaceProgram &p = surface[holes ? 1 : 0][d16][out][parity];
        p.program = linkProgram(kSurfaceVs, kSurfaceFs, defines.c_str());
        if (p.program == 0)
            return unexpected(Errc::NotSupported, "surface shader failed to build");
        glUseProgram(p.program);
        glUniform1i(glGetUniformLocation(p.program, "uDepth"), 0);
        glUniform1i(glGetUniformLocation(p.program, "uRgb"), 1);
        glUniform1i(glGetUniformLocation(p.program, "uY"), 1);
        glUniform1i(glGetUniformLocation(p.program, "uU"), 2);
        glUniform1i(glGetUniformLocation(p.program, "uV"), 3);
        glUniform1i(glGetUniformLocation(p.program, "uTileLevel"), 4);
        p.tileShift = glGetUniformLocation(p.program, "uTileShift");
        p.last = glGetUniformLocation(p.program, "uLast");
        p.columns = glGetUniformLocation(p.program, "uColumns");
        p.origin = glGetUniformLocation(p.program, "uOrigin");
        p.step = glGetUniformLocation(p.program, "uStep");
        p.zMap = glGetUniformLocation(p.program, "uZMap");
        p.texScale = glGetUniformLocation(p.program, "uTexScale");
        p.viewProj = glGetUniformLocation(p.program, "uViewProj");
        p.yuvToRgb = glGetUniformLocation(p.program, "uYuvToRgb");
        p.yuvOffset = glGetUniformLocation(p.program, "uYuvOffset");
        p.rowParity = glGetUniformLocation(p.program, "uRowParity");
        p.holeBelow = glGetUniformLocation(p.program, "uHoleBelow");
    }
    return ok();
}

Result<void> StereoRenderer::Gl::buildOverlayPrograms()
{
    avatarProgram = linkProgram(kAvatarVs, kAvatarFs, "");
    osdProgram = linkProgram(kOsdVs, kOsdFs, "");
    if (avatarProgram == 0 || osdProgram == 0)
        return unexpected(Errc::NotSupported, "avatar or OSD shader failed to build");
    avCenter = glGetUniformLocation(avatarProgram, "uCenter");
    avRadius = glGetUniformLocation(avatarProgram, "uRadius");
    avViewProj = glGetUniformLocation(avatarProgram, "uViewProj");
    avColor = glGetUniformLocation(avatarProgram, "uColor");
    avRowParity = glGetUniformLocation(avatarProgram, "uRowParity");
    glUseProgram(osdProgram);
    glUniform1i(glGetUniformLocation(osdProgram, "uFont"), 0);
    osdViewport = glGetUniformLocation(osdProgram, "uViewport");
    osdColor = glGetUniformLocation(osdProgram, "uColor");
    osdTextured = glGetUniformLocation(osdProgram, "uTextured");
    return ok();
}

void StereoRenderer::Gl::buildSphere()
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
            idx.insert(idx.end(),
                       {a, b, static_cast<std::uint16_t>(a + 1), static_cast<std::uint16_t>(a + 1),
                        b, static_cast<std::uint16_t>(b + 1)});
        }
    sphereIndexCount = static_cast<GLsizei>(idx.size());
    glGenVertexArrays(1, &sphereVao);
    glGenBuffers(1, &sphereVbo);
    glGenBuffers(1, &sphereIbo);
    glBindVertexArray(sphereVao);
    glBindBuffer(GL_ARRAY_BUFFER, sphereVbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(float)),
                 verts.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, sphereIbo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint16_t)), idx.data(),
                 GL_STATIC_DRAW);
    const GLint loc = glGetAttribLocation(avatarProgram, "aNormal");
    glEnableVertexAttribArray(static_cast<GLuint>(loc));
    glVertexAttribPointer(static_cast<GLuint>(loc), 3, GL_FLOAT, GL_FALSE, 0, nullptr);
}

void StereoRenderer::Gl::buildOsd()
{
    const int w = detail::kGlyphCount * detail::kCellWidth;
    const int h = detail::kCellHeight;
    std::vector<std::uint8_t> atlas(static_cast<std::size_t>(w * h), 0);
    for (int gi = 0; gi < detail::kGlyphCount; ++gi)
        for (int row = 0; row < 7; ++row)
            for (int col = 0; col < 5; ++col)
                if ((detail::kFont5x7[gi].rows[row] >> (4 - col)) & 1)
                    atlas[static_cast<std::size_t>(row * w + gi * detail::kCellWidth + col)] = 255;
    font.ensure(w, h, GL_R8, GL_NEAREST);
    uploadRows(font, atlas.data(), static_cast<std::size_t>(w), w, h, GL_RED, GL_UNSIGNED_BYTE, 1);
    glGenVertexArrays(1, &osdVao);
    glGenBuffers(1, &osdVbo);
    glBindVertexArray(osdVao);
    glBindBuffer(GL_ARRAY_BUFFER, osdVbo);
    const GLint loc = glGetAttribLocation(osdProgram, "aVertex");
    glEnableVertexAttribArray(static_cast<GLuint>(loc));
    glVertexAttribPointer(static_cast<GLuint>(loc), 4, GL_FLOAT, GL_FALSE, 0, nullptr);
}

StereoRenderer::StereoRenderer(const RendererOptions &options) : options_(options) {}

StereoRenderer::~StereoRenderer() = default;

Result<std::unique_ptr<StereoRenderer>> StereoRenderer::create(const RendererOptions &options)
{
    if (!(options.box.width > 0.0) || !(options.box.depth > 0.0))
        return unexpected(Errc::InvalidArgument, "scene box sizes must be > 0");
    std::unique_ptr<StereoRenderer> r(new StereoRenderer(options));
    r->gl_ = std::make_unique<Gl>();
    Gl &g = *r->gl_;

    DT_TRY(g.buildSurfacePrograms(false)); // with holes: at the first frame that has some
    DT_TRY(g.buildOverlayPrograms());

    // Surface: no attributes (gl_VertexID); its index buffer is a static grid's (uploaded once
    // per frame size and step) or one of the two dynamic ones (meshes made per frame), bound at
    // each draw.
    glGenVertexArrays(1, &g.surfaceVao);
    glGenBuffers(2, g.dynamic.buffer);

    // Avatar: a unit UV sphere (positions are the normals).
    g.buildSphere();

    // OSD: glyph atlas (one row of 6×8 cells) and a stream vertex buffer of (x, y, u, v) quads.
    g.buildOsd();
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
    r->colorOnCpu_ =
        r->options_.colorConversion == ColorConversion::Cpu ||
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

} // namespace depthtouch::render
