#include "depthtouch/synthetic/synthetic_scene.h"

#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>

#include <GLES3/gl3.h>

#include "depthtouch/platform/log.h"
#include "scene_impl.h"

DT_LOG_CATEGORY(Synthetic)

namespace depthtouch::synthetic {

namespace {

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

} // namespace

std::span<const SceneInfo> listScenes() noexcept
{
    return kSceneInfos;
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
    if (width < 16 || height < 16 || width > 4096 || height > 4096 || !(fps >= 1.0) || fps > 1000.0)
        return unexpected(Errc::InvalidArgument, "Synthetic scene size or rate out of range");
    const auto *version = reinterpret_cast<const char *>(glGetString(GL_VERSION));
    if (version == nullptr || std::strncmp(version, "OpenGL ES 3", 11) != 0)
        return unexpected(Errc::InvalidState,
                          "Synthetic scenes need a current OpenGL ES 3 context");

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
                                    const hal::ImageView &nearness, const hal::ImageView &material)
{
    const auto fits = [&](const hal::ImageView &v, hal::PixelFormat a, hal::PixelFormat b, int bppA,
                          int bppB) {
        if (v.empty())
            return true;
        const int bpp = v.format == a ? bppA : (v.format == b ? bppB : 0);
        return bpp > 0 && v.width == width_ && v.height == height_ &&
               v.planes[0].strideBytes >= width_ * bpp;
    };
    if (!fits(color, hal::PixelFormat::Rgb24, hal::PixelFormat::Rgba8, 3, 4))
        return unexpected(Errc::InvalidArgument, "Color output must be Rgb24/Rgba8 of scene size");
    if (!fits(nearness, hal::PixelFormat::Gray8, hal::PixelFormat::Gray16, 1, 2))
        return unexpected(Errc::InvalidArgument,
                          "Nearness output must be Gray8/Gray16 of scene size");
    if (!fits(material, hal::PixelFormat::Rgb24, hal::PixelFormat::Rgb24, 3, 3))
        return unexpected(Errc::InvalidArgument, "Material output must be Rgb24 of scene size");

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
    if (r && !material.empty()) {
        // The shot again, static part included, with each surface's material codes as colour;
        // where nothing is drawn, stiffness scale 1 without friction.
        glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
        s.beginFrame();
        glUniform1i(s.u.haptic, 1);
        glClearColor(64.0f / 255.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (headShot) {
            s.drawHead(t, true);
            s.drawHead(t, false);
        } else {
            s.drawSpheres(t, true);
            s.drawSpheres(t, false);
        }
        glUniform1i(s.u.haptic, 0);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        r = s.readBack(s.fbo, material, false);
    }
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previousFbo));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previousRead));
    glViewport(previousViewport[0], previousViewport[1], previousViewport[2], previousViewport[3]);
    if (r && glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while rendering a synthetic frame");
    return r;
}

} // namespace depthtouch::synthetic
