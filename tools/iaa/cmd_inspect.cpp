// `iaa inspect`: why one pixel came out as it did. Runs the renderer's own code path for the pixel
// (render_pixel, the function render() calls per pixel) with a PixelTrace, and prints every
// beam (the screen blocks above the pixel, then its quadtree of sub-beams), every depth piece the
// search tested with its F bounds and verdict, the result, the estimator and the decision, the
// shading and the final colour: as an indented tree (inspect_text.h), or as JSON
// (inspect_json.h). `--vtk` writes the same as a VTK multiblock (viz/inspect_vtk.h) with the
// enclosure boxes and the octree mesh near the pixel.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/files.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "iaa/command.h"
#include "iaa/inspect_json.h"
#include "iaa/inspect_text.h"
#include "iaa/render_flags.h"
#include "mesh/octree_mesher.h"
#include "render/render.h"
#include "scene/camera.h"
#ifdef IAA_HAVE_VIZ
#include "iaa/viz_plugin.h"
#endif

namespace iaa::cli {
namespace {

struct InspectOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string pixel;
  RenderFlags flags;
  bool json = false;
  std::string vtk;
  int enclose_depth = 7;
  int refine_possible = 2;
  double near = 3;
  bool no_mesh = false;
};

#ifdef IAA_HAVE_VIZ
// ---- What lies near the pixel ---------------------------------------------------------------

/// Screen rectangle of a pixel widened by `near` pixels, and a test of whether points project
/// into it.
struct ScreenWindow {
  const CameraFrame& frame;
  double u0, v0, u1, v1;

  /// True when the bounding rectangle of the points' projections meets the window; points
  /// behind the eye make the answer false (they are never in view).
  template <class Points>
  bool meets(const Points& pts) const {
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY;
    for (const Vec3& p : pts) {
      const Vec3 rel = p - frame.eye;
      const double t = dot(rel, frame.forward);
      if (!(t > 0)) return false;
      const double u = dot(rel, frame.right) / (t * frame.scale) + frame.half_w;
      const double v = frame.half_h - dot(rel, frame.up) / (t * frame.scale);
      lo_u = std::fmin(lo_u, u);
      hi_u = std::fmax(hi_u, u);
      lo_v = std::fmin(lo_v, v);
      hi_v = std::fmax(hi_v, v);
    }
    return lo_u <= u1 && hi_u >= u0 && lo_v <= v1 && hi_v >= v0;
  }
};

struct Nearby {
  EncloseSettings settings;
  Enclosure enclosure;  ///< cells near the pixel
  std::uint64_t all_cells = 0;
  bool have_mesh = false;
  TriangleSoup mesh;  ///< triangles near the pixel
  std::uint64_t all_triangles = 0;
};

Nearby nearby(const Scene& scene, const InspectOptions& o, int x, int y) {
  Nearby n;
  n.settings.bounds = scene.bounds;
  n.settings.depth = o.enclose_depth;
  n.settings.refine_possible = o.refine_possible;
  try {
    n.settings.validate();
  } catch (const SettingError& e) {
    throw SettingError(std::string("--enclose-depth / --refine-possible: ") + e.what());
  }
  const Enclosure enc = enclose(*scene.tape, n.settings);
  n.all_cells = enc.cells.size();
  const CameraFrame frame(scene.camera, scene.width, scene.height);
  const ScreenWindow win{frame, x - o.near, y - o.near, x + 1 + o.near, y + 1 + o.near};
  n.enclosure.bounds = enc.bounds;
  n.enclosure.counts_by_depth.assign(enc.counts_by_depth.size(), {0, 0});
  for (const Cell& c : enc.cells) {
    const Box3 b = enc.box(c);
    std::array<Vec3, 8> corners;
    for (int k = 0; k < 8; ++k) {
      corners[static_cast<std::size_t>(k)] = {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                                              (k & 4) ? b.hi.z : b.lo.z};
    }
    if (!win.meets(corners)) continue;
    n.enclosure.cells.push_back(c);
    ++n.enclosure.counts_by_depth[c.depth][c.cls == CellClass::kCrossing ? 0 : 1];
  }
  if (o.no_mesh || enc.cells.empty()) return n;
  OctreeMeshSettings ms;
  ms.enclose = n.settings;
  ms.validate();
  const OctreeMesh mesh = extract_mesh(*scene.tape, enc, ms);
  n.have_mesh = true;
  n.all_triangles = mesh.soup.triangles.size();
  std::vector<std::uint32_t> remap(mesh.soup.vertices.size(), UINT32_MAX);
  for (const auto& t : mesh.soup.triangles) {
    const std::array<Vec3, 3> p = {mesh.soup.vertices[t[0]], mesh.soup.vertices[t[1]],
                                   mesh.soup.vertices[t[2]]};
    if (!win.meets(p)) continue;
    std::array<std::uint32_t, 3> nt{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& m = remap[t[static_cast<std::size_t>(k)]];
      if (m == UINT32_MAX) {
        m = static_cast<std::uint32_t>(n.mesh.vertices.size());
        n.mesh.vertices.push_back(mesh.soup.vertices[t[static_cast<std::size_t>(k)]]);
      }
      nt[static_cast<std::size_t>(k)] = m;
    }
    n.mesh.triangles.push_back(nt);
  }
  return n;
}

#endif  // IAA_HAVE_VIZ

// ---- The command ------------------------------------------------------------------------------

/// Everything that can be checked before the work: the --vtk output, the enclosure options and
/// the type of the scene file.
void check_options(const InspectOptions& o) {
#ifndef IAA_HAVE_VIZ
  if (!o.vtk.empty()) {
    throw Error("--vtk: this iaa was built without VTK (IAA_WITH_VTK=OFF); no .vtm output");
  }
#endif
  if (!o.vtk.empty()) {
    const std::string ext = std::filesystem::path(o.vtk).extension().string();
    if (ext != ".vtm" && ext != ".VTM") {
      throw Error("--vtk: the output must be a .vtm file (a VTK multiblock), got '" + o.vtk + "'");
    }
    app::check_writable(o.vtk, "--vtk: ");
#ifdef IAA_HAVE_VIZ
    viz_plugin("--vtk");  // a missing plugin is said before the work
#endif
  }
  if (o.enclose_depth < 0 || o.enclose_depth > EncloseSettings::kMaxDepth) {
    throw SettingError("--enclose-depth must lie in 0.." +
                       std::to_string(EncloseSettings::kMaxDepth) + " (0: no enclosure), got " +
                       std::to_string(o.enclose_depth));
  }
  if (!(o.near >= 0 && o.near <= 1000)) {
    throw SettingError("--near must lie in 0..1000 pixels, got " + num_text(o.near));
  }
  std::string ext = std::filesystem::path(o.scene).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!ext.empty() && ext != ".toml") {
    throw Error("'" + o.scene + "': unknown file type '" + ext +
                "'; iaa inspect reads a scene file (.toml, see docs/scene-format.md)");
  }
}

/// Throws when pixel x, y lies outside the scene's image.
void check_pixel(const Scene& scene, int x, int y) {
  if (x < 0 || y < 0 || x >= scene.width || y >= scene.height) {
    throw Error("--pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                std::to_string(scene.width) + "x" + std::to_string(scene.height) +
                " image: X must lie in 0.." + std::to_string(scene.width - 1) + " and Y in 0.." +
                std::to_string(scene.height - 1));
  }
}

#ifdef IAA_HAVE_VIZ
/// Writes the --vtk multiblock of the traced pixel x, y; returns the line that says what it holds.
std::string write_vtk(const InspectOptions& o, const Scene& scene, const RenderSettings& st,
                      const PixelTrace& trace, int x, int y) {
  viz::InspectionInput in;
  in.scene = &scene;
  in.settings = st;
  in.trace = &trace;
  Nearby n;
  if (o.enclose_depth > 0) {
    n = nearby(scene, o, x, y);
    in.enclosure = &n.enclosure;
    in.enclose_settings = n.settings;
    if (n.have_mesh) in.mesh = &n.mesh;
  }
  viz_plugin("--vtk").write_inspection_vtm(o.vtk, in);
  std::string wrote = "wrote " + o.vtk;
  if (o.enclose_depth > 0) {
    wrote += " with " + std::to_string(n.enclosure.cells.size()) + " of " +
             std::to_string(n.all_cells) + " enclosure boxes (depth " +
             std::to_string(o.enclose_depth) + ") and " +
             (n.have_mesh ? std::to_string(n.mesh.triangles.size()) + " of " +
                                std::to_string(n.all_triangles) + " mesh triangles"
                          : std::string("no mesh")) +
             " within " + num_text(o.near) + " pixels of the pixel";
  }
  return wrote;
}
#endif  // IAA_HAVE_VIZ

void run(const InspectOptions& o) {
  check_options(o);
  const auto px = parse_int_pair(o.pixel, "--pixel");
  const Scene scene = app::load_scene(o.scene, with_image_size(o.flags, o.sets));
  const int x = px[0], y = px[1];
  check_pixel(scene, x, y);
  RenderSettings st = scene.settings;
  apply_render_flags(o.flags, &st);

  PixelTrace trace;
  const PixelResult r = render_pixel(scene, st, x, y, &trace);

  // The .vtm first: when it cannot be written, nothing is printed either.
  std::string wrote;
#ifdef IAA_HAVE_VIZ
  if (!o.vtk.empty()) wrote = write_vtk(o, scene, st, trace, x, y);
#endif
  if (o.json) {
    nlohmann::json j = inspection_json(scene, o.scene, st, trace, r);
    if (!o.vtk.empty()) j["vtk"] = o.vtk;
    std::printf("%s\n", j.dump(1).c_str());
  } else {
    print_inspection_tree(scene, st, trace, r);
    if (!wrote.empty()) std::printf("%s\n", wrote.c_str());
  }
}

void setup(CLI::App& app) {
  auto o = std::make_shared<InspectOptions>();
  add_scene_options(app, &o->scene, &o->sets);
  app.add_option("--pixel", o->pixel, "the pixel X,Y (column from the left, row from the top)")
      ->required();
  add_render_flags(app, &o->flags, kMethodFlag | kImageSizeFlags);
  app.add_flag("--json", o->json, "print the trace as JSON instead of a tree");
  app.add_option("--vtk", o->vtk,
                 "write a VTK multiblock (.vtm): beam pyramids, hit slabs, depth boxes, hit "
                 "points, enclosure boxes and mesh near the pixel (view with iaa-viz)");
  app.add_option("--enclose-depth", o->enclose_depth,
                 "--vtk: depth of the enclosure whose boxes near the pixel are shown (0: none)")
      ->capture_default_str();
  app.add_option("--refine-possible", o->refine_possible,
                 "--vtk: extra levels for possible enclosure boxes")
      ->capture_default_str();
  app.add_option("--near", o->near,
                 "--vtk: boxes and triangles whose projection comes within this many pixels of "
                 "the pixel are shown")
      ->capture_default_str();
  app.add_flag("--no-mesh", o->no_mesh, "--vtk: do not mesh the enclosure");
  app.footer(
      "The pixel goes through exactly the code the full render runs for it (the screen blocks\n"
      "above it, then its beams), so its colour and certificate are those of `iaa render` with\n"
      "the same options.\n\n"
      "Examples:\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --json > neck.json\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --vtk neck.vtm\n"
      "  iaa-viz neck.vtm -o neck.png\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --method point\n"
      "  iaa inspect data/scenes/chubs.toml --pixel 100,120 --max-level 3 --threshold 0.5\n"
      "See docs/inspect.md.");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{{"inspect",
                      "why one pixel came out as it did: every beam, depth test and decision", 25,
                      setup}};

}  // namespace
}  // namespace iaa::cli
