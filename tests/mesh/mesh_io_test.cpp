// Meshes held as OpenMesh TriMeshes and their files: exact round trips through PLY, float ones
// through OBJ and OFF, OpenMesh 9.0's precision as measured, the report on the held mesh, and
// clear errors for unreadable, empty and NaN meshes.
#include "mesh/mesh_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "enclose/octree.h"
#include "mesh/mesh_report.h"
#include "mesh/octree_mesher.h"

namespace iaa {
namespace {

#ifdef IAA_HAVE_OPENMESH

TriangleSoup tetrahedron() {
  TriangleSoup t;
  t.vertices = {{0.1, 0.2, 0.3}, {1.0 / 3, 0, 0}, {0, 1, 0}, {0, 0, std::sqrt(2.0)}};
  t.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return t;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// PLY files carry the exact doubles (x_double ...) besides float x y z; OBJ and OFF hold float
// coordinates, written with enough digits to read back exactly as floats.
TEST(MeshIo, RoundTripsExactInPlyAndAtFloatPrecisionOtherwise) {
  const TriangleSoup t = tetrahedron();
  TriangleSoup f = t;
  round_to_file_precision(f);
  const Mesh held = Mesh::from_triangles(t);
  EXPECT_EQ(held.precision(), CoordinatePrecision::kDouble);
  for (MeshFormat fmt : {MeshFormat::kPly, MeshFormat::kObj, MeshFormat::kOff}) {
    for (bool binary : {false, true}) {
      const Mesh back = decode_mesh(encode_mesh(held, fmt, binary), fmt, "test");
      const bool exact = fmt == MeshFormat::kPly;
      EXPECT_EQ(back.precision(),
                exact ? CoordinatePrecision::kDouble : CoordinatePrecision::kFloat);
      const TriangleSoup b = back.triangles();
      ASSERT_EQ(b.vertices.size(), t.vertices.size());
      ASSERT_EQ(b.triangles, t.triangles);
      for (std::size_t i = 0; i < t.vertices.size(); ++i)
        EXPECT_EQ(b.vertices[i], exact ? t.vertices[i] : f.vertices[i]);
      const MeshReport r = analyze_mesh(back);
      EXPECT_EQ(r.boundary_edges, 0u);
      EXPECT_EQ(r.inconsistent_edges, 0u);
      EXPECT_EQ(r.volume, analyze_mesh(exact ? t : f).volume);
    }
  }
}

// What OpenMesh 9.0 does with precision (the reason for x_double): its PLY writer declares x y z
// float whatever the traits, writes a persistent custom double property as double, and its
// reader rounds even `property double x` to float.
TEST(MeshIo, OpenMeshPlyPrecisionAsMeasured) {
  const std::string ply = encode_mesh(Mesh::from_triangles(tetrahedron()), MeshFormat::kPly);
  EXPECT_TRUE(contains(ply, "property float x\n"));
  EXPECT_TRUE(contains(ply, "property double x_double\n"));
  EXPECT_TRUE(contains(ply, "property double z_double\n"));
  const std::string foreign =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "1.1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n";
  const Mesh m = decode_mesh(foreign, MeshFormat::kPly, "foreign.ply");
  EXPECT_EQ(m.precision(), CoordinatePrecision::kFloat);
  EXPECT_EQ(m.triangles().vertices[0].x, double(1.1f));
  // A float mesh written again as PLY gets no x_double: it does not claim what it lacks.
  EXPECT_FALSE(contains(encode_mesh(m, MeshFormat::kPly), "x_double"));
}

// x_double is believed only where it rounds to the float beside it: an edited file falls back to
// float precision as a whole.
TEST(MeshIo, InconsistentExactCoordinatesAreIgnored) {
  std::string ply = encode_mesh(Mesh::from_triangles(tetrahedron()), MeshFormat::kPly);
  const std::size_t line = ply.find("end_header\n") + 11;
  std::istringstream first(ply.substr(line, ply.find('\n', line) - line));
  std::string x, y, z, xd, yd, zd;
  first >> x >> y >> z >> xd >> yd >> zd;
  ASSERT_EQ(xd, "0.10000000000000001");
  ply.replace(ply.find(xd, line), xd.size(), "0.5");
  const Mesh m = decode_mesh(ply, MeshFormat::kPly, "edited.ply");
  EXPECT_EQ(m.precision(), CoordinatePrecision::kFloat);
  EXPECT_EQ(m.triangles().vertices[0].x, double(0.1f));
  EXPECT_EQ(m.triangles().vertices[1].x, double(float(1.0 / 3)));
}

TEST(MeshIo, NonManifoldTrianglesAreKeptByCopyingVertices) {
  TriangleSoup t;  // three triangles on one edge
  t.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  t.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const Mesh held = Mesh::from_triangles(t);
  EXPECT_EQ(held.duplicated_vertices(), 3u);
  EXPECT_EQ(held.vertex_count(), 8u);
  // The report still sees the mesher's topology: one edge of three triangles.
  EXPECT_EQ(held.triangles().triangles, t.triangles);
  EXPECT_EQ(analyze_mesh(held).nonmanifold_edges, 1u);
  const Mesh back = decode_mesh(encode_mesh(held, MeshFormat::kOff), MeshFormat::kOff, "t");
  EXPECT_EQ(back.triangle_count(), 3u);
  // The copies carry their exact coordinates too.
  const Mesh ply = decode_mesh(encode_mesh(held, MeshFormat::kPly), MeshFormat::kPly, "t");
  EXPECT_EQ(ply.triangle_count(), 3u);
  EXPECT_EQ(ply.precision(), CoordinatePrecision::kDouble);
}

// A mesh read back from a float file is judged with the float tolerance: the plane z = 0.1 in
// +-1.1 has vertices on the faces x, y = +-1.1, which float does not hold.
TEST(MeshIo, FloatFileReportAllowsTheFloatRounding) {
  const Tape tape = Tape::parse("z - 0.1");
  OctreeMeshSettings s;
  s.enclose.bounds = {{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  s.enclose.depth = 4;
  const OctreeMesh om = mesh_octree(tape, s);
  const Enclosure enc = enclose(tape, s.enclose);
  const Mesh held = Mesh::from_triangles(om.soup);
  EXPECT_EQ(analyze_mesh(held, &tape, &enc).outside_enclosure, 0);
  for (MeshFormat fmt : {MeshFormat::kPly, MeshFormat::kObj}) {
    const Mesh back = decode_mesh(encode_mesh(held, fmt), fmt, "plane");
    EXPECT_EQ(analyze_mesh(back, &tape, &enc).outside_enclosure, 0);
  }
  const Mesh obj = decode_mesh(encode_mesh(held, MeshFormat::kObj), MeshFormat::kObj, "plane");
  EXPECT_GT(
      analyze_mesh(obj.triangles(), &tape, &enc, CoordinatePrecision::kDouble).outside_enclosure,
      0);
}

TEST(MeshIo, ExtensionsAreChecked) {
  EXPECT_EQ(mesh_format_from_extension("PLY"), MeshFormat::kPly);
  EXPECT_EQ(mesh_format_from_extension("obj"), MeshFormat::kObj);
  EXPECT_EQ(mesh_format_from_extension("STL"), MeshFormat::kStl);
  EXPECT_THROW(mesh_format_from_extension("stp"), Error);
}

// STL holds float corners per facet, ASCII or binary; OpenMesh's reader welds them back into a
// closed mesh of the same topology and float-rounded volume.
TEST(MeshIo, StlRoundTripsAtFloatPrecisionAsciiAndBinary) {
  const TriangleSoup t = tetrahedron();
  TriangleSoup f = t;
  round_to_file_precision(f);
  const Mesh held = Mesh::from_triangles(t);
  for (bool binary : {false, true}) {
    const std::string bytes = encode_mesh(held, MeshFormat::kStl, binary);
    EXPECT_EQ(bytes.rfind("solid", 0) == 0, !binary);
    if (binary) {
      EXPECT_EQ(bytes.size(), 84u + 50u * t.triangles.size());
    }
    const Mesh back = decode_mesh(bytes, MeshFormat::kStl, "test.stl");
    EXPECT_EQ(back.precision(), CoordinatePrecision::kFloat);
    const MeshReport r = analyze_mesh(back);
    EXPECT_EQ(r.triangles, 4u);
    EXPECT_EQ(r.vertices, 4u);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_EQ(r.inconsistent_edges, 0u);
    EXPECT_NEAR(r.volume, analyze_mesh(f).volume, 1e-12);
  }
}

TEST(MeshIo, BadMeshesGiveClearErrors) {
  // Unreadable.
  EXPECT_THROW(decode_mesh("this is not a mesh", MeshFormat::kPly, "bad.ply"), Error);
  EXPECT_THROW(
      check_mesh(decode_mesh("OFF\n3 1 0\n0 0 0\n1 0\n", MeshFormat::kOff, "short.off").triangles(),
                 "short.off"),
      Error);
  // Empty: readable, but check_mesh refuses it.
  const TriangleSoup empty = decode_mesh("OFF\n0 0 0\n", MeshFormat::kOff, "empty.off").triangles();
  try {
    check_mesh(empty, "empty.off");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos);
  }
  // NaN vertex.
  TriangleSoup t = tetrahedron();
  t.vertices[2].y = std::numeric_limits<double>::quiet_NaN();
  try {
    check_mesh(t, "nan.ply");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos);
  }
  const TriangleSoup nan_obj =
      decode_mesh("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", MeshFormat::kObj, "n.obj").triangles();
  EXPECT_THROW(check_mesh(nan_obj, "n.obj"), Error);
}

#else
TEST(MeshIo, DisabledInThisBuild) {
  GTEST_SKIP() << "built without OpenMesh";
}
#endif

}  // namespace
}  // namespace iaa
