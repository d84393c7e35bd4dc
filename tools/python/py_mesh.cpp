// iaa.mesh and iaa.compare: meshing as `iaa mesh` runs it (vertices and faces as NumPy arrays over
// the mesh's own buffers, the command's report, and the mesh file it writes), and a mesh set
// against the render's certificates as `iaa compare` does it.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <limits>
#include <optional>

#include "app/comparing.h"
#include "app/files.h"
#include "app/meshing.h"
#include "core/error.h"
#include "mesh/mesh_io.h"
#include "py_common.h"
#ifdef IAA_HAVE_VIZ
#include "viz/vtk_mesher.h"
#endif

namespace iaa::py {
namespace {

namespace meshing = app::meshing;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(sizeof(std::array<std::uint32_t, 3>) == 3 * sizeof(std::int32_t));

#ifdef IAA_HAVE_VIZ
constexpr meshing::VtkMesher kVtkMesher = viz::run_vtk_mesher;
#else
constexpr meshing::VtkMesher kVtkMesher = nullptr;
#endif

#ifdef IAA_HAVE_OPENMESH
/// The C++ side of a mesh: the mesh as iaa holds it (for save()) and its triangles as the report
/// sees them (the arrays' memory).
struct MeshData {
  Mesh mesh;
  TriangleSoup soup;
};
#endif

struct MeshResult {
#ifdef IAA_HAVE_OPENMESH
  std::shared_ptr<const MeshData> data;
#endif
  pb::object vertices, faces, report;
};

/// The mesher's parameters: MeshParams' fields by their keyword names.
meshing::MeshParams mesh_params(int resolution, const pb::dict& options) {
  meshing::MeshParams p;
  p.resolution = resolution;
  for (const auto& [key, value] : options) {
    const std::string k = pb::str(key);
    if (k == "min_depth")
      p.min_depth = value.cast<int>();
    else if (k == "max_depth")
      p.max_depth = value.cast<int>();
    else if (k == "strict")
      p.strict = value.cast<bool>();
    else if (k == "proof_cache")
      p.proof_cache = value.cast<bool>();
    else if (k == "depth")
      p.depth = value.cast<int>();
    else if (k == "refine")
      p.refine = value.cast<int>();
    else if (k == "flat_tolerance")
      p.flat_tolerance = value.cast<double>();
    else if (k == "max_boxes")
      p.max_boxes = value.cast<std::uint64_t>();
    else if (k == "facet_size")
      p.facet_size = value.cast<double>();
    else if (k == "facet_distance")
      p.facet_distance = value.cast<double>();
    else if (k == "facet_angle")
      p.facet_angle = value.cast<double>();
    else if (k == "grid")
      p.grid = value.cast<int>();
    else
      throw pb::type_error("mesh() got an unexpected keyword argument '" + k + "'");
  }
  p.validate();
  return p;
}

#ifdef IAA_HAVE_OPENMESH
/// Runs the mesher and analyses its mesh as `iaa mesh --report` does (on the worker thread).
void mesh_work(meshing::Method method, const meshing::Surface& surface,
               const meshing::MeshParams& p, const Exec& exec, MeshData& d, nlohmann::json& rep) {
  meshing::MeshRun run = meshing::run_mesher(method, surface, p, exec, kVtkMesher);
  const std::string why = meshing::no_surface_reason(run, method);
  if (!why.empty()) throw Error(why);
  d.mesh = Mesh::from_triangles(run.soup);
  run.soup = {};
  d.soup = d.mesh.triangles();
  const EncloseSettings check = p.enclose_settings(surface.bounds);
  const MeshReport r =
      meshing::analyze_run(method, surface, d.soup, d.mesh.precision(), run, exec, &check);
  rep = meshing::mesh_report_json(method, surface, run, r, d.soup, d.mesh.duplicated_vertices());
}
#endif

MeshResult mesh_scene(const PyScene& ps, const std::string& method_name, int resolution,
                      int threads, const pb::object& progress, const pb::kwargs& options) {
  [[maybe_unused]] const meshing::Method method =
      meshing::parse_mesh_method(method_name, kVtkMesher);
  [[maybe_unused]] const meshing::MeshParams p = mesh_params(resolution, options);
#ifndef IAA_HAVE_OPENMESH
  throw Error(
      "this iaa was built without OpenMesh (IAA_WITH_OPENMESH=OFF): meshes cannot be written");
#else
  const meshing::Surface surface = meshing::surface_of(ps.scene);
  auto data = std::make_shared<MeshData>();
  nlohmann::json rep;
  run_cancellable([&](const Exec& exec) { mesh_work(method, surface, p, exec, *data, rep); },
                  threads, progress);
  MeshResult r;
  r.data = data;
  r.report = to_python(rep);
  const pb::capsule base = owner_capsule(std::shared_ptr<const MeshData>(data));
  const auto nv = static_cast<pb::ssize_t>(data->soup.vertices.size());
  const auto nf = static_cast<pb::ssize_t>(data->soup.triangles.size());
  r.vertices =
      array_over(reinterpret_cast<const double*>(data->soup.vertices.data()), {nv, 3}, base);
  r.faces =
      array_over(reinterpret_cast<const std::int32_t*>(data->soup.triangles.data()), {nf, 3}, base);
  return r;
#endif
}

/// MeshResult.save: the file `iaa mesh -o PATH [--binary]` writes for the same mesh.
void save_mesh(const MeshResult& r, const std::filesystem::path& file, bool binary) {
#ifdef IAA_HAVE_OPENMESH
  const std::string path = file.string();
  const MeshFormat format = mesh_format_from_extension(app::extension_of(path));
  pb::gil_scoped_release release;
  app::write_text_atomically(path, encode_mesh(r.data->mesh, format, binary));
#else
  (void)r, (void)file, (void)binary;
#endif
}

#ifdef IAA_HAVE_CGAL
/// A TriangleSoup from (V, 3) vertices and (F, 3) vertex indices, checked as a mesh file is.
TriangleSoup soup_from(
    const pb::array_t<double, pb::array::c_style | pb::array::forcecast>& vertices,
    const pb::array_t<std::int64_t, pb::array::c_style | pb::array::forcecast>& faces) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3) {
    throw Error("vertices: expected a (V, 3) array of coordinates");
  }
  if (faces.ndim() != 2 || faces.shape(1) != 3) {
    throw Error("faces: expected an (F, 3) array of vertex indices");
  }
  TriangleSoup soup;
  soup.vertices.resize(static_cast<std::size_t>(vertices.shape(0)));
  std::copy(vertices.data(), vertices.data() + vertices.size(),
            reinterpret_cast<double*>(soup.vertices.data()));
  soup.triangles.resize(static_cast<std::size_t>(faces.shape(0)));
  const std::int64_t* f = faces.data();
  for (pb::ssize_t i = 0; i < faces.size(); ++i) {
    if (f[i] < 0 || f[i] > std::numeric_limits<std::uint32_t>::max()) {
      throw Error("faces: vertex index " + std::to_string(f[i]) + " out of range");
    }
    soup.triangles[static_cast<std::size_t>(i / 3)][static_cast<std::size_t>(i % 3)] =
        static_cast<std::uint32_t>(f[i]);
  }
  check_mesh(soup, "the mesh (vertices, faces)");
  return soup;
}

/// The C++ side of a comparison: the render, the cast and their verdicts, and the diff picture.
struct CompareData {
  app::ComparedViews views;
  app::Image8 diff;
  std::vector<std::uint8_t> lost, wrong;  ///< 1 where the verdict is lost (wrong)
};
#endif

struct CompareResult {
  pb::object lost, wrong, agreement, diff, report;
};

CompareResult compare_scene(
    const PyScene& ps, const pb::array_t<double, pb::array::c_style | pb::array::forcecast>& v,
    const pb::array_t<std::int64_t, pb::array::c_style | pb::array::forcecast>& f, int rays,
    int threads, const pb::object& progress) {
#ifndef IAA_HAVE_CGAL
  throw Error("this iaa was built without CGAL (IAA_WITH_CGAL=OFF): meshes cannot be ray-cast");
#else
  app::check_rays(rays);
  const TriangleSoup soup = soup_from(v, f);
  auto d = std::make_shared<CompareData>();
  run_cancellable(
      [&](const Exec& exec) {
        d->views = app::compare_views(ps.scene, soup, rays, exec);
        d->diff = app::diff_image(d->views);
      },
      threads, progress);
  for (PixelAgreement a : d->views.cmp.pixel) {
    d->lost.push_back(a == PixelAgreement::kLost);
    d->wrong.push_back(a == PixelAgreement::kWrong);
  }
  nlohmann::json rep = app::compare_report_json(ps.scene, "", soup, rays, d->views);
  rep["mesh"] = nullptr;  // arrays, not a file
  CompareResult r;
  r.report = to_python(rep);
  const pb::capsule base = owner_capsule(std::shared_ptr<const CompareData>(d));
  const pb::ssize_t h = d->views.film.height, w = d->views.film.width;
  r.lost = array_over(reinterpret_cast<const bool*>(d->lost.data()), {h, w}, base);
  r.wrong = array_over(reinterpret_cast<const bool*>(d->wrong.data()), {h, w}, base);
  r.agreement =
      array_over(reinterpret_cast<const std::uint8_t*>(d->views.cmp.pixel.data()), {h, w}, base);
  r.diff = array_over(d->diff.data.data(), {h, w, 3}, base);
  return r;
#endif
}

}  // namespace

void bind_mesh(pb::module_& m) {
  pb::class_<MeshResult>(m, "MeshResult", R"doc(
What iaa.mesh returns. vertices and faces share the mesh's memory (no copies); the triangles are
oriented with normals towards increasing f.)doc")
      .def_readonly("vertices", &MeshResult::vertices, "(V, 3) float64: the vertices")
      .def_readonly("faces", &MeshResult::faces,
                    "(F, 3) int32: vertex indices of each triangle, counter-clockwise seen from "
                    "the side f increases to")
      .def_readonly("report", &MeshResult::report,
                    "dict: the JSON report of `iaa mesh --report`, without its two file keys")
      .def("save", &save_mesh, pb::arg("path"), pb::arg("binary") = false,
           "Writes the mesh (.ply, .obj, .off or .stl; binary PLY or STL with binary=True): the "
           "file `iaa mesh -o PATH` writes.")
      .def("__repr__", [](const MeshResult& r) {
        return "<iaa.MeshResult " + std::to_string(pb::len(r.vertices)) + " vertices, " +
               std::to_string(pb::len(r.faces)) + " triangles>";
      });

  m.def("mesh", &mesh_scene, pb::arg("scene"), pb::arg("method") = "certified",
        pb::arg("resolution") = meshing::MeshParams{}.resolution, pb::kw_only(),
        pb::arg("threads") = 0, pb::arg("progress") = pb::none(), R"doc(
Meshes the scene's surface as `iaa mesh` does (docs/mesh.md).

method: "certified" (isotopic to the surface inside the cells it certifies), "octree" (from the
guaranteed enclosure), "cgal" (CGAL Mesh_3) or "vtk" (VTK flying edges); resolution: N, comparable
across methods. More keywords, as the command's flags: min_depth, max_depth, strict, proof_cache
(certified; proof_cache=False is --no-proof-cache);
depth, refine, flat_tolerance (octree); max_boxes (certified, octree); facet_size,
facet_distance, facet_angle (cgal); grid (vtk). threads, progress: as for render(). Raises
ValueError with the command's message, also when the mesher finds no surface.)doc");

  pb::class_<CompareResult>(m, "CompareResult", R"doc(
What iaa.compare returns: per pixel, the mesh's view against the IAA render's certificates.)doc")
      .def_readonly("lost", &CompareResult::lost,
                    "(H, W) bool: IAA certifies surface, the mesh shows none")
      .def_readonly("wrong", &CompareResult::wrong,
                    "(H, W) bool: IAA certifies empty, the mesh shows surface")
      .def_readonly("agreement", &CompareResult::agreement,
                    "(H, W) uint8: 0 not compared, 1 both empty, 2 both surface, 3 lost, 4 wrong, "
                    "5 uncertain with mesh, 6 uncertain without")
      .def_readonly("diff", &CompareResult::diff,
                    "(H, W, 3) uint8: the diff picture of `iaa compare -o` (red lost, blue wrong, "
                    "amber undecided without mesh)")
      .def_readonly("report", &CompareResult::report,
                    "dict: the JSON report of `iaa compare --report` (mesh: None)");

  m.def("compare", &compare_scene, pb::arg("scene"), pb::arg("vertices"), pb::arg("faces"),
        pb::kw_only(), pb::arg("rays") = 4, pb::arg("threads") = 0,
        pb::arg("progress") = pb::none(), R"doc(
Sets a mesh against the render's certificates of the same view, as `iaa compare` does: the scene
is rendered with IAA and the mesh ray-cast with its camera, a pixel showing the mesh when any ray
of its beam meets a triangle.

vertices: (V, 3) coordinates; faces: (F, 3) vertex indices (e.g. iaa.mesh's); rays: rays per pixel
side for the covered-area figure only (1..16). threads, progress: as for render().)doc");
}

}  // namespace iaa::py
