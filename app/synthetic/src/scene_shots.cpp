#include <cmath>
#include <numbers>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene_impl.h"

// The synthetic scenes' shots: the head in front of its curtain and the spheres in their room.

namespace depthtouch::synthetic {

namespace {

constexpr float kFovYDegrees = 28.0f;

glm::vec3 lin(float r, float g, float b)
{
    return {std::pow(r, 2.2f), std::pow(g, 2.2f), std::pow(b, 2.2f)};
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
        {0.10f,
         Marble,
         lin(0.92f, 0.90f, 0.86f),
         {-0.35f, -0.10f, -1.25f},
         {0.15f, 0.06f, 0.35f},
         {0.9f, 1.3f, 0.7f},
         {0.0f, 0.5f, 1.0f}},
        {0.08f,
         Paint,
         lin(0.80f, 0.12f, 0.10f),
         {0.30f, 0.05f, -0.95f},
         {0.12f, 0.10f, 0.20f},
         {1.1f, 0.8f, 0.9f},
         {1.2f, 0.0f, 2.0f}},
        {0.14f,
         Marble,
         lin(0.45f, 0.65f, 0.50f),
         {0.15f, -0.08f, -1.95f},
         {0.40f, 0.08f, 0.30f},
         {0.6f, 1.0f, 0.5f},
         {2.0f, 1.0f, 0.3f}},
        {0.07f,
         Rubber,
         lin(0.15f, 0.30f, 0.75f),
         {-0.10f, 0.12f, -0.80f},
         {0.20f, 0.05f, 0.08f},
         {1.4f, 1.7f, 1.2f},
         {0.7f, 2.2f, 0.0f}},
        {0.12f,
         Paint,
         lin(0.85f, 0.65f, 0.20f),
         {-0.60f, 0.10f, -2.20f},
         {0.20f, 0.12f, 0.10f},
         {0.7f, 0.9f, 0.8f},
         {3.0f, 0.4f, 1.5f}},
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

} // namespace depthtouch::synthetic
