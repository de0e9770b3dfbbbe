#pragma once
/// \file
/// \brief The `mesh-bvh` baseline: a conventional renderer that, for every new depth frame, builds
/// the full triangle mesh (2·(W−1)·(H−1) triangles) and an axis-aligned bounding-box tree over it,
/// then answers collision queries through the tree (paper III: "not applicable ... requires the
/// construction of new bounding boxes for each frame"). Kept for comparison only; not on the player
/// path.
///
/// Sample-and-hold (the mesh is the current frame); no correction, no interpolation; force-jump
/// safety as configured. Thread-safety: thread-bound. Memory for the largest frame is taken at
/// construction; setFrames() rebuilds in place without allocating.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

class MeshBvhRenderer final : public HapticRenderer {
public:
    /// \param maxWidth, maxHeight largest frame accepted by setFrames() (≥ 2), pixels.
    /// Allocates ≈ 12·W·H + 44·(W−1)·(H−1) bytes (vertices, triangle indices, centroids, nodes).
    MeshBvhRenderer(const RendererConfig &config, int maxWidth, int maxHeight);

    /// \brief Rebuilds the mesh and the AABB tree from \a current (\a next is ignored).
    [[nodiscard]] Result<void> setFrames(const DepthFrameView &current,
                                         const DepthFrameView *next) noexcept override;
    HapticOutput update(const glm::dvec3 &hip, double t) noexcept override;
    void reset(const glm::dvec3 &hip) noexcept override;
    void setStiffness(double newtonsPerMetre) noexcept override
    {
        force_.setStiffness(newtonsPerMetre);
    }
    [[nodiscard]] Method method() const noexcept override { return Method::MeshBvh; }

    /// \return the number of tree nodes of the last build.
    [[nodiscard]] std::size_t nodeCount() const noexcept { return nodesUsed_; }

    /// \brief First downward crossing of \a p0 → \a p1 through the tree (exact segment–triangle
    /// tests). Its cost figures count tree nodes, not grid cells: cellsVisited is every node taken
    /// from the walk's stack (the root, and both children of each inner node whose box the segment
    /// meets), cellsTested every triangle tested exactly (those of the leaves whose box it meets).
    [[nodiscard]] Crossing firstCrossingBvh(const glm::dvec3 &p0,
                                            const glm::dvec3 &p1) const noexcept;

    /// Grid-surface view of the built mesh (vertex positions as stored), for the proxy solver.
    class MeshSurface {
    public:
        explicit MeshSurface(const MeshBvhRenderer &owner) noexcept : m_(owner) {}
        [[nodiscard]] int columns() const noexcept { return m_.w_; }
        [[nodiscard]] int rows() const noexcept { return m_.h_; }
        [[nodiscard]] double spacing() const noexcept { return m_.field_.spacing(); }
        [[nodiscard]] double xToColumn(double x) const noexcept { return m_.field_.xToColumn(x); }
        [[nodiscard]] double yToRow(double y) const noexcept { return m_.field_.yToRow(y); }
        [[nodiscard]] double columnToX(double u) const noexcept { return m_.field_.columnToX(u); }
        [[nodiscard]] double rowToY(double v) const noexcept { return m_.field_.rowToY(v); }
        [[nodiscard]] glm::dvec3 vertex(int c, int r) const noexcept
        {
            const std::size_t i =
                3 * (static_cast<std::size_t>(r) * static_cast<std::size_t>(m_.w_) +
                     static_cast<std::size_t>(c));
            return {m_.vertices_[i], m_.vertices_[i + 1], m_.vertices_[i + 2]};
        }
        [[nodiscard]] double vertexZ(int c, int r) const noexcept { return vertex(c, r).z; }

    private:
        const MeshBvhRenderer &m_;
    };

private:
    struct Node {
        float lo[3];
        float hi[3];
        std::uint32_t first; ///< Leaf: first triangle index; inner: left child (right = first + 1).
        std::uint32_t count; ///< Triangles in a leaf; 0 for an inner node.
    };
    void build() noexcept;
    TriangleId triangleOf(std::uint32_t index) const noexcept;

    RendererConfig config_;
    HeightField field_; ///< Only for the §3 mapping of the current frame.
    ForceStage force_;
    int maxW_;
    int maxH_;
    int w_ = 0;
    int h_ = 0;
    std::vector<double> vertices_;        ///< x, y, z per vertex, row-major.
    std::vector<std::uint32_t> triIndex_; ///< Triangle indices, ordered by the tree.
    std::vector<float> centroids_;        ///< x, y, z per triangle (build scratch).
    std::vector<Node> nodes_;
    std::size_t nodesUsed_ = 0;
    glm::dvec3 proxy_{};
    bool haveProxy_ = false;
};

} // namespace depthtouch::haptics
