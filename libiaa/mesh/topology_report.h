// Topology of a triangle mesh per connected component: Euler characteristic, boundary edges and,
// for closed orientable manifold components, the genus. Complements mesh_report.h's totals.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/triangle_soup.h"

namespace iaa {

/// One component (connected through shared vertices).
struct ComponentTopology {
  std::uint64_t vertices = 0, edges = 0, triangles = 0;
  std::uint64_t boundary_edges = 0;     ///< edges of exactly one triangle
  std::uint64_t nonmanifold_edges = 0;  ///< edges of three or more triangles
  std::int64_t euler = 0;               ///< V - E + F
  /// (2 - euler) / 2 when the component is closed and every edge has two triangles (a closed
  /// surface, orientable when the mesher oriented it consistently); -1 otherwise.
  std::int64_t genus = -1;
};

struct TopologyReport {
  /// Components in the order of their smallest vertex index.
  std::vector<ComponentTopology> components;
};

/// Counts per component; vertices no triangle uses belong to none.
TopologyReport analyze_topology(const TriangleSoup& mesh);

}  // namespace iaa
