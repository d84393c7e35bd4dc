// Numbers that describe any triangle mesh, whatever made it: size, topology (boundary and
// non-manifold edges, components, Euler characteristic, in total and per component with the genus
// of each closed one), geometry (area, enclosed volume), and how
// well it fits the surface (max |f| at vertices, vertices outside the guaranteed enclosure).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "enclose/octree.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa {

/// The topology of one connected component of a mesh.
struct ComponentTopology {
  std::uint64_t vertices = 0, edges = 0, triangles = 0;
  std::uint64_t boundary_edges = 0;      ///< edges of exactly one triangle
  std::uint64_t nonmanifold_edges = 0;   ///< edges of three or more triangles
  std::uint64_t inconsistent_edges = 0;  ///< two-triangle edges traversed the same way by both
  std::int64_t euler = 0;                ///< V - E + F
  /// (2 - euler) / 2 when the component is a closed, consistently oriented surface (every edge
  /// has two triangles that traverse it in opposite directions); -1 otherwise.
  std::int64_t genus = -1;
};

struct MeshReport {
  std::uint64_t vertices = 0;         ///< vertices used by some triangle
  std::uint64_t unused_vertices = 0;  ///< vertices no triangle uses
  std::uint64_t triangles = 0;
  std::uint64_t degenerate_triangles = 0;  ///< a repeated vertex index
  std::uint64_t edges = 0;
  std::uint64_t boundary_edges = 0;      ///< edges of exactly one triangle
  std::uint64_t nonmanifold_edges = 0;   ///< edges of three or more triangles
  std::uint64_t inconsistent_edges = 0;  ///< two-triangle edges traversed the same way by both
  std::uint64_t components = 0;          ///< connected through shared vertices
  std::int64_t euler = 0;                ///< V - E + F
  /// Per component, in the order of their smallest vertex index; the totals above are their sums.
  std::vector<ComponentTopology> component_topology;
  double area = 0;
  double volume = 0;     ///< signed volume (divergence theorem); meaningful for closed meshes
  double max_abs_f = 0;  ///< max |f| over the vertices (when a tape is given)
  std::uint64_t undefined_vertices = 0;  ///< f not finite there
  /// Vertices outside every leaf box of the enclosure (-1 when no enclosure was given).
  std::int64_t outside_enclosure = -1;
};

/// How exactly the coordinates handed to analyze_mesh are known; it sets how far outside a leaf
/// box a vertex may lie and still count as inside the enclosure.
enum class CoordinatePrecision {
  /// As the mesher computed them (double). A vertex the mesher put on a leaf face may miss the
  /// face by the few double roundings of the face's and the test's own arithmetic: the test
  /// allows 1e-9 of the bounds' size per axis, far above those roundings (~1e-16 relative) and
  /// below any leaf (2^-29 of the size at the deepest, depth 21 + refine 8).
  kDouble,
  /// Rounded to float, as a mesh file holding float coordinates gives them back: the true
  /// coordinate c lies within half a float gap of the stored value v, |c - v| <= 2^-24 |v| (plus
  /// 2^-150 below the normal range), which is allowed on top of the kDouble slack.
  kFloat,
};

/// Analyses a mesh. With a tape, evaluates f at every vertex; with an enclosure, counts vertices
/// that lie outside all of its leaves, within the tolerance `precision` stands for.
MeshReport analyze_mesh(const TriangleSoup& mesh, const Tape* tape = nullptr,
                        const Enclosure* enclosure = nullptr,
                        CoordinatePrecision precision = CoordinatePrecision::kDouble);

/// Throws iaa::Error when the mesh cannot be used: no triangles, a non-finite vertex coordinate,
/// or a triangle index out of range. `what` names the mesh in the message (a path).
void check_mesh(const TriangleSoup& mesh, const std::string& what);

}  // namespace iaa
