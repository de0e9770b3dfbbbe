#include <cmath>
#include <cstring>
#include <vector>

#include <GLES3/gl3.h>
#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "depthtouch/platform/log.h"
#include "depthtouch/render/gl_program.h"
#include "scene_impl.h"
#include "shaders.h"

DT_LOG_CATEGORY(Synthetic)

// The synthetic scenes' GL plumbing: meshes, programs, framebuffers, the static backgrounds and
// reading color and nearness back.

namespace depthtouch::synthetic {

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

Result<void> SyntheticScene::Impl::init()
{
    lit = render::gl::linkProgram(shaders::kLitVertex, shaders::kLitFragment);
    nearness = render::gl::linkProgram(shaders::kQuadVertex, shaders::kNearnessFragment);
    if (lit == 0 || nearness == 0)
        return unexpected(Errc::NotSupported, "Synthetic scene shaders do not compile");
    u.model = glGetUniformLocation(lit, "uModel");
    u.viewProj = glGetUniformLocation(lit, "uViewProj");
    u.normalMatrix = glGetUniformLocation(lit, "uNormalMatrix");
    u.haptic = glGetUniformLocation(lit, "uHaptic");
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
    for (const GLenum wrap :
         {GLenum{GL_TEXTURE_WRAP_S}, GLenum{GL_TEXTURE_WRAP_T}, GLenum{GL_TEXTURE_WRAP_R}})
        glTexParameteri(GL_TEXTURE_3D, wrap, GL_REPEAT);
    glBindTexture(GL_TEXTURE_3D, 0);

    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &colorRb);
    glBindRenderbuffer(GL_RENDERBUFFER, colorRb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    depthTex = render::gl::createTexture2D(GL_DEPTH_COMPONENT32F, width, height, GL_NEAREST);
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
    glUniform1i(u.haptic, 0);
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

} // namespace depthtouch::synthetic
