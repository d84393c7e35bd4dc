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

}  // namespace
}  // namespace iaa
