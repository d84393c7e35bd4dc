// `iaa bench mesh`: the four meshers on the paper's five surfaces at one resolution, each mesh
// set against the IAA render of its scene: wall time, triangles, lost and wrong pixels, in one run.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

#include "app/files.h"
#include "app/scene_loading.h"
#include "compare/compare.h"
#include "iaa/bench.h"
#include "iaa/bench_scenes.h"
#include "iaa/mesh_common.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_raycast.h"
#include "render/render.h"

namespace iaa::cli {
namespace {

struct Options {
  std::string scene_dir;
  std::vector<std::string> surfaces = {"teardrop", "chubs", "tritrumpet", "twist", "blobby"};
  std::vector<std::string> methods = {"certified", "octree", "cgal", "vtk"};
  meshing::MeshParams p;
  int image = 500;
  int runs = 3;
  int threads = 0;
  bool no_compare = false;
  bool no_scaling = false;
  std::string json;
};

void run(const Options& o) {
#if !defined(IAA_HAVE_CGAL) || !defined(IAA_HAVE_OPENMESH)
  throw Error("iaa bench mesh needs CGAL and OpenMesh (this iaa was built without them)");
#else
  if (o.runs < 1 || o.runs > 50)
    throw SettingError("--runs must be in 1..50, got " + std::to_string(o.runs));
  if (o.image < 8 || o.image > 4000)
    throw SettingError("--image must be in 8..4000, got " + std::to_string(o.image));
  o.p.validate();  // before the table's header
  const std::string dir = find_scene_dir(o.scene_dir);
  std::vector<meshing::Method> methods;
  for (const std::string& m : o.methods) methods.push_back(meshing::parse_mesh_method(m));
  Exec exec;
  exec.threads = o.threads;
  std::printf(
      "resolution %d (octree depth %d + refine %d, vtk grid %d, cgal facet size edge/%d), "
      "images %dx%d, %d threads\n",
      o.p.resolution, o.p.octree_depth(), o.p.refine, o.p.grid > 0 ? o.p.grid : o.p.resolution,
      o.p.resolution, o.image, o.image, exec.resolved_threads());
  std::printf("%-11s %-7s %9s %10s %8s %8s %10s  %s\n", "surface", "method", "time s", "triangles",
              "lost px", "wrong px", "undecided", "notes");
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : o.surfaces) {
    const std::string path = dir + "/" + name + ".toml";
    const std::string size = std::to_string(o.image);
    Scene scene = app::load_scene(path, {"image.width=" + size, "image.height=" + size});
    meshing::Surface s;
    s.name = scene.name;
    s.expression = scene.expression;
    s.tape = scene.tape;
    s.bounds = scene.bounds;
    RenderSettings rs = scene.settings;
    rs.method = RenderMethod::kIaa;
    const Film film = o.no_compare ? Film{} : render(scene, rs, exec);
    double certified_seconds = 0;
    for (meshing::Method m : methods) {
      // Median time over runs (CGAL, the slowest, once); the mesh of the last run is compared.
      const int runs = m == meshing::Method::kCgal ? 1 : o.runs;
      std::vector<double> times;
      static const char* kPhases[] = {"seconds_enclose", "seconds_signs", "seconds_extract",
                                      "seconds_vertices"};
      std::vector<std::vector<double> > phases(4);
      meshing::MeshRun last;
      for (int r = 0; r < runs; ++r) {
        last = meshing::run_mesher(m, s, o.p, exec);
        times.push_back(last.seconds);
        for (int ph = 0; ph < 4; ++ph) {
          if (last.details.contains(kPhases[ph]))
            phases[ph].push_back(last.details[kPhases[ph]].get<double>());
        }
      }
      const auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      const double t = median(times);
      round_to_file_precision(last.soup);
      CompareCounts k;
      if (!o.no_compare) {
        if (!last.soup.empty())
          k = compare_with_film(film, view_mesh(last.soup, scene, 1, exec).any).counts;
        else
          k.lost = film.stats.covered;
      }
      std::string notes;
      if (last.details.contains("unmeshed_possible_leaves")) {
        notes = last.details["unmeshed_possible_leaves"].dump() + " possible leaves unmeshed";
      }
      if (m == meshing::Method::kCertified) {
        certified_seconds = t;
        notes = last.details["uncertified_leaves"].dump() + " uncertified cells, depth " +
                last.details["min_depth"].dump() + ".." + last.details["finest_depth"].dump();
      }
      if (m == meshing::Method::kVtk && certified_seconds > 0) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "certified/vtk time %.2fx", certified_seconds / t);
        notes = buf;
      }
      if (!phases[0].empty()) {  // the octree's phases, medians over the runs
        char buf[96];
        std::snprintf(buf, sizeof buf, "; phases %.3f/%.3f/%.3f/%.3f s", median(phases[0]),
                      median(phases[1]), median(phases[2]), median(phases[3]));
        notes += buf;
      }
      std::printf("%-11s %-7s %9.3f %10zu %8llu %8llu %10llu  %s\n", name.c_str(),
                  meshing::method_label(m), t, last.soup.triangles.size(),
                  (unsigned long long)k.lost, (unsigned long long)k.wrong,
                  (unsigned long long)k.uncertain_empty, notes.c_str());
      std::fflush(stdout);
      out.push_back({{"surface", name},
                     {"method", meshing::method_label(m)},
                     {"seconds_median", t},
                     {"runs", runs},
                     {"triangles", last.soup.triangles.size()},
                     {"lost_pixels", k.lost},
                     {"wrong_pixels", k.wrong},
                     {"undecided_without_mesh", k.uncertain_empty},
                     {"iaa_covered_pixels", film.stats.covered},
                     {"settings", last.details}});
    }
  }
  // CGAL Mesh_3's thread scaling: the first surface at half the resolution, 1 thread and all.
  nlohmann::json scaling;
  if (!o.no_scaling && exec.resolved_threads() > 1 && !o.surfaces.empty() &&
      std::find(methods.begin(), methods.end(), meshing::Method::kCgal) != methods.end()) {
    const std::string path = dir + "/" + o.surfaces.front() + ".toml";
    const Scene scene = app::load_scene(path);
    meshing::Surface s;
    s.name = scene.name;
    s.expression = scene.expression;
    s.tape = scene.tape;
    s.bounds = scene.bounds;
    meshing::MeshParams p = o.p;
    p.resolution = std::max(8, o.p.resolution / 2);
    std::printf("cgal thread scaling (%s, resolution %d):", s.name.c_str(), p.resolution);
    for (int threads : {1, exec.resolved_threads()}) {
      Exec e = exec;
      e.threads = threads;
      const std::clock_t c0 = std::clock();
      const meshing::MeshRun r = meshing::run_mesher(meshing::Method::kCgal, s, p, e);
      const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
      std::printf(" %d thread%s %.3f s (cpu %.3f s)%s", threads, threads > 1 ? "s" : "", r.seconds,
                  cpu, threads == 1 ? "," : "\n");
      scaling.push_back({{"threads", threads}, {"seconds", r.seconds}, {"cpu_seconds", cpu}});
      std::fflush(stdout);
    }
  }
  std::printf(
      "lost: IAA certifies surface in the pixel, the mesh shows none; wrong: IAA certifies\n"
      "the pixel empty, the mesh shows surface; undecided: IAA could not decide, no mesh there.\n"
      "octree phases: enclosure / grid signs / loop extraction / vertex placement.\n");
  if (!o.json.empty()) {
    nlohmann::json j = {{"rows", out}};
    if (!scaling.is_null()) j["cgal_thread_scaling"] = scaling;
    app::write_text_atomically(o.json, j.dump(2) + "\n");
  }
#endif
}

void setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("--scene-dir", o->scene_dir,
                 "directory of the scene files (default: data/scenes in the working directory, "
                 "else in the source tree above the executable)");
  app.add_option("--surface", o->surfaces, "surfaces (scene names) to run (repeatable)")
      ->capture_default_str();
  app.add_option("--method", o->methods,
                 "meshers to run: certified, octree, cgal, vtk (repeatable)")
      ->capture_default_str();
  app.add_option("--resolution", o->p.resolution, "grid resolution shared by the meshers")
      ->capture_default_str();
  app.add_option("--max-depth", o->p.max_depth, "certified: the certification depth limit")
      ->capture_default_str();
  app.add_option("--refine", o->p.refine, "octree: extra levels for possible leaves")
      ->capture_default_str();
  app.add_option("--flat-tolerance", o->p.flat_tolerance,
                 "octree: bend (of the leaf's edge) above which a loop of 3 or 4 gets a centre")
      ->capture_default_str();
  app.add_option("--image", o->image, "image size (square) of the compared views")
      ->capture_default_str();
  app.add_option("--runs", o->runs, "timed runs per mesher (median; cgal runs once)")
      ->capture_default_str();
  app.add_option("--threads", o->threads, "worker threads, 0 = all")->capture_default_str();
  app.add_flag("--no-scaling", o->no_scaling,
               "skip the cgal thread-scaling line (1 thread and all, half the resolution)");
  app.add_flag("--no-compare", o->no_compare,
               "time the meshers only: no render, no lost or wrong pixels (shown as 0)");
  app.add_option("--json", o->json, "also write the table as JSON");
  app.footer(
      "Examples:\n"
      "  iaa bench mesh\n"
      "  iaa bench mesh --surface teardrop --resolution 128 --json mesh.json");
  app.callback([o] { run(*o); });
}

BenchRegistrar reg{
    {"mesh", "certified, octree, cgal and vtk meshers: time, triangles, lost pixels", setup}};

}  // namespace
}  // namespace iaa::cli
