#pragma once
/// \file
/// \brief The inside of SyntheticScene, private to dt_synthetic: the scene table's record, the
/// materials, meshes on the GPU and the Impl that holds the GL objects. The Impl's members live in
/// scene_gl.cpp (programs, framebuffers, backgrounds, read-back) and scene_shots.cpp (the head and
/// spheres shots); synthetic_scene.cpp holds the scene table and the public calls.
/// Needs a current GLES context. Thread-safety: the GL thread only.

#include <cstdint>
#include <vector>

#include <GLES3/gl3.h>
#include <glm/glm.hpp>

#include "depthtouch/synthetic/synthetic_scene.h"
#include "meshes.h"

namespace depthtouch::synthetic {

/// Which shots a scene shows.
enum class Kind : std::uint8_t { Head, Spheres, Cut };

struct SceneDef {
    SceneInfo info;
    Kind kind;
    float nearM; ///< Near clip plane = depth mapping near, metres.
    float farM;  ///< Far clip plane = depth mapping far, metres.
};

/// Material index of the lit shader.
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

/// \brief A mesh uploaded to the GPU (interleaved position and normal, 32-bit indices).
struct GpuMesh {
    GLuint vao = 0;
    GLuint vbo = 0;
    GLuint ibo = 0;
    GLsizei count = 0;
};

/// \return \a m uploaded into a new vertex array (attribute 0 position, 1 normal).
GpuMesh upload(const MeshData &m);

/// Deletes the GL objects of \a g and clears it.
void destroy(GpuMesh &g) noexcept;

/// \brief The GL objects and state of one SyntheticScene.
struct SyntheticScene::Impl {
    const SceneDef *def = nullptr;
    int width = 0;
    int height = 0;
    GLuint lit = 0;
    GLuint nearness = 0;
    struct {
        GLint model, viewProj, normalMatrix, material, haptic, tint, eye, keyPosition, keyColor,
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

} // namespace depthtouch::synthetic
