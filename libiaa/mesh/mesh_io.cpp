// Meshes held as OpenMesh TriMeshes, and their files; see mesh_io.h.
#include "mesh/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cctype>
#include <cstdint>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "core/interval.h"

namespace iaa {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// The PLY vertex properties that carry the exact coordinates (see mesh_io.h).
constexpr const char* kExactNames[3] = {"x_double", "y_double", "z_double"};

const char* ext_of(MeshFormat f) {
  switch (f) {
    case MeshFormat::kPly:
      return ".ply";
    case MeshFormat::kObj:
      return ".obj";
    case MeshFormat::kOff:
      return ".off";
    case MeshFormat::kStl:
      return ".stl";
  }
  return ".ply";
}

// A binary STL is an 80-byte header, a 32-bit little-endian triangle count n and 50 bytes per
// triangle. Its header may begin with "solid" like an ASCII file, so the size decides.
bool is_binary_stl(const std::string& bytes) {
  if (bytes.size() < 84) return false;
  std::uint64_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(bytes[80 + i]);
  return bytes.size() == 84 + 50 * n;
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
  if (e == "stl") return MeshFormat::kStl;
  throw Error("unsupported mesh format '" + std::string(ext) + "': use .ply, .obj, .off or .stl");
}

struct Mesh::Impl {
  /// When precision is kDouble, vertex properties x_double, y_double, z_double (persistent, so
  /// the PLY writer stores them) hold the points' coordinates.
  TriMesh mesh;
  std::size_t originals = 0;  ///< vertices 0..originals-1 are the input's; the rest are copies
  std::vector<std::uint32_t> copy_of;  ///< for vertex originals + i, the vertex it copies
  CoordinatePrecision precision = CoordinatePrecision::kDouble;

  void add_exact_coordinates() {
    for (int a = 0; a < 3; ++a) {
      OpenMesh::VPropHandleT<double> h;
      if (!mesh.get_property_handle(h, kExactNames[a])) mesh.add_property(h, kExactNames[a]);
      mesh.property(h).set_persistent(true);
      for (const auto v : mesh.vertices()) mesh.property(h, v) = mesh.point(v)[a];
    }
  }
};

Mesh::Mesh() : impl_(std::make_unique<Impl>()) {}
Mesh::~Mesh() = default;
Mesh::Mesh(Mesh&&) noexcept = default;
Mesh& Mesh::operator=(Mesh&&) noexcept = default;

Mesh Mesh::from_triangles(const TriangleSoup& soup) {
  io_mutex();  // silences OpenMesh's logging before add_face can complain
  Mesh out;
  Impl& m = *out.impl_;
  TriMesh& mesh = m.mesh;
  mesh.reserve(soup.vertices.size(), 3 * soup.triangles.size(), soup.triangles.size());
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(soup.vertices.size());
  for (const Vec3& p : soup.vertices) vh.push_back(mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z)));
  m.originals = soup.vertices.size();
  for (const auto& t : soup.triangles) {
    if (t[0] >= vh.size() || t[1] >= vh.size() || t[2] >= vh.size()) {
      throw Error("mesh: a triangle refers to a vertex that does not exist");
    }
    std::vector<TriMesh::VertexHandle> f{vh[t[0]], vh[t[1]], vh[t[2]]};
    // add_face refuses a face that would make an edge or vertex complex (non-manifold).
    if (!mesh.add_face(f).is_valid()) {
      for (int k = 0; k < 3; ++k) {
        const TriMesh::Point p = mesh.point(f[std::size_t(k)]);  // a copy: add_vertex may move
        f[std::size_t(k)] = mesh.add_vertex(p);
        m.copy_of.push_back(t[std::size_t(k)]);
      }
      mesh.add_face(f);
    }
  }
  out.impl_->add_exact_coordinates();
  return out;
}

std::size_t Mesh::vertex_count() const {
  return impl_->mesh.n_vertices();
}
std::size_t Mesh::triangle_count() const {
  return impl_->mesh.n_faces();
}
std::size_t Mesh::duplicated_vertices() const {
  return impl_->copy_of.size();
}
CoordinatePrecision Mesh::precision() const {
  return impl_->precision;
}

TriangleSoup Mesh::triangles() const {
  const Impl& m = *impl_;
  TriangleSoup soup;
  soup.vertices.reserve(m.originals);
  for (std::size_t i = 0; i < m.originals; ++i) {
    const auto& p = m.mesh.point(TriMesh::VertexHandle(int(i)));
    soup.vertices.push_back({p[0], p[1], p[2]});
  }
  soup.triangles.reserve(m.mesh.n_faces());
  for (const auto f : m.mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (const auto v : m.mesh.fv_range(f)) {
      if (k < 3) {
        const std::size_t i = std::size_t(v.idx());
        t[std::size_t(k)] = i < m.originals ? std::uint32_t(i) : m.copy_of[i - m.originals];
      }
      ++k;
    }
    if (k == 3) soup.triangles.push_back(t);
  }
  return soup;
}

MeshReport analyze_mesh(const Mesh& mesh, const Tape* tape, const Enclosure* enclosure) {
  return analyze_mesh(mesh.triangles(), tape, enclosure, mesh.precision());
}

std::string encode_mesh(const Mesh& held, MeshFormat format, bool binary) {
  const TriMesh* source = &held.impl_->mesh;
  NearestScope nearest;  // the writer's float x y z: the nearest floats
  OpenMesh::IO::Options opt;
  if (binary && (format == MeshFormat::kPly || format == MeshFormat::kStl)) {
    opt += OpenMesh::IO::Options::Binary;
  }
  if (format == MeshFormat::kPly) {
    opt += OpenMesh::IO::Options::Custom;  // the x_double properties, when the mesh has them
  }
  // STL stores a normal per facet, which OpenMesh's writer takes from the face normals (zero
  // without them): a copy of the mesh gets them.
  TriMesh with_normals;
  if (format == MeshFormat::kStl) {
    opt += OpenMesh::IO::Options::FaceNormal;
    with_normals = *source;
    with_normals.request_face_normals();
    with_normals.update_face_normals();
    source = &with_normals;
  }
  const TriMesh& mesh = *source;
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

Mesh decode_mesh(const std::string& bytes, MeshFormat format, const std::string& what) {
  Mesh out;
  Mesh::Impl& m = *out.impl_;
  TriMesh& mesh = m.mesh;
  std::istringstream is(bytes, std::ios::in | std::ios::binary);
  OpenMesh::IO::Options opt;
  if (format == MeshFormat::kPly) opt += OpenMesh::IO::Options::Custom;  // reads x_double
  // OpenMesh's STL reader takes a stream as ASCII unless told which it is.
  if (format == MeshFormat::kStl && is_binary_stl(bytes)) opt += OpenMesh::IO::Options::Binary;
  bool ok = false;
  {
    std::lock_guard<std::mutex> lock(io_mutex());
    ok = OpenMesh::IO::read_mesh(mesh, is, ext_of(format), opt);
  }
  if (!ok) throw Error(what + ": not a readable " + std::string(ext_of(format) + 1) + " mesh");
  m.originals = mesh.n_vertices();
  // The reader gives x, y, z as float; a PLY written by iaa also holds them exactly. The exact
  // values are taken only if every one rounds to the float the file holds beside it (as the
  // writer made it): an edited file, or a vertex OpenMesh's importer copied for a non-manifold
  // face (its properties are default, 0), leaves the whole mesh at float precision.
  NearestScope nearest;
  OpenMesh::VPropHandleT<double> exact[3];
  bool have_exact = true;
  for (int a = 0; a < 3; ++a)
    have_exact = have_exact && mesh.get_property_handle(exact[a], kExactNames[a]);
  for (const auto v : mesh.vertices()) {
    if (!have_exact) break;
    for (int a = 0; a < 3; ++a) {
      const double e = mesh.property(exact[a], v);
      if (!(static_cast<float>(e) == static_cast<float>(mesh.point(v)[a]))) have_exact = false;
    }
  }
  if (have_exact) {
    for (const auto v : mesh.vertices()) {
      TriMesh::Point p = mesh.point(v);
      for (int a = 0; a < 3; ++a) p[a] = mesh.property(exact[a], v);
      mesh.set_point(v, p);
    }
    m.add_exact_coordinates();  // marks them persistent for a later write
  } else {
    m.precision = CoordinatePrecision::kFloat;  // and no x_double: a PLY write holds floats
  }
  return out;
}

}  // namespace iaa
