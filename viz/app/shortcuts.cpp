// `iaa-viz enclose SCENE` and `iaa-viz mesh SCENE` (see shortcuts.h).
#include "viz/app/shortcuts.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include "app/meshing.h"
#include "app/progress_bar.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "mesh/certified_mesher.h"
#include "mesh/octree_mesher.h"
#include "viz/app/view_options.h"
#include "viz/box_vtk.h"
#include "viz/enclosure_vtk.h"
#include "viz/scene_render.h"
#include "viz/soup_vtk.h"

namespace iaa::viz {
namespace {

struct ShortcutOptions {
  std::string scene;
  std::vector<std::string> sets;
  int depth = 6;
  int refine = 0;
  std::string method = "certified";  ///< mesh: certified or octree
  int resolution = 256;              ///< mesh, certified: as `iaa mesh --resolution`
  int max_depth = CertifiedMeshSettings{}.max_depth;
  int threads = 0;
  bool quiet = false;
  ViewOptions view;
};

EncloseSettings enclose_settings(const Scene& scene, const ShortcutOptions& o) {
  EncloseSettings s;
  s.bounds = scene.bounds;
  s.depth = o.depth;
  s.refine_possible = o.refine;
  s.validate();
  return s;
}

Layer enclosure_layer(const Enclosure& enc, const Scene& scene, const EncloseSettings& s,
                      const std::string& name) {
  Layer l;
  l.name = name;
  l.data = enclosure_to_grid(enc, EnclosureInfo{scene.expression, s});
  l.role = LayerRole::kEnclosure;
  return l;
}

/// The threads and progress bar the options ask for.
struct ShortcutExec {
  explicit ShortcutExec(const ShortcutOptions& o) : bar(o.quiet) {
    exec.threads = o.threads;
    exec.progress = &bar;
  }
  app::ProgressBar bar;
  Exec exec;
};

std::string default_title(const Scene& scene, const std::string& what) {
  return (scene.name.empty() ? std::string("scene") : scene.name) + ": " + what;
}

void run_enclose(const ShortcutOptions& o) {
  const Scene scene = app::load_scene(o.scene, o.sets);
  const EncloseSettings s = enclose_settings(scene, o);
  const ShortcutExec run(o);
  const Enclosure enc = enclose(*scene.tape, s, run.exec);
  const std::uint64_t crossing = enc.count(CellClass::kCrossing);
  const std::uint64_t possible = enc.count(CellClass::kPossible);
  std::printf(
      "enclosure: %zu boxes (%llu crossing, %llu possible), depth %d%s, %llu evaluations\n",
      enc.cells.size(), static_cast<unsigned long long>(crossing),
      static_cast<unsigned long long>(possible), s.depth,
      s.refine_possible ? (" + " + std::to_string(s.refine_possible) + " refined").c_str() : "",
      static_cast<unsigned long long>(enc.evaluations));
  if (enc.cells.empty()) {
    throw Error("the enclosure is empty: no part of the surface lies inside the bounds of '" +
                o.scene + "', nothing to show");
  }
  std::vector<Layer> layers{enclosure_layer(enc, scene, s, "enclosure")};
  ViewOptions v = o.view;
  if (v.title.empty()) {
    v.title = default_title(scene, "enclosure at depth " + std::to_string(s.depth) + ", " +
                                       std::to_string(enc.cells.size()) + " boxes");
  }
  show(layers, v, std::nullopt, &scene);
}

Layer mesh_layer(const TriangleSoup& soup) {
  Layer m;
  m.name = "mesh";
  m.data = soup_to_polydata(soup);
  m.role = LayerRole::kMesh;
  return m;
}

/// What a mesher left for the left view: the mesh and the boxes it could not handle, and the
/// caption that counts them.
struct MeshView {
  std::vector<Layer> layers;
  std::string caption;
};

/// The certified mesh (the default of `iaa mesh`) with its uncertified cells in red.
MeshView certified_view(const Scene& scene, const ShortcutOptions& o, const Exec& exec) {
  // The same settings as `iaa mesh --resolution N --max-depth D` (app/meshing.h).
  app::meshing::MeshParams params;
  params.resolution = o.resolution;
  params.max_depth = o.max_depth;
  const app::meshing::MeshRun mesh = app::meshing::run_mesher(
      app::meshing::Method::kCertified, app::meshing::surface_of(scene), params, exec, nullptr);
  std::printf("mesh: certified, %zu vertices, %zu triangles, %llu leaves, %zu uncertified cells\n",
              mesh.soup.vertices.size(), mesh.soup.triangles.size(),
              static_cast<unsigned long long>(mesh.details.value("leaves", std::uint64_t{0})),
              mesh.uncertified.size());
  MeshView v;
  if (!mesh.soup.empty()) v.layers.push_back(mesh_layer(mesh.soup));
  if (!mesh.uncertified.empty()) {
    std::vector<LabelledBox> boxes;
    for (const UncertifiedCell& c : mesh.uncertified) boxes.push_back({c.box, c.depth, c.reason});
    Layer u;
    u.name = "uncertified cells";
    u.data = boxes_to_grid(boxes, scene.expression);
    u.role = LayerRole::kUncertified;
    v.layers.push_back(std::move(u));
  }
  v.caption = "certified mesh: " + std::to_string(mesh.soup.triangles.size()) + " triangles, " +
              (mesh.uncertified.empty()
                   ? std::string("topology certified")
                   : std::to_string(mesh.uncertified.size()) + " uncertified cells (red)");
  return v;
}

/// The octree mesh of the enclosure, with the possible boxes it could not mesh.
MeshView octree_view(const Scene& scene, const ShortcutOptions& o, const Enclosure& enc,
                     const Exec& exec) {
  OctreeMeshSettings ms;
  ms.enclose = enclose_settings(scene, o);
  ms.validate();
  const OctreeMesh mesh = extract_mesh(*scene.tape, enc, ms, exec);
  std::printf(
      "mesh: octree, %zu vertices, %zu triangles from %zu boxes; %llu possible boxes not "
      "meshed\n",
      mesh.soup.vertices.size(), mesh.soup.triangles.size(), enc.cells.size(),
      static_cast<unsigned long long>(mesh.unmeshed.size()));
  MeshView v;
  if (!mesh.soup.empty()) v.layers.push_back(mesh_layer(mesh.soup));
  // Boxes the mesher could not mesh may still hold surface: show them beside the mesh.
  if (!mesh.unmeshed.empty()) {
    Enclosure rest;
    rest.bounds = enc.bounds;
    rest.cells = mesh.unmeshed;
    v.layers.push_back(enclosure_layer(rest, scene, ms.enclose, "unmeshed possible boxes"));
  }
  v.caption = "octree mesh: " + std::to_string(mesh.soup.triangles.size()) + " triangles";
  return v;
}

void run_mesh(const ShortcutOptions& o) {
  const Scene scene = app::load_scene(o.scene, o.sets);
  if (o.method != "certified" && o.method != "octree") {
    throw Error("--method: unknown mesher '" + o.method + "'; use certified or octree");
  }
  const EncloseSettings es = enclose_settings(scene, o);
  const ShortcutExec run(o);
  const Enclosure enc = enclose(*scene.tape, es, run.exec);
  MeshView mv = o.method == "certified" ? certified_view(scene, o, run.exec)
                                        : octree_view(scene, o, enc, run.exec);
  std::vector<Layer> layers = std::move(mv.layers);
  if (!enc.cells.empty()) {
    Layer e = enclosure_layer(enc, scene, es, "enclosure");
    e.viewport = 1;
    layers.push_back(std::move(e));
  }
  if (layers.empty()) {
    throw Error("no surface inside the bounds of '" + o.scene + "': nothing to show");
  }
  ViewOptions v = o.view;
  v.viewports = 2;
  if (v.captions.empty()) {
    v.captions = {mv.caption, "enclosure: " + std::to_string(enc.cells.size()) + " boxes"};
  }
  if (v.title.empty())
    v.title = default_title(
        scene, o.method + " mesh, and the enclosure at depth " + std::to_string(o.depth));
  if (o.view.size == ViewOptions{}.size) v.size = "1200x600";
  show(layers, v, std::nullopt, &scene);
}

}  // namespace

int run_shortcut(const char* name, int argc, char** argv) {
  const bool is_mesh = std::string(name) == "mesh";
  CLI::App app{is_mesh ? "iaa-viz mesh: mesh a scene's surface (certified by default, as iaa mesh) "
                         "and show the mesh with the cells it could not certify in red (left) "
                         "next to the scene's enclosure (right)"
                       : "iaa-viz enclose: compute the guaranteed enclosure of a scene's surface "
                         "and show its boxes, coloured by class (crossing / possible)",
               std::string("iaa-viz ") + name};
  ShortcutOptions o;
  app.add_option("scene", o.scene, "the scene file (TOML)")->required();
  app.add_option("--depth", o.depth, "leaf depth of the enclosure (cells are bounds / 2^depth)")
      ->capture_default_str();
  app.add_option("--refine", o.refine, "extra levels for possible boxes")->capture_default_str();
  if (is_mesh) {
    app.add_option("--method", o.method,
                   "certified (isotopic inside certified cells, as iaa mesh) or octree (from the "
                   "enclosure at --depth)")
        ->capture_default_str();
    app.add_option("--resolution", o.resolution,
                   "certified: cells of at most 2 edge/N, as iaa mesh --resolution (2..4096)")
        ->capture_default_str();
    app.add_option("--max-depth", o.max_depth,
                   "certified: splits below the root cells at most; deeper cells are uncertified")
        ->capture_default_str();
  }
  app.add_option("--set", o.sets, "override a scene key, e.g. --set camera.fov=30 (repeatable)");
  app.add_option("-j,--threads", o.threads, "worker threads (0 = all)");
  app.add_flag("-q,--quiet", o.quiet, "no progress bar");
  add_view_options(app, o.view);
  app.footer(is_mesh
                 ? "Examples:\n"
                   "  iaa-viz mesh data/scenes/teardrop.toml -o teardrop-mesh.png\n"
                   "  iaa-viz mesh data/scenes/chubs.toml --resolution 128 --camera auto\n"
                   "  iaa-viz mesh data/scenes/teardrop.toml --method octree --depth 7 --refine 2\n"
                 : "Examples:\n"
                   "  iaa-viz enclose data/scenes/teardrop.toml --depth 6 -o boxes.png\n"
                   "  iaa-viz enclose data/scenes/chubs.toml --depth 5 --camera auto --size "
                   "640x480 -o b.png");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // Bad view options or a window without a display are reported before the computation.
  check_view(o.view);
  if (is_mesh) {
    run_mesh(o);
  } else {
    run_enclose(o);
  }
  return 0;
}

}  // namespace iaa::viz
