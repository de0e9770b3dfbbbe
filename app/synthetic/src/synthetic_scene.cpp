#include "depthtouch/synthetic/synthetic_scene.h"

#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <GLES3/gl3.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "depthtouch/platform/log.h"
#include "meshes.h"
#include "shaders.h"

DT_LOG_CATEGORY(Synthetic)

namespace depthtouch::synthetic {

namespace {

enum class Kind : std::uint8_t { Head, Spheres, Cut };

struct SceneDef {
    SceneInfo info;
    Kind kind;
    float nearM; ///< Near clip plane = depth mapping near, metres.
    float farM;  ///< Far clip plane = depth mapping far, metres.
};

constexpr SceneDef kScenes[] = {
    {{"head", "A lit, textured head turning and nodding in front of a curtain"},
     Kind::Head,
     0.5f,
     1.5f},
    {{"spheres", "Five textured spheres moving at different depths in a room"},
     Kind::Spheres,
     0.5f,
     3.0f},
    {{"cut", "Shots of head and spheres alternating every 2 s (scene cuts)"},
     Kind::Cut,
     0.5f,
     3.0f},
};

constexpr SceneInfo kSceneInfos[] = {kScenes[0].info, kScenes[1].info, kScenes[2].info};

constexpr double kShotSeconds = 2.0;
constexpr float kFovYDegrees = 28.0f;

enum Material : int {
    Skin = 0,
    Cloth = 1,
    Marble = 2,
    Paint = 3,
    Wood = 4,
    Plaster = 5,
    Rubber = 6,
    Bust = 7
};

glm::vec3 lin(float r, float g, float b)
{
    return {std::pow(r, 2.2f), std::pow(g, 2.2f), std::pow(b, 2.2f)};
}

struct GpuMesh {
    GLuint vao = 0;
    GLuint vbo = 0;
    GLuint ibo = 0;
    GLsizei count = 0;
};

GpuMesh upload(const MeshData &m)
{
    GpuMesh g;
    std::vector<float> interleaved;
    interleaved.reserve(m.positions.size() * 6);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const glm::vec3 &p = m.positions[i];
        const glm::vec3 &n = m.normals[i];
        interleaved.insert(interleaved.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
    }
    glGenVertexArrays(1, &g.vao);
    glGenBuffers(1, &g.vbo);
    glGenBuffers(1, &g.ibo);
    glBindVertexArray(g.vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                 interleaved.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(m.indices.size() * sizeof(std::uint32_t)),
                 m.indices.data(), GL_STATIC_DRAW);
    constexpr auto kStride = static_cast<GLsizei>(6 * sizeof(float));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, kStride, nullptr);
    glEnableVertexAttribArray(1);
    // GL takes the attribute offset as a pointer.
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, kStride,
                          reinterpret_cast<const void *>(3 * sizeof(float)));
    glBindVertexArray(0);
    g.count = static_cast<GLsizei>(m.indices.size());
    return g;
}

void destroy(GpuMesh &g) noexcept
{
    glDeleteVertexArrays(1, &g.vao);
    glDeleteBuffers(1, &g.vbo);
    glDeleteBuffers(1, &g.ibo);
    g = {};
}

GLuint compile(GLenum type, const char *source)
{
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint okFlag = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &okFlag);
    if (okFlag == 0) {
        std::array<char, 2048> log{};
        glGetShaderInfoLog(s, static_cast<GLsizei>(log.size()), nullptr, log.data());
        DT_LOG(Synthetic, Error, "Failed to compile a shader: %s", log.data());
        glDeleteShader(s);
        return 0;
    }
    return s;
}

GLuint link(const char *vertex, const char *fragment)
{
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
    if (vs == 0 || fs == 0) {
        glDeleteShader(vs);
        glDeleteShader(fs);
        return 0;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint okFlag = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &okFlag);
    if (okFlag == 0) {
        std::array<char, 2048> log{};
        glGetProgramInfoLog(p, static_cast<GLsizei>(log.size()), nullptr, log.data());
        DT_LOG(Synthetic, Error, "Failed to link a shader program: %s", log.data());
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

/// A sphere of the `spheres` scene: radius, material, tint, and a path base + amp·sin(ω t + φ).
struct SphereTrack {
    float radius;
    Material material;
    glm::vec3 tint;
    glm::vec3 base;
    glm::vec3 amplitude;
    glm::vec3 omega;
    glm::vec3 phase;
};

} // namespace

std::span<const SceneInfo> listScenes() noexcept
{
    return kSceneInfos;
}

struct SyntheticScene::Impl {
    const SceneDef *def = nullptr;
    int width = 0;
    int height = 0;
    GLuint lit = 0;
    GLuint nearness = 0;
    struct {
        GLint model, viewProj, normalMatrix, material, tint, eye, keyPosition, keyColor,
            fillDirection, fillColor, ambient, noise;
    } u{};
    GLint uDepth = -1;
    GLint uNear = -1;
    GLint uFar = -1;
    GpuMesh head, sphere, bust, curtain, floor, wall;
    GLuint fbo = 0;
    GLuint colorRb = 0;
    GLuint depthTex = 0;
    GLuint nearFbo = 0;
    GLuint nearRb = 0;
    GLuint emptyVao = 0;
    GLuint noiseTex = 0;
    /// The static part of a shot (curtain; floor and wall), rendered once: color + depth copied
    /// into the scene framebuffer before the moving objects are drawn. Lights and camera do not
    /// move, so it is the same every frame.
    struct Background {
        GLuint fbo = 0;
        GLuint color = 0;
        GLuint depth = 0;
    } headBackground, spheresBackground;
    std::vector<std::uint8_t> staging;

    ~Impl()
    {
        glDeleteProgram(lit);
        glDeleteProgram(nearness);
        for (GpuMesh *m : {&head, &sphere, &bust, &curtain, &floor, &wall})
            destroy(*m);
        glDeleteFramebuffers(1, &fbo);
        glDeleteFramebuffers(1, &nearFbo);
        glDeleteRenderbuffers(1, &colorRb);
        glDeleteRenderbuffers(1, &nearRb);
        glDeleteTextures(1, &depthTex);
        glDeleteVertexArrays(1, &emptyVao);
        glDeleteTextures(1, &noiseTex);
        for (Background *b : {&headBackground, &spheresBackground}) {
            glDeleteFramebuffers(1, &b->fbo);
            glDeleteRenderbuffers(1, &b->color);
            glDeleteRenderbuffers(1, &b->depth);
        }
    }

    Result<void> init();
    void draw(const GpuMesh &mesh, const glm::mat4 &model, Material material,
              const glm::vec3 &tint) const;
    void setLights(const glm::mat4 &viewProj, const glm::vec3 &eye, const glm::vec3 &key) const;
    void beginFrame() const;
    /// Draws the head shot at time \a t: its moving objects, or only its static ones.
    void drawHead(double t, bool staticPart) const;
    void drawSpheres(double t, bool staticPart) const;
    Result<void> makeBackground(Background &b, bool headShot);
    Result<void> readBack(GLuint framebuffer, const hal::ImageView &out, bool nearnessOut);
};

Result<void> SyntheticScene::Impl::init()
{
    lit = link(shaders::kLitVertex, shaders::kLitFragment);
    nearness = link(shaders::kQuadVertex, shaders::kNearnessFragment);
    if (lit == 0 || nearness == 0)
        return unexpected(Errc::NotSupported, "Synthetic scene shaders do not compile");
    u.model = glGetUniformLocation(lit, "uModel");
    u.viewProj = glGetUniformLocation(lit, "uViewProj");
    u.normalMatrix = glGetUniformLocation(lit, "uNormalMatrix");
    u.material = glGetUniformLocation(lit, "uMaterial");
    u.tint = glGetUniformLocation(lit, "uTint");
    u.eye = glGetUniformLocation(lit, "uEye");
    u.keyPosition = glGetUniformLocation(lit, "uKeyPosition");
    u.keyColor = glGetUniformLocation(lit, "uKeyColor");
    u.fillDirection = glGetUniformLocation(lit, "uFillDirection");
    u.fillColor = glGetUniformLocation(lit, "uFillColor");
    u.ambient = glGetUniformLocation(lit, "uAmbient");
    u.noise = glGetUniformLocation(lit, "uNoise");
    uDepth = glGetUniformLocation(nearness, "uDepth");
    uNear = glGetUniformLocation(nearness, "uNear");
    uFar = glGetUniformLocation(nearness, "uFar");

    if (def->kind != Kind::Spheres) {
        head = upload(makeHead(160, 200));
        bust = upload(makeBust(48, 96));
        curtain = upload(makeCurtain(1.4f, 0.9f, 0.035f, 0.22f, 280, 4));
    }
    if (def->kind != Kind::Head) {
        sphere = upload(makeSphere(48, 96));
        floor = upload(makeFloor(4.0f, 4.0f));
        wall = upload(makeCurtain(3.4f, 1.8f, 0.0f, 1.0f, 1, 1));
    }
    glGenVertexArrays(1, &emptyVao);

    // The noise texture of the procedural materials: fixed seed, so every run renders the same.
    constexpr int kNoiseSize = 32;
    std::vector<std::uint8_t> noiseBytes(kNoiseSize * kNoiseSize * kNoiseSize * 4);
    std::uint32_t state = 0x9e3779b9u;
    for (std::uint8_t &b : noiseBytes) {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        b = static_cast<std::uint8_t>(state >> 24);
    }
    glGenTextures(1, &noiseTex);
    glBindTexture(GL_TEXTURE_3D, noiseTex);
    glTexStorage3D(GL_TEXTURE_3D, 1, GL_RGBA8, kNoiseSize, kNoiseSize, kNoiseSize);
    glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, kNoiseSize, kNoiseSize, kNoiseSize, GL_RGBA,
                    GL_UNSIGNED_BYTE, noiseBytes.data());
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (const GLenum wrap : {GLenum{GL_TEXTURE_WRAP_S}, GLenum{GL_TEXTURE_WRAP_T}, GLenum{GL_TEXTURE_WRAP_R}})
        glTexParameteri(GL_TEXTURE_3D, wrap, GL_REPEAT);
    glBindTexture(GL_TEXTURE_3D, 0);

    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &colorRb);
    glBindRenderbuffer(GL_RENDERBUFFER, colorRb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenTextures(1, &depthTex);
    glBindTexture(GL_TEXTURE_2D, depthTex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colorRb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depthTex, 0);
    const GLenum sceneStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glGenFramebuffers(1, &nearFbo);
    glGenRenderbuffers(1, &nearRb);
    glBindRenderbuffer(GL_RENDERBUFFER, nearRb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, nearFbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, nearRb);
    const GLenum nearStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (sceneStatus != GL_FRAMEBUFFER_COMPLETE || nearStatus != GL_FRAMEBUFFER_COMPLETE) {
        DT_LOG(Synthetic, Error, "Failed to create the %dx%d scene framebuffers (0x%x, 0x%x)",
               width, height, sceneStatus, nearStatus);
        return unexpected(Errc::NotSupported, "Synthetic scene framebuffer incomplete");
    }
    staging.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    if (def->kind != Kind::Spheres)
        DT_TRY(makeBackground(headBackground, true));
    if (def->kind != Kind::Head)
        DT_TRY(makeBackground(spheresBackground, false));
    glUseProgram(0);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::NotSupported, "GL error while setting up a synthetic scene");
    return ok();
}

void SyntheticScene::Impl::draw(const GpuMesh &mesh, const glm::mat4 &model, Material material,
                                const glm::vec3 &tint) const
{
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(model)));
    glUniformMatrix4fv(u.model, 1, GL_FALSE, glm::value_ptr(model));
    glUniformMatrix3fv(u.normalMatrix, 1, GL_FALSE, glm::value_ptr(normalMatrix));
    glUniform1i(u.material, material);
    glUniform3fv(u.tint, 1, glm::value_ptr(tint));
    glBindVertexArray(mesh.vao);
    glDrawElements(GL_TRIANGLES, mesh.count, GL_UNSIGNED_INT, nullptr);
}

void SyntheticScene::Impl::setLights(const glm::mat4 &viewProj, const glm::vec3 &eye,
                                     const glm::vec3 &key) const
{
    glUniformMatrix4fv(u.viewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    glUniform3fv(u.eye, 1, glm::value_ptr(eye));
    glUniform3fv(u.keyPosition, 1, glm::value_ptr(key));
    glUniform3f(u.keyColor, 1.25f, 1.15f, 1.0f);
    glUniform3f(u.fillDirection, -0.7f, 0.15f, 0.6f);
    glUniform3f(u.fillColor, 0.16f, 0.19f, 0.26f);
    glUniform3f(u.ambient, 0.07f, 0.07f, 0.08f);
}

void SyntheticScene::Impl::beginFrame() const
{
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(lit);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, noiseTex);
    glUniform1i(u.noise, 1);
    glActiveTexture(GL_TEXTURE0);
}

Result<void> SyntheticScene::Impl::makeBackground(Background &b, bool headShot)
{
    glGenFramebuffers(1, &b.fbo);
    glGenRenderbuffers(1, &b.color);
    glGenRenderbuffers(1, &b.depth);
    glBindRenderbuffer(GL_RENDERBUFFER, b.color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, b.depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, b.fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, b.color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, b.depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return unexpected(Errc::NotSupported, "Synthetic background framebuffer incomplete");
    beginFrame();
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClearDepthf(1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (headShot)
        drawHead(0.0, true);
    else
        drawSpheres(0.0, true);
    return ok();
}

void SyntheticScene::Impl::drawHead(double t, bool staticPart) const
{
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const glm::mat4 proj =
        glm::perspective(glm::radians(kFovYDegrees), aspect, def->nearM, def->farM);
    const glm::vec3 eye(0.0f);
    const glm::mat4 view = glm::lookAt(eye, glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0, 1, 0));
    setLights(proj * view, eye, glm::vec3(0.45f, 0.45f, 0.05f));
    if (staticPart) {
        const glm::mat4 curtainModel =
            glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -1.25f));
        draw(curtain, curtainModel, Cloth, lin(0.36f, 0.44f, 0.55f));
        return;
    }

    // The head turns and nods about the top of the neck; frame 0 faces the camera.
    constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
    const auto ts = static_cast<float>(t);
    const float yaw = glm::radians(35.0f) * std::sin(kTwoPi * ts / 4.0f);
    const float pitch = glm::radians(12.0f) * std::sin(kTwoPi * ts / 2.5f);
    const glm::vec3 pivot(0.0f, -0.04f, -0.76f);
    glm::mat4 neck = glm::translate(glm::mat4(1.0f), pivot);
    neck = glm::rotate(neck, 0.25f * yaw, glm::vec3(0, 1, 0));
    glm::mat4 headModel = glm::rotate(neck, 0.75f * yaw, glm::vec3(0, 1, 0));
    headModel = glm::rotate(headModel, pitch, glm::vec3(1, 0, 0));
    headModel = glm::translate(headModel, glm::vec3(0.0f, 0.07f, 0.01f));

    draw(head, headModel, Skin, glm::vec3(1.0f));
    draw(bust, neck, Bust, lin(0.30f, 0.18f, 0.22f));
}

void SyntheticScene::Impl::drawSpheres(double t, bool staticPart) const
{
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const glm::mat4 proj =
        glm::perspective(glm::radians(kFovYDegrees + 12.0f), aspect, def->nearM, def->farM);
    const glm::vec3 eye(0.0f, 0.12f, 0.0f);
    const glm::mat4 view =
        glm::lookAt(eye, glm::vec3(0.0f, -0.05f, -1.5f), glm::vec3(0.0f, 1.0f, 0.0f));
    setLights(proj * view, eye, glm::vec3(0.8f, 1.2f, -0.4f));
    if (staticPart) {
        const glm::mat4 floorModel =
            glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -0.35f, -1.5f));
        draw(floor, floorModel, Wood, glm::vec3(1.0f));
        const glm::mat4 wallModel = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.50f, -2.6f));
        draw(wall, wallModel, Plaster, lin(0.85f, 0.82f, 0.74f));
        return;
    }

    static const SphereTrack kTracks[] = {
        {0.10f, Marble, lin(0.92f, 0.90f, 0.86f), {-0.35f, -0.10f, -1.25f}, {0.15f, 0.06f, 0.35f},
         {0.9f, 1.3f, 0.7f}, {0.0f, 0.5f, 1.0f}},
        {0.08f, Paint, lin(0.80f, 0.12f, 0.10f), {0.30f, 0.05f, -0.95f}, {0.12f, 0.10f, 0.20f},
         {1.1f, 0.8f, 0.9f}, {1.2f, 0.0f, 2.0f}},
        {0.14f, Marble, lin(0.45f, 0.65f, 0.50f), {0.15f, -0.08f, -1.95f}, {0.40f, 0.08f, 0.30f},
         {0.6f, 1.0f, 0.5f}, {2.0f, 1.0f, 0.3f}},
        {0.07f, Rubber, lin(0.15f, 0.30f, 0.75f), {-0.10f, 0.12f, -0.80f}, {0.20f, 0.05f, 0.08f},
         {1.4f, 1.7f, 1.2f}, {0.7f, 2.2f, 0.0f}},
        {0.12f, Paint, lin(0.85f, 0.65f, 0.20f), {-0.60f, 0.10f, -2.20f}, {0.20f, 0.12f, 0.10f},
         {0.7f, 0.9f, 0.8f}, {3.0f, 0.4f, 1.5f}},
    };
    const auto ts = static_cast<float>(t);
    for (const SphereTrack &s : kTracks) {
        const glm::vec3 c = s.base + s.amplitude * glm::sin(s.omega * ts + s.phase);
        glm::mat4 model = glm::translate(glm::mat4(1.0f), c);
        model = glm::rotate(model, 0.8f * ts * s.omega.x, glm::vec3(0.3f, 1.0f, 0.2f));
        model = glm::scale(model, glm::vec3(s.radius));
        draw(sphere, model, s.material, s.tint);
    }
}

Result<void> SyntheticScene::Impl::readBack(GLuint framebuffer, const hal::ImageView &out,
                                            bool nearnessOut)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, staging.data());
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "glReadPixels failed");
    const auto w = static_cast<std::size_t>(width);
    for (int y = 0; y < height; ++y) {
        // GL rows run bottom to top.
        const std::uint8_t *src = staging.data() + static_cast<std::size_t>(height - 1 - y) * w * 4;
        std::uint8_t *dst = out.row(0, y);
        if (!nearnessOut) {
            if (out.format == hal::PixelFormat::Rgba8) {
                std::memcpy(dst, src, w * 4);
            } else {
                for (std::size_t x = 0; x < w; ++x)
                    std::memcpy(dst + 3 * x, src + 4 * x, 3);
            }
        } else if (out.format == hal::PixelFormat::Gray16) {
            auto *d16 = reinterpret_cast<std::uint16_t *>(dst);
            for (std::size_t x = 0; x < w; ++x)
                d16[x] = static_cast<std::uint16_t>(src[4 * x] << 8 | src[4 * x + 1]);
        } else {
            for (std::size_t x = 0; x < w; ++x) {
                const unsigned v16 = static_cast<unsigned>(src[4 * x]) << 8 | src[4 * x + 1];
                dst[x] = static_cast<std::uint8_t>((v16 * 255u + 32767u) / 65535u);
            }
        }
    }
    return ok();
}

SyntheticScene::SyntheticScene(std::unique_ptr<Impl> impl, int width, int height, double fps)
    : impl_(std::move(impl)), width_(width), height_(height), fps_(fps)
{
}

SyntheticScene::~SyntheticScene() = default;

Result<std::unique_ptr<SyntheticScene>> SyntheticScene::create(std::string_view name, int width,
                                                               int height, double fps)
{
    const SceneDef *def = nullptr;
    for (const SceneDef &d : kScenes)
        if (name == d.info.name)
            def = &d;
    if (def == nullptr) {
        DT_LOG(Synthetic, Error, "Unknown synthetic scene '%.*s' (available: head, spheres, cut)",
               static_cast<int>(name.size()), name.data());
        return unexpected(Errc::InvalidArgument, "Unknown synthetic scene");
    }
    if (width < 16 || height < 16 || width > 4096 || height > 4096 || !(fps >= 1.0) ||
        fps > 1000.0)
        return unexpected(Errc::InvalidArgument, "Synthetic scene size or rate out of range");
    const auto *version = reinterpret_cast<const char *>(glGetString(GL_VERSION));
    if (version == nullptr || std::strncmp(version, "OpenGL ES 3", 11) != 0)
        return unexpected(Errc::InvalidState, "Synthetic scenes need a current OpenGL ES 3 context");

    GLint previousFbo = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previousFbo);
    auto impl = std::make_unique<Impl>();
    impl->def = def;
    impl->width = width;
    impl->height = height;
    const Result<void> r = impl->init();
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previousFbo));
    if (!r)
        return unexpected(r.error());
    return std::unique_ptr<SyntheticScene>(new SyntheticScene(std::move(impl), width, height, fps));
}

const char *SyntheticScene::name() const noexcept
{
    return impl_->def->info.name;
}
double SyntheticScene::nearMetres() const noexcept
{
    return static_cast<double>(impl_->def->nearM);
}
double SyntheticScene::farMetres() const noexcept
{
    return static_cast<double>(impl_->def->farM);
}

bool SyntheticScene::isCut(std::uint64_t frameIndex) const noexcept
{
    if (impl_->def->kind != Kind::Cut || frameIndex == 0)
        return false;
    const auto shot = static_cast<std::uint64_t>(std::llround(kShotSeconds * fps_));
    return frameIndex % (shot > 0 ? shot : 1) == 0;
}

Result<void> SyntheticScene::render(std::uint64_t frameIndex, const hal::ImageView &color,
                                    const hal::ImageView &nearness)
{
    const auto fits = [&](const hal::ImageView &v, hal::PixelFormat a, hal::PixelFormat b,
                          int bppA, int bppB) {
        if (v.empty())
            return true;
        const int bpp = v.format == a ? bppA : (v.format == b ? bppB : 0);
        return bpp > 0 && v.width == width_ && v.height == height_ &&
               v.planes[0].strideBytes >= width_ * bpp;
    };
    if (!fits(color, hal::PixelFormat::Rgb24, hal::PixelFormat::Rgba8, 3, 4))
        return unexpected(Errc::InvalidArgument, "Color output must be Rgb24/Rgba8 of scene size");
    if (!fits(nearness, hal::PixelFormat::Gray8, hal::PixelFormat::Gray16, 1, 2))
        return unexpected(Errc::InvalidArgument, "Nearness output must be Gray8/Gray16 of scene size");

    Impl &s = *impl_;
    GLint previousFbo = 0;
    GLint previousRead = 0;
    std::array<GLint, 4> previousViewport{};
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previousRead);
    glGetIntegerv(GL_VIEWPORT, previousViewport.data());

    const double t = static_cast<double>(frameIndex) / fps_;
    bool headShot = s.def->kind == Kind::Head;
    if (s.def->kind == Kind::Cut) {
        const auto shot = static_cast<std::uint64_t>(std::llround(kShotSeconds * fps_));
        headShot = (frameIndex / (shot > 0 ? shot : 1)) % 2 == 0;
    }
    // Start from the shot's static background (color and depth), then draw what moves.
    const Impl::Background &background = headShot ? s.headBackground : s.spheresBackground;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, background.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s.fbo);
    glDisable(GL_SCISSOR_TEST);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_,
                      GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
    s.beginFrame();
    if (headShot)
        s.drawHead(t, false);
    else
        s.drawSpheres(t, false);

    Result<void> r = ok();
    if (!nearness.empty()) {
        glBindFramebuffer(GL_FRAMEBUFFER, s.nearFbo);
        glDisable(GL_DEPTH_TEST);
        glUseProgram(s.nearness);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, s.depthTex);
        glUniform1i(s.uDepth, 0);
        glUniform1f(s.uNear, s.def->nearM);
        glUniform1f(s.uFar, s.def->farM);
        glBindVertexArray(s.emptyVao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindTexture(GL_TEXTURE_2D, 0);
        r = s.readBack(s.nearFbo, nearness, true);
    }
    if (r && !color.empty())
        r = s.readBack(s.fbo, color, false);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previousFbo));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previousRead));
    glViewport(previousViewport[0], previousViewport[1], previousViewport[2],
               previousViewport[3]);
    if (r && glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while rendering a synthetic frame");
    return r;
}

} // namespace depthtouch::synthetic
