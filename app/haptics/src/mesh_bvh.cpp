#include "depthtouch/haptics/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/proxy_solver.h"

namespace depthtouch::haptics {

namespace {

constexpr std::uint32_t kLeafSize = 4;
constexpr int kStackSize = 96;

std::size_t triangleCount(int w, int h) noexcept
{
    return 2u * static_cast<std::size_t>(w - 1) * static_cast<std::size_t>(h - 1);
}

} // namespace

MeshBvhRenderer::MeshBvhRenderer(const RendererConfig &config, int maxWidth, int maxHeight)
    : config_(config), field_(config.box), force_(config), maxW_(std::max(maxWidth, 2)),
      maxH_(std::max(maxHeight, 2))
{
    const std::size_t nVert = static_cast<std::size_t>(maxW_) * static_cast<std::size_t>(maxH_);
    const std::size_t nTri = triangleCount(maxW_, maxH_);
    vertices_.resize(3 * nVert);
    triIndex_.resize(nTri);
    centroids_.resize(3 * nTri);
    // Median splits down to leaves of ≤ kLeafSize (≥ 2 each, split of ≥ 5) give < nTri nodes.
    nodes_.resize(nTri + 1);
}

TriangleId MeshBvhRenderer::triangleOf(std::uint32_t index) const noexcept
{
    const std::uint32_t cell = index / 2;
    const auto cells = static_cast<std::uint32_t>(w_ - 1);
    return TriangleId{static_cast<int>(cell % cells), static_cast<int>(cell / cells),
                      static_cast<int>(index % 2)};
}

Result<void> MeshBvhRenderer::setFrames(const DepthFrameView &current,
                                        const DepthFrameView *) noexcept
{
    DT_TRY(current.validate());
    if (current.width > maxW_ || current.height > maxH_)
        return unexpected(Errc::InvalidArgument,
                          "depth frame larger than the renderer was built for");
    DT_TRY(field_.setFrames(current, nullptr));
    w_ = current.width;
    h_ = current.height;
    // The conventional path: materialise every vertex, then every triangle's box, then the tree.
    for (int r = 0; r < h_; ++r) {
        for (int c = 0; c < w_; ++c) {
            const glm::dvec3 v = field_.vertex(c, r);
            const std::size_t i = 3 * (static_cast<std::size_t>(r) * static_cast<std::size_t>(w_) +
                                       static_cast<std::size_t>(c));
            vertices_[i] = v.x;
            vertices_[i + 1] = v.y;
            vertices_[i + 2] = v.z;
        }
    }
    build();
    return ok();
}

void MeshBvhRenderer::build() noexcept
{
    const MeshSurface surf(*this);
    const auto n = static_cast<std::uint32_t>(triangleCount(w_, h_));
    for (std::uint32_t i = 0; i < n; ++i) {
        triIndex_[i] = i;
        glm::dvec3 v[3];
        triangleVertices(surf, triangleOf(i), v);
        const glm::dvec3 s = (v[0] + v[1] + v[2]) / 3.0;
        centroids_[3 * i] = static_cast<float>(s.x);
        centroids_[3 * i + 1] = static_cast<float>(s.y);
        centroids_[3 * i + 2] = static_cast<float>(s.z);
    }
    // Top-down: split each node at the median centroid along the widest centroid extent.
    nodesUsed_ = 1;
    nodes_[0].first = 0;
    nodes_[0].count = n;
    std::uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        Node &node = nodes_[stack[--top]];
        if (node.count <= kLeafSize || top + 2 > kStackSize)
            continue;
        float clo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                        std::numeric_limits<float>::max()};
        float chi[3] = {-clo[0], -clo[1], -clo[2]};
        for (std::uint32_t j = node.first; j < node.first + node.count; ++j) {
            for (std::uint32_t a = 0; a < 3; ++a) {
                const float cv = centroids_[3 * triIndex_[j] + a];
                clo[a] = std::min(clo[a], cv);
                chi[a] = std::max(chi[a], cv);
            }
        }
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (chi[a] - clo[a] > chi[axis] - clo[axis])
                axis = a;
        const std::uint32_t half = node.count / 2;
        std::uint32_t *first = triIndex_.data() + node.first;
        const float *cen = centroids_.data();
        const auto ax = static_cast<std::uint32_t>(axis);
        std::nth_element(first, first + half, first + node.count,
                         [cen, ax](std::uint32_t x, std::uint32_t y) {
                             return cen[3 * x + ax] < cen[3 * y + ax];
                         });
        const auto left = static_cast<std::uint32_t>(nodesUsed_);
        nodesUsed_ += 2;
        nodes_[left].first = node.first;
        nodes_[left].count = half;
        nodes_[left + 1].first = node.first + half;
        nodes_[left + 1].count = node.count - half;
        node.first = left;
        node.count = 0;
        stack[top++] = left;
        stack[top++] = left + 1;
    }
    // Bottom-up: children always have larger indices than their parent, so one reverse sweep fits
    // every leaf to its triangles and every inner node to its two children (O(n), not O(n log n)).
    // Float boxes, widened so rounding never loses a triangle.
    const double pad = 1e-6 * (config_.box.width + config_.box.depth);
    for (std::size_t k = nodesUsed_; k-- > 0;) {
        Node &node = nodes_[k];
        if (node.count == 0) {
            const Node &l = nodes_[node.first];
            const Node &r = nodes_[node.first + 1];
            for (int a = 0; a < 3; ++a) {
                node.lo[a] = std::min(l.lo[a], r.lo[a]);
                node.hi[a] = std::max(l.hi[a], r.hi[a]);
            }
            continue;
        }
        double lo[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                        std::numeric_limits<double>::max()};
        double hi[3] = {-lo[0], -lo[1], -lo[2]};
        for (std::uint32_t j = node.first; j < node.first + node.count; ++j) {
            glm::dvec3 v[3];
            triangleVertices(surf, triangleOf(triIndex_[j]), v);
            for (const glm::dvec3 &p : v) {
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], p[a]);
                    hi[a] = std::max(hi[a], p[a]);
                }
            }
        }
        for (int a = 0; a < 3; ++a) {
            node.lo[a] = static_cast<float>(lo[a] - pad);
            node.hi[a] = static_cast<float>(hi[a] + pad);
        }
    }
}

Crossing MeshBvhRenderer::firstCrossingBvh(const glm::dvec3 &p0,
                                           const glm::dvec3 &p1) const noexcept
{
    Crossing out;
    if (w_ < 2)
        return out;
    const MeshSurface surf(*this);
    const glm::dvec3 d = p1 - p0;
    double inv[3];
    for (int a = 0; a < 3; ++a)
        inv[a] = d[a] != 0.0 ? 1.0 / d[a] : std::numeric_limits<double>::infinity();
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node &node = nodes_[stack[--top]];
        ++out.cellsVisited;
        // Slab test of the segment against the node box.
        double t0 = 0.0;
        double t1 = std::min(1.0, best);
        bool miss = false;
        for (int a = 0; a < 3 && !miss; ++a) {
            const auto blo = static_cast<double>(node.lo[a]);
            const auto bhi = static_cast<double>(node.hi[a]);
            if (d[a] == 0.0) {
                miss = p0[a] < blo || p0[a] > bhi;
                continue;
            }
            double ta = (blo - p0[a]) * inv[a];
            double tb = (bhi - p0[a]) * inv[a];
            if (ta > tb)
                std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
            miss = t0 > t1;
        }
        if (miss)
            continue;
        if (node.count == 0) {
            if (top + 2 <= kStackSize) {
                stack[top++] = node.first;
                stack[top++] = node.first + 1;
            }
            continue;
        }
        for (std::uint32_t j = node.first; j < node.first + node.count; ++j) {
            ++out.cellsTested;
            keepNearerCrossing(surf, triangleOf(triIndex_[j]), p0, p1, 1e-9, best, out);
        }
    }
    if (out.hit)
        out.point = p0 + out.t * d;
    return out;
}

void MeshBvhRenderer::reset(const glm::dvec3 &hip) noexcept
{
    proxy_ = hip;
    haveProxy_ = true;
    force_.reset();
}

HapticOutput MeshBvhRenderer::update(const glm::dvec3 &hip, double t) noexcept
{
    HapticOutput out;
    out.hip = hip;
    glm::dvec3 proxy = hip;
    bool contact = false;
    const Crossing hit = firstCrossingBvh(haveProxy_ ? proxy_ : hip, hip);
    out.cellsVisited = hit.cellsVisited;
    out.cellsTested = hit.cellsTested;
    if (hit.hit) {
        const MeshSurface surf(*this);
        const ProxySolution sol = solveProxy(surf, hit.triangle, hip);
        out.proxySteps = sol.steps;
        const Crossing again = firstCrossingBvh(sol.point, hip);
        if (again.hit) {
            proxy = sol.point;
            contact = true;
            out.constraints = sol.constraints;
        }
    }
    double above = std::nan("");
    if (field_.contains(hip.x, hip.y))
        above = field_.heightAt(hip.x, hip.y);
    out.force = force_.apply(hip, proxy, contact, t, above, out.released);
    out.proxy = proxy;
    out.contact = contact;
    proxy_ = proxy;
    haveProxy_ = true;
    return out;
}

} // namespace depthtouch::haptics
