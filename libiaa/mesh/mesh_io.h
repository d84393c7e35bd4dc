// Meshes as iaa holds them: an OpenMesh TriMesh with double-precision points (class Mesh), built
// from a mesher's triangles or read from a file, analysed (analyze_mesh) and written with
// OpenMesh's readers and writers (PLY, OBJ, OFF). The library works on bytes in memory; reading
// and writing files is the tool's job. This header is free of OpenMesh types; everything in it
// exists when IAA_HAVE_OPENMESH is defined.
//
// Precision of the files (measured with OpenMesh 9.0, tests/mesh/mesh_io_test.cpp): its PLY, OBJ
// and OFF writers store x, y, z as float whatever the mesh's traits (the exporter's pointd() is
// used by the .om writer only), and its readers round even a PLY `property double x` to float.
// Custom vertex properties, though, are written and read with their own type. So a PLY file
// carries both: float x y z, which every reader understands, and the exact double coordinates
// as `property double x_double`, `y_double`, `z_double`, which decode_mesh prefers. OBJ and OFF
// files hold float coordinates only (written with 17 digits, so the float reads back exactly).
// STL files (ASCII, or binary with --binary) hold float coordinates and a normal per triangle,
// and no shared vertices: OpenMesh's reader welds equal points back together.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "enclose/octree.h"
#include "expr/tape.h"
#include "mesh/mesh_report.h"
#include "mesh/triangle_soup.h"

namespace iaa {

enum class MeshFormat { kPly, kObj, kOff, kStl };

/// The format for a file extension ("ply", "obj", "off", "stl", any case, without the dot); throws
/// iaa::Error naming the supported formats otherwise.
MeshFormat mesh_format_from_extension(std::string_view ext);

/// A triangle mesh held as an OpenMesh TriMesh with double-precision points and normals.
class Mesh {
 public:
  Mesh();
  ~Mesh();
  Mesh(Mesh&&) noexcept;
  Mesh& operator=(Mesh&&) noexcept;

  /// Builds the TriMesh from a mesher's triangles, points kept exactly. A triangle OpenMesh's
  /// halfedge structure refuses (it would make an edge or a vertex non-manifold) gets its own
  /// copies of its vertices, as OpenMesh's own importer does; each copy remembers the vertex it
  /// copies. Throws iaa::Error for a vertex index out of range.
  static Mesh from_triangles(const TriangleSoup& soup);

  std::size_t vertex_count() const;         ///< TriMesh vertices, copies included
  std::size_t triangle_count() const;       ///< TriMesh faces
  std::size_t duplicated_vertices() const;  ///< copies made by from_triangles
  /// kDouble for a mesher's mesh or a PLY file with the x_double properties; kFloat for a file
  /// that holds float coordinates only.
  CoordinatePrecision precision() const;

  /// The TriMesh's points and faces as plain arrays, each vertex copy merged back into the vertex
  /// it copies, so that the topology is the mesher's (a non-manifold edge stays one edge): what
  /// the report and the ray caster work on.
  TriangleSoup triangles() const;

  struct Impl;

 private:
  friend std::string encode_mesh(const Mesh& mesh, MeshFormat format, bool binary);
  friend Mesh decode_mesh(const std::string& bytes, MeshFormat format, const std::string& what);
  std::unique_ptr<Impl> impl_;
};

/// The report (mesh_report.h) of a held mesh: computed on the TriMesh's own points (double) and
/// faces, with the tolerance its precision() calls for.
MeshReport analyze_mesh(const Mesh& mesh, const Tape* tape = nullptr,
                        const Enclosure* enclosure = nullptr);

/// Encodes a mesh (ASCII with 17 significant digits, or binary PLY); see the header's note on
/// what each format holds. Throws iaa::Error if OpenMesh fails.
std::string encode_mesh(const Mesh& mesh, MeshFormat format, bool binary = false);

/// Decodes a mesh (polygons are split into triangles). `what` names the source in errors.
/// Throws iaa::Error when OpenMesh cannot read it.
Mesh decode_mesh(const std::string& bytes, MeshFormat format, const std::string& what);

/// Rounds every coordinate to float: the coordinates an OBJ or OFF file (or a PLY reader that
/// ignores x_double) gives back.
void round_to_file_precision(TriangleSoup& mesh);

}  // namespace iaa
