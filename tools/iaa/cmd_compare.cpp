// `iaa compare`: ray-casts a mesh with a scene's camera and sets it against the IAA certificates
// of the same view: lost pixels (IAA certifies surface, the mesh shows none), wrong pixels (IAA
// certifies empty, the mesh shows surface). Writes a diff picture and a JSON report.
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/comparing.h"
#include "app/files.h"
#include "app/png.h"
#include "app/progress_bar.h"
#include "app/scene_loading.h"
#include "compare/compare.h"
#include "core/error.h"
#include "iaa/command.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_raycast.h"
#include "render/render.h"

namespace iaa::cli {
namespace {

struct CompareOptions {
  std::string scene;
  std::string mesh;
  std::string output;
  std::string report;
  std::vector<std::string> sets;
  int rays = 4;
  int threads = 0;
  bool quiet = false;
};

/// Throws when this build cannot read or ray-cast meshes, naming exactly the option(s) it
/// switched off.
void check_build() {
#if !defined(IAA_HAVE_CGAL) || !defined(IAA_HAVE_OPENMESH)
  std::string missing;
#ifndef IAA_HAVE_CGAL
  missing = "CGAL (IAA_WITH_CGAL=OFF)";
#endif
#ifndef IAA_HAVE_OPENMESH
  missing +=
      std::string(missing.empty() ? "" : " and without ") + "OpenMesh (IAA_WITH_OPENMESH=OFF)";
#endif
  throw Error("this iaa was built without " + missing +
              ": meshes cannot be read or ray-cast, no file was written");
#endif
}

/// Everything that can be checked before the scene and mesh are read, so that the command fails
/// before its work rather than after it.
void check_options(const CompareOptions& o) {
  if (o.threads < 0)
    throw SettingError("--threads must be 0 (all) or more, got " + std::to_string(o.threads));
  check_build();
  if (app::extension_of(o.output) != "png") {
    throw Error("-o: the diff picture must be a .png file, got '" + o.output + "'");
  }
  if (!o.report.empty() && app::extension_of(o.report) != "json") {
    throw Error("--report: the report must be a .json file, got '" + o.report + "'");
  }
  app::check_rays(o.rays);
}

#if defined(IAA_HAVE_CGAL) && defined(IAA_HAVE_OPENMESH)
/// The scene (with its --set overrides) and the mesh to set against it.
struct Inputs {
  Scene scene;
  TriangleSoup mesh;
};

Inputs load(const CompareOptions& o) {
  Scene scene = app::load_scene(o.scene, o.sets);
  const MeshFormat format = mesh_format_from_extension(app::extension_of(o.mesh));
  // Held as an OpenMesh TriMesh on reading; cast as plain triangles (exact in PLY files written
  // by iaa mesh, float from other files).
  TriangleSoup mesh = decode_mesh(app::read_file(o.mesh), format, o.mesh).triangles();
  check_mesh(mesh, o.mesh);
  return {std::move(scene), std::move(mesh)};
}

/// The IAA render and the mesh's ray cast of the same view, under a progress bar.
app::ComparedViews cast_both(const CompareOptions& o, const Inputs& in) {
  app::ProgressBar bar(o.quiet);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  app::ComparedViews v = app::compare_views(in.scene, in.mesh, o.rays, exec);
  bar.finish();
  return v;
}

/// The summary on stdout: the counts per verdict, the times and what was written.
void print_summary(const CompareOptions& o, const Inputs& in, const app::ComparedViews& v) {
  const CompareCounts& k = v.cmp.counts;
  std::printf("scene        %s (%dx%d), mesh %s: %zu triangles\n", in.scene.name.c_str(),
              v.film.width, v.film.height, o.mesh.c_str(), in.mesh.triangles.size());
  std::printf("lost         %llu pixels (IAA certifies surface, the mesh shows none)\n",
              (unsigned long long)k.lost);
  std::printf("wrong        %llu pixels (IAA certifies empty, the mesh shows surface)\n",
              (unsigned long long)k.wrong);
  std::printf("agree        %llu surface, %llu empty\n", (unsigned long long)k.both_surface,
              (unsigned long long)k.both_empty);
  std::printf("uncertain    %llu pixels IAA could not decide: %llu with mesh, %llu without\n",
              (unsigned long long)(k.uncertain_mesh + k.uncertain_empty),
              (unsigned long long)k.uncertain_mesh, (unsigned long long)k.uncertain_empty);
  std::printf("time         render %.3f s, mesh cast %.3f s\n", v.t_render, v.t_cast);
  std::printf("wrote        %s (red: lost, blue: wrong, amber: undecided without mesh)\n",
              o.output.c_str());
}

/// The --report JSON: the summary's figures and where the lost and wrong pixels are.
void write_report(const CompareOptions& o, const Inputs& in, const app::ComparedViews& v) {
  const nlohmann::json j = app::compare_report_json(in.scene, o.mesh, in.mesh, o.rays, v);
  app::write_text_atomically(o.report, j.dump(2) + "\n");
  std::printf("report       %s\n", o.report.c_str());
}
#endif

void run(const CompareOptions& o) {
  check_options(o);
#if defined(IAA_HAVE_CGAL) && defined(IAA_HAVE_OPENMESH)
  const Inputs in = load(o);
  const app::ComparedViews v = cast_both(o, in);
  Exec exec;  // the image's conversion and compression in --threads threads
  exec.threads = o.threads;
  exec.run([&] { app::write_png(o.output, app::diff_image(v)); });
  print_summary(o, in, v);
  if (!o.report.empty()) write_report(o, in, v);
#endif
}

void setup(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  app.add_option("scene", o->scene, "scene file (TOML): surface, camera and image size")
      ->required();
  app.add_option("--mesh", o->mesh, "mesh file (.ply, .obj, .off, .stl)")->required();
  app.add_option("-o,--output", o->output, "diff picture (.png)")->required();
  app.add_option("--report", o->report, "write the counts as JSON");
  app.add_option("--set", o->sets, "override a scene key, e.g. image.width=200 (repeatable)");
  app.add_option("--rays", o->rays,
                 "rays per pixel side for the covered-area figure only (1..16); the verdicts "
                 "use the whole-pixel beam test")
      ->capture_default_str();
  app.add_option("--threads", o->threads, "worker threads, 0 = all")->capture_default_str();
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.footer(
      "A pixel shows the mesh when any ray through its area meets a triangle: the pixel's whole\n"
      "beam is tested against the AABB tree, so thin triangles are not missed between sample "
      "rays.\n"
      "Lost and wrong pixels come from that test; --rays only measures the covered area.\n"
      "Examples:\n"
      "  iaa mesh data/scenes/teardrop.toml -o teardrop.ply\n"
      "  iaa compare data/scenes/teardrop.toml --mesh teardrop.ply -o diff.png --report diff.json\n"
      "  iaa compare data/scenes/chubs.toml --mesh chubs.obj -o diff.png --set image.width=250 "
      "--set image.height=250");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{{"compare",
                      "set a mesh against the ray trace's certificates: lost and wrong pixels", 45,
                      setup}};

}  // namespace
}  // namespace iaa::cli
