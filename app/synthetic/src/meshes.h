#pragma once
// CPU-side geometry of the synthetic scenes: triangle meshes with per-vertex normals, in metres.
// Pure (no GL); uploaded by synthetic_scene.cpp.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace depthtouch::synthetic {

struct MeshData {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::uint32_t> indices; ///< Triangles, counter-clockwise seen from outside.
};

/// \brief The head: an ellipsoid (half-axes 0.070 m wide, 0.10 m high, 0.09 m deep, narrowing to
/// the jaw) with smooth bumps for the nose, brows, eye sockets, cheekbones, lips, chin and ears.
/// Object frame: origin at the head centre, x right, y up, z out of the face (the nose tip is at
/// about (0, -0.018, 0.114)).
MeshData makeHead(int rings, int segments);

/// \brief A unit sphere (radius 1) around the origin.
MeshData makeSphere(int rings, int segments);

/// \brief A neck-and-shoulders body: a vertical tube (radius 0.042 m, from y = 0.02 m, inside the
/// head, down to -0.06 m) flaring into shoulders (half-width 0.19 m) down to y = -0.24 m. Origin at
/// the top of the neck (the pivot the head turns about).
MeshData makeBust(int rings, int segments);

/// \brief A rectangle in the x-y plane facing +z, \a width × \a height metres centred on the
/// origin, with vertical folds of wavelength \a foldPeriod whose amplitude deepens linearly from
/// 0.6 \a foldDepth (metres) at the top edge to \a foldDepth at the bottom, as a hanging curtain's.
MeshData makeCurtain(float width, float height, float foldDepth, float foldPeriod, int columns,
                     int rows);

/// \brief A flat rectangle in the x-z plane facing +y, \a width × \a depth metres, centred.
MeshData makeFloor(float width, float depth);

} // namespace depthtouch::synthetic
