// `iaa-viz enclose SCENE` and `iaa-viz mesh SCENE` (see shortcuts.h).
#include "viz/app/shortcuts.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include "app/progress_bar.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "mesh/octree_mesher.h"
#include "viz/app/view_options.h"
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

std::string default_title(const Scene& scene, const std::string& what) {
  return (scene.name.empty() ? std::string("scene") : scene.name) + ": " + what;
}

void run_enclose(const ShortcutOptions& o) {
  const Scene scene = app::load_scene(o.scene, o.sets);
  const EncloseSettings s = enclose_settings(scene, o);
  app::ProgressBar bar(o.quiet);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const Enclosure enc = enclose(*scene.tape, s, exec);
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

void run_mesh(const ShortcutOptions& o) {
  const Scene scene = app::load_scene(o.scene, o.sets);
  OctreeMeshSettings ms;
  ms.enclose = enclose_settings(scene, o);
  ms.validate();
  app::ProgressBar bar(o.quiet);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const Enclosure enc = enclose(*scene.tape, ms.enclose, exec);
  const OctreeMesh mesh = extract_mesh(*scene.tape, enc, ms, exec);
  std::printf("mesh: %zu vertices, %zu triangles from %zu boxes; %llu possible boxes not meshed\n",
              mesh.soup.vertices.size(), mesh.soup.triangles.size(), enc.cells.size(),
              static_cast<unsigned long long>(mesh.unmeshed.size()));
  std::vector<Layer> layers;
  if (!mesh.soup.empty()) {
    Layer m;
    m.name = "mesh";
    m.data = soup_to_polydata(mesh.soup);
    m.role = LayerRole::kMesh;
    layers.push_back(std::move(m));
  }
  // Boxes the mesher could not mesh may still hold surface: show them beside the mesh.
  if (!mesh.unmeshed.empty()) {
    Enclosure rest;
    rest.bounds = enc.bounds;
    rest.cells = mesh.unmeshed;
    Layer u = enclosure_layer(rest, scene, ms.enclose, "unmeshed possible boxes");
    layers.push_back(std::move(u));
  }
  if (!enc.cells.empty()) {
    Layer e = enclosure_layer(enc, scene, ms.enclose, "enclosure");
    e.viewport = 1;
    layers.push_back(std::move(e));
  }
  if (layers.empty()) {
    throw Error("no surface inside the bounds of '" + o.scene + "': nothing to show");
  }
  ViewOptions v = o.view;
  v.viewports = 2;
  if (v.captions.empty()) {
    v.captions = {"octree mesh: " + std::to_string(mesh.soup.triangles.size()) + " triangles",
                  "enclosure: " + std::to_string(enc.cells.size()) + " boxes"};
  }
  if (v.title.empty())
    v.title = default_title(scene, "mesh and enclosure at depth " + std::to_string(o.depth));
  if (o.view.size == ViewOptions{}.size) v.size = "1200x600";
  show(layers, v, std::nullopt, &scene);
}

}  // namespace

int run_shortcut(const char* name, int argc, char** argv) {
  const bool is_mesh = std::string(name) == "mesh";
  CLI::App app{is_mesh ? "iaa-viz mesh: mesh a scene's surface with the octree mesher and show the "
                         "mesh (left) next to the enclosure it came from (right)"
                       : "iaa-viz enclose: compute the guaranteed enclosure of a scene's surface "
                         "and show its boxes, coloured by class (crossing / possible)",
               std::string("iaa-viz ") + name};
  ShortcutOptions o;
  app.add_option("scene", o.scene, "the scene file (TOML)")->required();
  app.add_option("--depth", o.depth, "leaf depth of the enclosure (cells are bounds / 2^depth)")
      ->capture_default_str();
  app.add_option("--refine", o.refine, "extra levels for possible boxes")->capture_default_str();
  app.add_option("--set", o.sets, "override a scene key, e.g. --set camera.fov=30 (repeatable)");
  app.add_option("-j,--threads", o.threads, "worker threads (0 = all)");
  app.add_flag("-q,--quiet", o.quiet, "no progress bar");
  add_view_options(app, o.view);
  app.footer(is_mesh
                 ? "Examples:\n"
                   "  iaa-viz mesh data/scenes/chubs.toml --depth 6 -o chubs-mesh.png\n"
                   "  iaa-viz mesh data/scenes/teardrop.toml --depth 7 --refine 2 --camera auto\n"
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
