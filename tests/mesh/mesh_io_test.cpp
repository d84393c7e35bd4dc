// Mesh files through OpenMesh: exact round trips in every format, and clear errors for unreadable,
// empty and NaN meshes.
#include "mesh/mesh_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "mesh/mesh_report.h"

namespace iaa {
namespace {

#ifdef IAA_HAVE_OPENMESH

TriangleSoup tetrahedron() {
  TriangleSoup t;
  t.vertices = {{0.1, 0.2, 0.3}, {1.0 / 3, 0, 0}, {0, 1, 0}, {0, 0, std::sqrt(2.0)}};
  t.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return t;
}

// OpenMesh 9.0's readers and writers carry positions as float whatever the mesh traits (measured):
// a file holds each coordinate rounded to float, written with enough digits to read back exactly.
TEST(MeshIo, RoundTripsEveryFormatAtFloatPrecision) {
  TriangleSoup t = tetrahedron();
  for (Vec3& p : t.vertices) {
    for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(p[a]);
  }
  for (MeshFormat f : {MeshFormat::kPly, MeshFormat::kObj, MeshFormat::kOff}) {
    for (bool binary : {false, true}) {
      const TriangleSoup back = decode_mesh(encode_mesh(t, f, binary), f, "test");
      ASSERT_EQ(back.vertices.size(), t.vertices.size());
      ASSERT_EQ(back.triangles.size(), t.triangles.size());
      for (std::size_t i = 0; i < t.vertices.size(); ++i)
        EXPECT_EQ(back.vertices[i], t.vertices[i]);
      const MeshReport r = analyze_mesh(back);
      EXPECT_EQ(r.boundary_edges, 0u);
      EXPECT_EQ(r.inconsistent_edges, 0u);
      EXPECT_EQ(r.volume, analyze_mesh(t).volume);
    }
  }
}

TEST(MeshIo, NonManifoldTrianglesAreKeptByCopyingVertices) {
  TriangleSoup t;  // three triangles on one edge
  t.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  t.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  std::size_t copies = 0;
  const TriangleSoup back =
      decode_mesh(encode_mesh(t, MeshFormat::kOff, false, &copies), MeshFormat::kOff, "t");
  EXPECT_EQ(back.triangles.size(), 3u);
  EXPECT_EQ(copies, 3u);
}

TEST(MeshIo, ExtensionsAreChecked) {
  EXPECT_EQ(mesh_format_from_extension("PLY"), MeshFormat::kPly);
  EXPECT_EQ(mesh_format_from_extension("obj"), MeshFormat::kObj);
  EXPECT_THROW(mesh_format_from_extension("stl"), Error);
}

TEST(MeshIo, BadMeshesGiveClearErrors) {
  // Unreadable.
  EXPECT_THROW(decode_mesh("this is not a mesh", MeshFormat::kPly, "bad.ply"), Error);
  EXPECT_THROW(check_mesh(decode_mesh("OFF\n3 1 0\n0 0 0\n1 0\n", MeshFormat::kOff, "short.off"),
                          "short.off"),
               Error);
  // Empty: readable, but check_mesh refuses it.
  const TriangleSoup empty = decode_mesh("OFF\n0 0 0\n", MeshFormat::kOff, "empty.off");
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
      decode_mesh("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", MeshFormat::kObj, "n.obj");
  EXPECT_THROW(check_mesh(nan_obj, "n.obj"), Error);
}

#else
TEST(MeshIo, DisabledInThisBuild) {
  GTEST_SKIP() << "built without OpenMesh";
}
#endif

}  // namespace
}  // namespace iaa
