/// \file
/// \brief triangulate(): the only translation unit that includes CGAL (its headers are costly to
/// compile).

#include "depthtouch/depth/enhance.h"

#include <utility>
#include <vector>

#if DT_DEPTH_HAVE_CGAL
// GCC's optimiser reports a possible null dereference inside CGAL's Compact_container even though
// the headers are system headers; silence that one diagnostic for CGAL's code only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#pragma GCC diagnostic pop
#endif

namespace depthtouch::depth {

#if DT_DEPTH_HAVE_CGAL

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
} // namespace

Result<Mesh> triangulate(const std::vector<PixelPoint> &points, const Plane<float> &heights)
{
    if (points.size() < 3)
        return unexpected(Errc::InvalidArgument, "Triangulation needs at least three points");
    Mesh mesh;
    mesh.vertices = points;
    mesh.heights.reserve(points.size());
    std::vector<std::pair<Kernel::Point_2, std::uint32_t>> input;
    input.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const PixelPoint p = points[i];
        if (p.x < 0 || p.y < 0 || p.x >= heights.width || p.y >= heights.height)
            return unexpected(Errc::InvalidArgument, "Feature point outside the depth map");
        mesh.heights.push_back(heights.at(p.x, p.y));
        input.emplace_back(Kernel::Point_2(p.x, p.y), static_cast<std::uint32_t>(i));
    }

    try {
        Delaunay dt;
        // The range insert sorts the points spatially first (fast for large point sets).
        dt.insert(input.begin(), input.end());
        if (dt.number_of_vertices() != points.size())
            return unexpected(Errc::InvalidArgument, "Duplicate feature points");
        if (dt.dimension() < 2)
            return unexpected(Errc::InvalidArgument, "Feature points are collinear");
        mesh.triangles.reserve(static_cast<std::size_t>(dt.number_of_faces()));
        for (const auto face : dt.finite_face_handles())
            mesh.triangles.push_back(
                {face->vertex(0)->info(), face->vertex(1)->info(), face->vertex(2)->info()});
    } catch (const std::exception &) {
        return unexpected(Errc::OutOfResources, "Delaunay triangulation failed");
    }
    return mesh;
}

#else

Result<Mesh> triangulate(const std::vector<PixelPoint> &, const Plane<float> &)
{
    return unexpected(Errc::NotSupported, "Built without CGAL: no Delaunay triangulation");
}

#endif

} // namespace depthtouch::depth
