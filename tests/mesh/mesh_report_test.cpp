// The mesh report's enclosure check: vertices on a bounds face whose coordinate is not exact in
// float (1.1) count as inside for the double-precision mesh, and for its float rounding when the
// report is told the coordinates are float; a vertex really outside is still counted.
#include "mesh/mesh_report.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/mesh_test_util.h"
#include "mesh/octree_mesher.h"

namespace iaa {
namespace {

// The plane z = 0.1 in bounds +-1.1: the mesh meets the four side faces x, y = +-1.1, where the
// float rounding of 1.1 (1.10000002384...) lies outside the bounds.
struct PlaneCase {
  Tape tape = Tape::parse("z - 0.1");
  Box3 bounds{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  Enclosure enc = test::local_enclose(tape, bounds, 4, 0);
  TriangleSoup mesh;
  std::uint64_t on_side_faces = 0;
  PlaneCase() {
    OctreeMeshSettings s;
    s.enclose.bounds = bounds;
    mesh = extract_mesh(tape, enc, s).soup;
    for (const Vec3& p : mesh.vertices) {
      if (std::fabs(p.x) == 1.1 || std::fabs(p.y) == 1.1) ++on_side_faces;
    }
  }
};

TriangleSoup rounded_to_float(TriangleSoup m) {
  for (Vec3& p : m.vertices) {
    for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(p[a]);
  }
  return m;
}

TEST(MeshReport, DoubleMeshOnTheBoundsIsInsideTheEnclosure) {
  const PlaneCase c;
  ASSERT_GT(c.on_side_faces, 8u);
  EXPECT_EQ(analyze_mesh(c.mesh, &c.tape, &c.enc).outside_enclosure, 0);
}

TEST(MeshReport, FloatCoordinatesAllowTheirRounding) {
  const PlaneCase c;
  const TriangleSoup f = rounded_to_float(c.mesh);
  // Read as exact, the float copy pokes out of the bounds on two of the four faces (float(1.1) >
  // 1.1, float(-1.1) < -1.1): the false count the float tolerance removes.
  EXPECT_GT(analyze_mesh(f, &c.tape, &c.enc, CoordinatePrecision::kDouble).outside_enclosure, 0);
  EXPECT_EQ(analyze_mesh(f, &c.tape, &c.enc, CoordinatePrecision::kFloat).outside_enclosure, 0);
}

TEST(MeshReport, VerticesReallyOutsideAreCounted) {
  PlaneCase c;
  // Beyond the float rounding of the bounds (2.4e-8 at 1.1) but closer than any leaf: outside.
  c.mesh.vertices[c.mesh.triangles[0][0]].z = 1.1 + 1e-6;
  // Inside the bounds, far from the plane's leaves (z in [0, 0.1375] at depth 4).
  c.mesh.vertices[c.mesh.triangles[0][1]].z = -0.5;
  for (CoordinatePrecision p : {CoordinatePrecision::kDouble, CoordinatePrecision::kFloat}) {
    EXPECT_EQ(analyze_mesh(c.mesh, &c.tape, &c.enc, p).outside_enclosure, 2);
  }
}

TEST(MeshReport, NoEnclosureNoCount) {
  const PlaneCase c;
  EXPECT_EQ(analyze_mesh(c.mesh, &c.tape).outside_enclosure, -1);
}

// Per-component topology: two tetrahedra and an open triangle. The consistently oriented
// tetrahedron has genus 0; the one with a face turned has none (not consistently oriented); the
// triangle is open. The totals are the components' sums.
TEST(MeshReport, TopologyPerComponent) {
  TriangleSoup m;
  for (int k = 0; k < 3; ++k) {
    const double o = 3.0 * k;
    m.vertices.insert(m.vertices.end(), {{o, 0, 0}, {o + 1, 0, 0}, {o, 1, 0}, {o, 0, 1}});
  }
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},  // outward
                 {4, 6, 5}, {4, 5, 7}, {4, 7, 6}, {5, 7, 6},  // last face turned
                 {8, 9, 10}};
  const MeshReport r = analyze_mesh(m);
  ASSERT_EQ(r.component_topology.size(), 3u);
  EXPECT_EQ(r.components, 3u);
  EXPECT_EQ(r.component_topology[0].genus, 0);
  EXPECT_EQ(r.component_topology[0].euler, 2);
  EXPECT_EQ(r.component_topology[1].genus, -1);
  EXPECT_GT(r.component_topology[1].inconsistent_edges, 0u);
  EXPECT_EQ(r.component_topology[2].genus, -1);
  EXPECT_EQ(r.component_topology[2].boundary_edges, 3u);
  EXPECT_EQ(r.component_topology[2].euler, 1);
  EXPECT_EQ(r.euler, 2 + 2 + 1);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(r.inconsistent_edges, r.component_topology[1].inconsistent_edges);
  EXPECT_EQ(r.unused_vertices, 1u);  // vertex 11 of the third group
}

}  // namespace
}  // namespace iaa
