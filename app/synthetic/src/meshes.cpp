#include "meshes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace depthtouch::synthetic {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// A smooth bump: amplitude \a a at centre \a c, Gaussian widths \a s per axis (metres).
struct Bump {
    glm::vec3 c;
    glm::vec3 s;
    float a;
};

// The face, in the head frame (z out of the face). Amplitudes push the surface along its radius.
constexpr Bump kFaceBumps[] = {
    {{0.0f, 0.012f, 0.088f}, {0.007f, 0.022f, 0.03f}, 0.010f},    // nose bridge
    {{0.0f, -0.016f, 0.088f}, {0.011f, 0.011f, 0.03f}, 0.024f},   // nose tip
    {{0.011f, -0.022f, 0.085f}, {0.007f, 0.006f, 0.03f}, 0.008f}, // nostril wings
    {{-0.011f, -0.022f, 0.085f}, {0.007f, 0.006f, 0.03f}, 0.008f},
    {{0.030f, 0.032f, 0.075f}, {0.018f, 0.006f, 0.03f}, 0.006f}, // brows
    {{-0.030f, 0.032f, 0.075f}, {0.018f, 0.006f, 0.03f}, 0.006f},
    {{0.030f, 0.016f, 0.078f}, {0.013f, 0.008f, 0.03f}, -0.007f}, // eye sockets
    {{-0.030f, 0.016f, 0.078f}, {0.013f, 0.008f, 0.03f}, -0.007f},
    {{0.030f, 0.016f, 0.078f}, {0.008f, 0.005f, 0.03f}, 0.005f}, // eyeballs under the lids
    {{-0.030f, 0.016f, 0.078f}, {0.008f, 0.005f, 0.03f}, 0.005f},
    {{0.046f, -0.004f, 0.062f}, {0.018f, 0.014f, 0.03f}, 0.005f}, // cheekbones
    {{-0.046f, -0.004f, 0.062f}, {0.018f, 0.014f, 0.03f}, 0.005f},
    {{0.0f, -0.041f, 0.080f}, {0.017f, 0.005f, 0.03f}, 0.006f}, // upper lip
    {{0.0f, -0.052f, 0.078f}, {0.015f, 0.005f, 0.03f}, 0.007f}, // lower lip
    {{0.0f, -0.0465f, 0.080f}, {0.019f, 0.0015f, 0.03f}, -0.003f}, // mouth line
    {{0.0f, -0.076f, 0.060f}, {0.018f, 0.013f, 0.03f}, 0.008f},    // chin
    {{0.070f, 0.004f, -0.008f}, {0.012f, 0.021f, 0.012f}, 0.013f}, // ears
    {{-0.070f, 0.004f, -0.008f}, {0.012f, 0.021f, 0.012f}, 0.013f},
};

float bumps(const glm::vec3 &p) noexcept
{
    float sum = 0.0f;
    for (const Bump &b : kFaceBumps) {
        const glm::vec3 d = (p - b.c) / b.s;
        sum += b.a * std::exp(-0.5f * glm::dot(d, d));
    }
    return sum;
}

/// The head surface in direction \a dir (unit).
glm::vec3 headPoint(const glm::vec3 &dir) noexcept
{
    constexpr glm::vec3 kRadii{0.070f, 0.10f, 0.09f};
    const glm::vec3 q = dir / kRadii;
    const float r0 = 1.0f / std::sqrt(glm::dot(q, q));
    glm::vec3 p = dir * r0;
    // Narrower jaw and a flatter back of the head.
    const float jaw = std::clamp(-p.y / 0.10f, 0.0f, 1.0f);
    p.x *= 1.0f - 0.25f * jaw * jaw;
    if (p.z < 0.0f)
        p.z *= 0.92f;
    const float r = glm::length(p);
    return dir * (r + bumps(p));
}

/// Direction of ring \a i (0 = top) and segment \a j (0 = back of the head, turning through +x).
glm::vec3 ringDirection(int i, int rings, int j, int segments) noexcept
{
    const float theta = kPi * static_cast<float>(i) / static_cast<float>(rings);
    const float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

/// A closed surface of revolution-like topology: (rings + 1) × segments vertices, columns wrapping
/// around (no seam), from the point function \a f(i, j).
template <class F> MeshData makeClosedGrid(int rings, int segments, F f)
{
    MeshData m;
    const auto cols = static_cast<std::uint32_t>(segments);
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j)
            m.positions.push_back(f(i, j));
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(rings); ++i) {
        for (std::uint32_t j = 0; j < cols; ++j) {
            const std::uint32_t a = i * cols + j;
            const std::uint32_t b = i * cols + (j + 1) % cols;
            const std::uint32_t c = (i + 1) * cols + j;
            const std::uint32_t d = (i + 1) * cols + (j + 1) % cols;
            m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    }
    return m;
}

/// Area-weighted vertex normals from the triangles (counter-clockwise seen from outside).
void computeNormals(MeshData &m) noexcept
{
    m.normals.assign(m.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::vec3 &p0 = m.positions[m.indices[t]];
        const glm::vec3 &p1 = m.positions[m.indices[t + 1]];
        const glm::vec3 &p2 = m.positions[m.indices[t + 2]];
        const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
        for (std::size_t k = 0; k < 3; ++k)
            m.normals[m.indices[t + k]] += n;
    }
    for (glm::vec3 &n : m.normals) {
        const float len = glm::length(n);
        n = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
    }
}

} // namespace

MeshData makeHead(int rings, int segments)
{
    MeshData m = makeClosedGrid(rings, segments, [&](int i, int j) {
        return headPoint(ringDirection(i, rings, j, segments));
    });
    computeNormals(m);
    return m;
}

MeshData makeSphere(int rings, int segments)
{
    MeshData m = makeClosedGrid(rings, segments,
                                [&](int i, int j) { return ringDirection(i, rings, j, segments); });
    m.normals = m.positions; // exact on a unit sphere
    return m;
}

MeshData makeBust(int rings, int segments)
{
    // Profile: radius as a function of height, a neck flaring into shoulders (elliptical section,
    // deeper than wide at the neck, wider than deep at the shoulders).
    MeshData m = makeClosedGrid(rings, segments, [&](int i, int j) {
        const float t = static_cast<float>(i) / static_cast<float>(rings); // 0 top .. 1 bottom
        const float y = 0.02f - 0.26f * t;
        const float flare = std::clamp((t - 0.30f) / 0.50f, 0.0f, 1.0f);
        const float s = flare * flare * (3.0f - 2.0f * flare);
        const float rx = 0.042f + (0.19f - 0.042f) * s;
        const float rz = 0.046f + (0.10f - 0.046f) * s;
        const float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
        return glm::vec3(rx * std::sin(phi), y, -0.012f - rz * std::cos(phi));
    });
    computeNormals(m);
    return m;
}

MeshData makeCurtain(float width, float height, float foldDepth, float foldPeriod, int columns,
                     int rows)
{
    MeshData m;
    for (int r = 0; r <= rows; ++r) {
        for (int c = 0; c <= columns; ++c) {
            const float x = width * (static_cast<float>(c) / static_cast<float>(columns) - 0.5f);
            const float y = height * (0.5f - static_cast<float>(r) / static_cast<float>(rows));
            const float k = 2.0f * kPi / foldPeriod;
            // Folds deepen towards the floor, as a hanging curtain's do.
            const float amp = foldDepth * (0.6f + 0.4f * (0.5f - y / height));
            const float z = amp * std::sin(k * x);
            const float dzdx = amp * k * std::cos(k * x);
            m.positions.emplace_back(x, y, z);
            m.normals.push_back(glm::normalize(glm::vec3(-dzdx, 0.0f, 1.0f)));
        }
    }
    const auto cols = static_cast<std::uint32_t>(columns + 1);
    for (std::uint32_t r = 0; r < static_cast<std::uint32_t>(rows); ++r) {
        for (std::uint32_t c = 0; c < static_cast<std::uint32_t>(columns); ++c) {
            const std::uint32_t a = r * cols + c;
            const std::uint32_t b = a + 1;
            const std::uint32_t d = a + cols;
            const std::uint32_t e = d + 1;
            m.indices.insert(m.indices.end(), {a, d, b, b, d, e});
        }
    }
    return m;
}

MeshData makeFloor(float width, float depth)
{
    MeshData m;
    const float hw = width / 2.0f;
    const float hd = depth / 2.0f;
    m.positions = {{-hw, 0.0f, -hd}, {hw, 0.0f, -hd}, {-hw, 0.0f, hd}, {hw, 0.0f, hd}};
    m.normals.assign(4, glm::vec3(0.0f, 1.0f, 0.0f));
    m.indices = {0, 2, 1, 1, 2, 3};
    return m;
}

} // namespace depthtouch::synthetic
