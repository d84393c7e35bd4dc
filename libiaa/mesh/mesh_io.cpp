// Mesh encoding and decoding through OpenMesh; see mesh_io.h.
#include "mesh/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cctype>
#include <mutex>
#include <sstream>

#include "core/error.h"

namespace iaa {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

const char* ext_of(MeshFormat f) {
  switch (f) {
    case MeshFormat::kPly:
      return ".ply";
    case MeshFormat::kObj:
      return ".obj";
    case MeshFormat::kOff:
      return ".off";
  }
  return ".ply";
}

// OpenMesh's readers and writers log to its own streams (stdout); the library never prints, so
// they are silenced once. OpenMesh's IO manager is not thread-safe: calls are serialised.
std::mutex& io_mutex() {
  static std::mutex m;
  static const bool silenced = [] {
    omlog().disable();
    omout().disable();
    omerr().disable();
    return true;
  }();
  (void)silenced;
  return m;
}

}  // namespace

MeshFormat mesh_format_from_extension(std::string_view ext) {
  std::string e(ext);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (e == "ply") return MeshFormat::kPly;
  if (e == "obj") return MeshFormat::kObj;
  if (e == "off") return MeshFormat::kOff;
  throw Error("unsupported mesh format '" + std::string(ext) + "': use .ply, .obj or .off");
}

std::string encode_mesh(const TriangleSoup& soup, MeshFormat format, bool binary,
                        std::size_t* duplicated) {
  io_mutex();  // silences OpenMesh's logging before add_face can complain
  TriMesh mesh;
  mesh.reserve(soup.vertices.size(), 3 * soup.triangles.size(), soup.triangles.size());
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(soup.vertices.size());
  for (const Vec3& p : soup.vertices) vh.push_back(mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z)));
  std::size_t copies = 0;
  for (const auto& t : soup.triangles) {
    if (t[0] >= vh.size() || t[1] >= vh.size() || t[2] >= vh.size()) {
      throw Error("mesh: a triangle refers to a vertex that does not exist");
    }
    std::vector<TriMesh::VertexHandle> f{vh[t[0]], vh[t[1]], vh[t[2]]};
    // add_face refuses a face that would make an edge or vertex complex (non-manifold).
    TriMesh::FaceHandle fh = mesh.add_face(f);
    if (!fh.is_valid()) {
      for (auto& v : f) {
        const TriMesh::Point p = mesh.point(v);  // a copy: add_vertex may move the points
        v = mesh.add_vertex(p);
      }
      mesh.add_face(f);
      copies += 3;
    }
  }
  if (duplicated) *duplicated = copies;
  OpenMesh::IO::Options opt;
  if (binary && format == MeshFormat::kPly) opt += OpenMesh::IO::Options::Binary;
  std::ostringstream os(binary ? std::ios::out | std::ios::binary : std::ios::out);
  bool ok = false;
  {
    std::lock_guard<std::mutex> lock(io_mutex());
    ok = OpenMesh::IO::write_mesh(mesh, os, ext_of(format), opt, 17);
  }
  if (!ok) throw Error(std::string("OpenMesh could not write the mesh as ") + (ext_of(format) + 1));
  return os.str();
}

void round_to_file_precision(TriangleSoup& mesh) {
  for (Vec3& p : mesh.vertices) {
    for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(p[a]);
  }
}

TriangleSoup decode_mesh(const std::string& bytes, MeshFormat format, const std::string& what) {
  TriMesh mesh;
  std::istringstream is(bytes, std::ios::in | std::ios::binary);
  OpenMesh::IO::Options opt;
  bool ok = false;
  {
    std::lock_guard<std::mutex> lock(io_mutex());
    ok = OpenMesh::IO::read_mesh(mesh, is, ext_of(format), opt);
  }
  if (!ok) throw Error(what + ": not a readable " + std::string(ext_of(format) + 1) + " mesh");
  TriangleSoup soup;
  soup.vertices.reserve(mesh.n_vertices());
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    soup.vertices.push_back({p[0], p[1], p[2]});
  }
  soup.triangles.reserve(mesh.n_faces());
  for (const auto f : mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (const auto v : mesh.fv_range(f)) {
      if (k < 3) t[std::size_t(k)] = static_cast<std::uint32_t>(v.idx());
      ++k;
    }
    if (k == 3) soup.triangles.push_back(t);
  }
  return soup;
}

}  // namespace iaa
