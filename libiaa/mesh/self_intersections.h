// Self-intersections of a triangle mesh, counted with CGAL's Polygon Mesh Processing. CGAL-free
// header; the function exists when IAA_HAVE_CGAL is defined.
#pragma once

#include <cstdint>

#include "mesh/triangle_soup.h"

namespace iaa {

/// The number of pairs of triangles that intersect other than along the edge or at the vertex
/// they share (CGAL::Polygon_mesh_processing::self_intersections, exact predicates). Triangles
/// that would make an edge non-manifold get their own copies of their vertices, so a pair of them
/// that only touches there counts too.
std::uint64_t count_self_intersections(const TriangleSoup& mesh);

}  // namespace iaa
