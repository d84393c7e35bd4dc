// A plain indexed triangle mesh: the common currency between the meshers (octree, CGAL, VTK), the
// mesh file formats (mesh_io.h) and the comparison against the ray trace. Deliberately free of
// CGAL, OpenMesh and VTK types so that every module can use it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace iaa {

/// Vertices and triangles that index into them. Triangles are oriented: (a, b, c) counter-clockwise
/// seen from the side its normal (b - a) x (c - a) points to.
struct TriangleSoup {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  bool empty() const { return triangles.empty(); }
};

}  // namespace iaa
