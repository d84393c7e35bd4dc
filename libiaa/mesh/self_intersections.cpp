// Self-intersections through CGAL PMP; see self_intersections.h. A translation unit of its own:
// CGAL's headers are slow to compile.
#include "mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <iterator>
#include <utility>
#include <vector>

#include "core/interval.h"

namespace iaa {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = SurfaceMesh::Face_index;
}  // namespace

std::uint64_t count_self_intersections(const TriangleSoup& soup) {
  NearestScope nearest;  // CGAL's filters manage the rounding mode from round-to-nearest
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> v;
  v.reserve(soup.vertices.size());
  for (const Vec3& p : soup.vertices) v.push_back(mesh.add_vertex({p.x, p.y, p.z}));
  for (const auto& t : soup.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    if (mesh.add_face(v[t[0]], v[t[1]], v[t[2]]) != SurfaceMesh::null_face()) continue;
    // A face the halfedge structure refuses (non-manifold) gets its own vertices.
    SurfaceMesh::Vertex_index c[3];
    for (int k = 0; k < 3; ++k) c[k] = mesh.add_vertex(mesh.point(v[t[std::size_t(k)]]));
    mesh.add_face(c[0], c[1], c[2]);
  }
  std::vector<std::pair<Face, Face>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  return pairs.size();
}

}  // namespace iaa
