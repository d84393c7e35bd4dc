// The octree mesher: watertight, oriented, manifold meshes with the right area, volume and
// topology on analytic shapes, crack-free across mixed cell depths, thin features reached by
// refinement, and surfaces without a sign change reported rather than meshed.
#include "mesh/octree_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "expr/eval_point_grad.h"
#include "mesh/mesh_report.h"
#include "mesh/mesh_test_util.h"
#include "test_progress.h"

namespace iaa {
namespace {

constexpr double kPi = 3.14159265358979323846;
const Box3 kCube{{-1, -1, -1}, {1, 1, 1}};

OctreeMeshSettings settings_for(const Box3& b) {
  OctreeMeshSettings s;
  s.enclose.bounds = b;
  return s;
}

void expect_watertight(const MeshReport& r) {
  EXPECT_GT(r.triangles, 0u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.unused_vertices, 0u);
}

TEST(OctreeMesher, SphereIsClosedWithAreaAndVolume) {
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.64");
  const Enclosure enc = test::local_enclose(tape, kCube, 5, 0);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  expect_watertight(r);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.outside_enclosure, 0);
  EXPECT_EQ(m.stats.open_chains, 0u);
  EXPECT_NEAR(r.area, 4 * kPi * 0.64, 0.02 * 4 * kPi * 0.64);
  // Normals point towards increasing f (outwards here), so the signed volume is positive.
  EXPECT_NEAR(r.volume, 4.0 / 3 * kPi * 0.512, 0.02 * 4.0 / 3 * kPi * 0.512);
  EXPECT_LT(r.max_abs_f, 1e-3);
}

TEST(OctreeMesher, TorusHasEulerCharacteristicZero) {
  const Tape tape = Tape::parse("(x^2 + y^2 + z^2 + 0.6^2 - 0.25^2)^2 - 4*0.36*(x^2 + y^2)");
  const Enclosure enc = test::local_enclose(tape, kCube, 6, 0);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  expect_watertight(r);
  EXPECT_EQ(r.euler, 0);
  EXPECT_EQ(r.components, 1u);
  const double area = 4 * kPi * kPi * 0.6 * 0.25, volume = 2 * kPi * kPi * 0.6 * 0.0625;
  EXPECT_NEAR(r.area, area, 0.02 * area);
  EXPECT_NEAR(r.volume, volume, 0.03 * volume);
}

TEST(OctreeMesher, MixedDepthsAreCrackFree) {
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.64");
  // Cells with x > 0.1 are split two levels further, in a pattern that also mixes depths along
  // edges; the mesh must stay closed and manifold.
  const Enclosure enc = test::local_enclose(
      tape, kCube, 4, 0,
      [](const Box3& b, int d) { return (b.lo.x > 0.1 && d < 6) || (d == 6 && b.lo.y > 0.3); }, 7);
  int depths[8] = {};
  for (const Cell& c : enc.cells) ++depths[c.depth];
  ASSERT_GT(depths[4], 0);
  ASSERT_GT(depths[6], 0);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  expect_watertight(r);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(m.stats.open_chains, 0u);
  EXPECT_NEAR(r.volume, 4.0 / 3 * kPi * 0.512, 0.03 * 4.0 / 3 * kPi * 0.512);
}

TEST(OctreeMesher, ClippedPlaneHasABoundaryAndNoOtherDefect) {
  const Tape tape = Tape::parse("z - 0.1 + 0.05*x");
  const Enclosure enc = test::local_enclose(tape, kCube, 4, 0);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  EXPECT_GT(r.boundary_edges, 0u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.euler, 1);  // a disk
  EXPECT_NEAR(r.area, 4 * std::sqrt(1 + 0.0025), 1e-6);
}

TEST(OctreeMesher, RefinementReachesThinFeatures) {
  // A thin tube (radius 0.004) along x, f > 0 inside: invisible at depth 5 (cells 0.0625 wide).
  const Tape tape = Tape::parse("0.004^2 - (y - 0.013)^2 - (z + 0.011)^2");
  const Enclosure coarse = test::local_enclose(tape, kCube, 5, 0);
  const OctreeMesh m0 = extract_mesh(tape, coarse, settings_for(kCube));
  EXPECT_EQ(m0.soup.triangles.size(), 0u);
  EXPECT_GT(m0.stats.unmeshed_possible, 0u);
  EXPECT_EQ(m0.unmeshed.size(), m0.stats.unmeshed_possible);
  const Enclosure fine = test::local_enclose(tape, kCube, 5, 5);
  const OctreeMesh m1 = extract_mesh(tape, fine, settings_for(kCube));
  const MeshReport r = analyze_mesh(m1.soup, &tape, &fine);
  EXPECT_GT(r.triangles, 0u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.outside_enclosure, 0);
  const double area = 2 * kPi * 0.004 * 2;  // open tube across the cube
  EXPECT_NEAR(r.area, area, 0.1 * area);
}

// Largest first-order distance |f| / |grad f| from the surface over the triangles' centroids.
double max_centroid_distance(const Tape& tape, const TriangleSoup& soup) {
  PointGradEval pg(tape);
  double worst = 0;
  for (const auto& t : soup.triangles) {
    const Vec3 c = (soup.vertices[t[0]] + soup.vertices[t[1]] + soup.vertices[t[2]]) / 3.0;
    const PGrad f = pg.eval(c);
    worst = std::max(worst, std::fabs(f.v) / std::sqrt(dot(f.g, f.g)));
  }
  return worst;
}

TEST(OctreeMesher, LoopsWhereTheSurfaceBendsGetACentreVertex) {
  // A thin disc (radius 0.7, half thickness 0.028): its rim turns through 180 degrees within
  // leaves 0.03 wide, where one or two flat triangles per loop cut it back.
  const Tape tape = Tape::parse("x^2 + y^2 + (z/0.04)^2 - 0.49");
  const Enclosure enc = test::local_enclose(tape, kCube, 6, 2);
  OctreeMeshSettings flat = settings_for(kCube), all = settings_for(kCube);
  flat.flat_tolerance = 1;  // practically no leaf bends that far: loops of 3 and 4 stay flat
  all.flat_tolerance = 0;   // nearly every loop gets a centre
  const OctreeMesh m_flat = extract_mesh(tape, enc, flat);
  const OctreeMesh m_all = extract_mesh(tape, enc, all);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  EXPECT_EQ(m_flat.stats.bent_loops, 0u);
  EXPECT_GT(m.stats.bent_loops, 0u);
  EXPECT_EQ(m.soup.triangles.size(), m_flat.soup.triangles.size() + 2 * m.stats.bent_loops);
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  expect_watertight(r);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.outside_enclosure, 0);
  // The default gets (to 5%) what centring every loop gets, at a fraction of its triangles.
  const double d_flat = max_centroid_distance(tape, m_flat.soup);
  const double d_all = max_centroid_distance(tape, m_all.soup);
  const double d = max_centroid_distance(tape, m.soup);
  EXPECT_LT(d, 0.8 * d_flat) << "flat " << d_flat << ", default " << d;
  EXPECT_LE(d, 1.05 * d_all) << "all centred " << d_all << ", default " << d;
  EXPECT_LT(m.soup.triangles.size(), m_all.soup.triangles.size() * 3 / 5);
}

TEST(OctreeMesher, LoopsOnASmoothSurfaceStayFlat) {
  // A sphere of radius 0.5 in leaves 0.03 wide: a loop's chords lie at most ~0.016 of the leaf's
  // edge from the surface, under the default tolerance; a finer tolerance bends some loops.
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.25");
  const Enclosure enc = test::local_enclose(tape, kCube, 6, 0);
  EXPECT_EQ(extract_mesh(tape, enc, settings_for(kCube)).stats.bent_loops, 0u);
  OctreeMeshSettings fine = settings_for(kCube);
  fine.flat_tolerance = 0.01;
  const OctreeMesh m = extract_mesh(tape, enc, fine);
  EXPECT_GT(m.stats.bent_loops, 0u);
  const MeshReport r = analyze_mesh(m.soup, &tape, &enc);
  expect_watertight(r);
  EXPECT_EQ(r.euler, 2);
}

TEST(OctreeMesher, NoSignChangeMeansNothingMeshedButReported) {
  const Tape tape = Tape::parse("(x^2 + y^2 + z^2 - 0.5)^2");
  const Enclosure enc = test::local_enclose(tape, kCube, 4, 1);
  const OctreeMesh m = extract_mesh(tape, enc, settings_for(kCube));
  EXPECT_EQ(m.soup.triangles.size(), 0u);
  EXPECT_EQ(m.stats.unmeshed_possible, enc.cells.size());
}

TEST(OctreeMesher, OutputIsIdenticalForAnyThreadCount) {
  const Tape tape = Tape::parse("x^4 + y^4 + z^4 - x^2 - y^2 - z^2 + 0.5");
  const Box3 b{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  const Enclosure enc = test::local_enclose(tape, b, 4, 2);
  Exec one;
  one.threads = 1;
  Exec two;
  two.threads = 2;
  const OctreeMesh a = extract_mesh(tape, enc, settings_for(b), one);
  const OctreeMesh c = extract_mesh(tape, enc, settings_for(b), two);
  test::expect_same_soup(a.soup, c.soup);
}

TEST(OctreeMesher, SettingsAreValidated) {
  OctreeMeshSettings s = settings_for(kCube);
  s.enclose.depth = 15;
  s.enclose.refine_possible = 8;
  EXPECT_THROW(s.validate(), SettingError);
  s = settings_for(kCube);
  s.flat_tolerance = -0.1;
  EXPECT_THROW(s.validate(), SettingError);
  s.flat_tolerance = std::nan("");
  EXPECT_THROW(s.validate(), SettingError);
}

// Ctrl-C (Progress::cancel) reaches the octree mesher's phases: it stops with an error instead of
// finishing the mesh.
TEST(OctreeMesher, CancelStopsWithAnError) {
  test::CancelAtStart progress;
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.64");
  const Enclosure enc = test::local_enclose(tape, kCube, 5, 0);
  Exec exec;
  exec.progress = &progress;
  EXPECT_THROW(extract_mesh(tape, enc, settings_for(kCube), exec), Error);
}

}  // namespace
}  // namespace iaa
