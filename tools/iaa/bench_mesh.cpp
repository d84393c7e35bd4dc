// `iaa bench mesh`: the four meshers on the paper's five surfaces at one resolution, each mesh
// set against the IAA render of its scene: wall time, triangles, lost and wrong pixels, and the
// peak resident memory of a mesher's run (bench.h, PeakMemory), in one run.
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

#if defined(IAA_HAVE_CGAL) && defined(IAA_HAVE_OPENMESH)
/// Everything checked before the table's header is printed.
void check_options(const Options& o) {
  if (o.runs < 1 || o.runs > 50)
    throw SettingError("--runs must be in 1..50, got " + std::to_string(o.runs));
  if (o.image < 8 || o.image > 4000)
    throw SettingError("--image must be in 8..4000, got " + std::to_string(o.image));
  o.p.validate();
}

/// The settings line and the table's column heads.
void print_header(const Options& o, const Exec& exec) {
  std::printf(
      "resolution %d (octree depth %d + refine %d, vtk grid %d, cgal facet size edge/%d), "
      "images %dx%d, %d thread%s\n",
      o.p.resolution, o.p.octree_depth(), o.p.refine, o.p.grid > 0 ? o.p.grid : o.p.resolution,
      o.p.resolution, o.image, o.image, exec.resolved_threads(),
      exec.resolved_threads() == 1 ? "" : "s");
  std::printf("%-11s %-7s %9s %10s %8s %8s %10s %9s  %s\n", "surface", "method", "time s",
              "triangles", "lost px", "wrong px", "undecided", "peak MiB", "notes");
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// One mesher's timed runs: the median time, the octree's phase times per run and the last
/// run's mesh (the one compared).
struct Timed {
  int runs = 0;
  double seconds = 0;
  std::vector<std::vector<double> > phases;
  meshing::MeshRun last;
  std::uint64_t peak_bytes = 0;  ///< the largest peak resident memory of the runs
  bool peak_exact = true;        ///< every run's peak was its own (PeakMemory::exact)
};

/// Runs the mesher --runs times (CGAL, the slowest, once) and takes the median time.
Timed time_mesher(const Options& o, meshing::Method m, const meshing::Surface& s,
                  const Exec& exec) {
  // The phases each of our meshers reports (their medians go into the row's notes).
  static const char* kOctree[] = {"seconds_enclose", "seconds_signs", "seconds_extract",
                                  "seconds_vertices"};
  static const char* kCertified[] = {"seconds_refine", "seconds_table", "seconds_extract",
                                     "seconds_assemble"};
  const char* const* phases = m == meshing::Method::kCertified ? kCertified : kOctree;
  Timed tm;
  tm.runs = m == meshing::Method::kCgal ? 1 : o.runs;
  tm.phases.resize(4);
  std::vector<double> times;
  for (int r = 0; r < tm.runs; ++r) {
    tm.last = {};  // the previous run's mesh is not part of this run's peak
    const PeakMemory memory;
    tm.last = meshing::run_mesher(m, s, o.p, exec);
    tm.peak_bytes = std::max(tm.peak_bytes, memory.peak_bytes());
    tm.peak_exact = tm.peak_exact && memory.exact();
    times.push_back(tm.last.seconds);
    for (int ph = 0; ph < 4; ++ph) {
      if (tm.last.details.contains(phases[ph]))
        tm.phases[ph].push_back(tm.last.details[phases[ph]].get<double>());
    }
  }
  tm.seconds = median(times);
  return tm;
}

/// The mesh (rounded as a file would hold it) set against the IAA render; an empty mesh loses
/// every pixel IAA covers.
CompareCounts compare_mesh(const Options& o, TriangleSoup& soup, const Film& film,
                           const Scene& scene, const Exec& exec) {
  round_to_file_precision(soup);
  CompareCounts k;
  if (!o.no_compare) {
    if (!soup.empty())
      k = compare_with_film(film, view_mesh(soup, scene, 1, exec).any).counts;
    else
      k.lost = film.stats.covered;
  }
  return k;
}

/// The row's notes: what the mesher left unmeshed or uncertified, certified against VTK's time,
/// and the phases of our meshers.
std::string notes_for(meshing::Method m, const Timed& tm, double certified_seconds) {
  const nlohmann::json& d = tm.last.details;
  std::string notes;
  if (d.contains("unmeshed_possible_leaves")) {
    notes = d["unmeshed_possible_leaves"].dump() + " possible leaves unmeshed";
  }
  if (m == meshing::Method::kCertified) {
    notes = d["uncertified_leaves"].dump() + " uncertified cells, depth " + d["min_depth"].dump() +
            ".." + d["finest_depth"].dump();
  }
  if (m == meshing::Method::kVtk && certified_seconds > 0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "certified/vtk time %.2fx", certified_seconds / tm.seconds);
    notes = buf;
  }
  if (!tm.phases[0].empty()) {  // our meshers' phases, medians over the runs
    char buf[96];
    std::snprintf(buf, sizeof buf, "; phases %.3f/%.3f/%.3f/%.3f s", median(tm.phases[0]),
                  median(tm.phases[1]), median(tm.phases[2]), median(tm.phases[3]));
    notes += buf;
  }
  return notes;
}

/// Every mesher on one surface: a table row each (printed as soon as it is done) and a JSON row.
void bench_surface(const Options& o, const std::string& dir, const std::string& name,
                   const std::vector<meshing::Method>& methods, const Exec& exec,
                   nlohmann::json& out) {
  const std::string size = std::to_string(o.image);
  const Scene scene =
      app::load_scene(dir + "/" + name + ".toml", {"image.width=" + size, "image.height=" + size});
  const meshing::Surface s = meshing::surface_of(scene);
  RenderSettings rs = scene.settings;
  rs.method = RenderMethod::kIaa;
  const Film film = o.no_compare ? Film{} : render(scene, rs, exec);
  double certified_seconds = 0;
  for (meshing::Method m : methods) {
    Timed tm = time_mesher(o, m, s, exec);
    const CompareCounts k = compare_mesh(o, tm.last.soup, film, scene, exec);
    const std::string notes = notes_for(m, tm, certified_seconds);
    if (m == meshing::Method::kCertified) certified_seconds = tm.seconds;
    std::printf("%-11s %-7s %9.3f %10zu %8llu %8llu %10llu %8.1f%s  %s\n", name.c_str(),
                meshing::method_label(m), tm.seconds, tm.last.soup.triangles.size(),
                (unsigned long long)k.lost, (unsigned long long)k.wrong,
                (unsigned long long)k.uncertain_empty, mib(tm.peak_bytes),
                tm.peak_exact ? " " : "*", notes.c_str());
    std::fflush(stdout);
    out.push_back({{"surface", name},
                   {"method", meshing::method_label(m)},
                   {"seconds_median", tm.seconds},
                   {"runs", tm.runs},
                   {"triangles", tm.last.soup.triangles.size()},
                   {"lost_pixels", k.lost},
                   {"wrong_pixels", k.wrong},
                   {"undecided_without_mesh", k.uncertain_empty},
                   {"iaa_covered_pixels", film.stats.covered},
                   {"peak_rss_mib", mib(tm.peak_bytes)},
                   {"peak_rss_per_run", tm.peak_exact},
                   {"settings", tm.last.details}});
  }
}

/// CGAL Mesh_3's thread scaling: the first surface at half the resolution, 1 thread and all;
/// null when skipped (--no-scaling, one thread, or no cgal among the methods).
nlohmann::json cgal_scaling(const Options& o, const std::string& dir,
                            const std::vector<meshing::Method>& methods, const Exec& exec) {
  nlohmann::json scaling;
  if (o.no_scaling || exec.resolved_threads() <= 1 || o.surfaces.empty() ||
      std::find(methods.begin(), methods.end(), meshing::Method::kCgal) == methods.end())
    return scaling;
  const meshing::Surface s =
      meshing::surface_of(app::load_scene(dir + "/" + o.surfaces.front() + ".toml"));
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
  return scaling;
}
#endif

void run(const Options& o) {
#if !defined(IAA_HAVE_CGAL) || !defined(IAA_HAVE_OPENMESH)
  throw Error("iaa bench mesh needs CGAL and OpenMesh (this iaa was built without them)");
#else
  check_options(o);
  const std::string dir = find_scene_dir(o.scene_dir);
  std::vector<meshing::Method> methods;
  for (const std::string& m : o.methods) methods.push_back(meshing::parse_mesh_method(m));
  Exec exec;
  exec.threads = o.threads;
  print_header(o, exec);
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : o.surfaces) bench_surface(o, dir, name, methods, exec, out);
  const nlohmann::json scaling = cgal_scaling(o, dir, methods, exec);
  std::printf(
      "lost: IAA certifies surface in the pixel, the mesh shows none; wrong: IAA certifies\n"
      "the pixel empty, the mesh shows surface; undecided: IAA could not decide, no mesh there.\n"
      "phases, certified: refinement / corner table / extraction / assembly;\n"
      "octree: enclosure / grid signs / loop extraction / vertex placement.\n%s\n",
      kPeakNote);
  if (!o.json.empty()) {
    nlohmann::json j = {{"rows", out}};
    if (!scaling.is_null()) j["cgal_thread_scaling"] = scaling;
    app::write_text_atomically(o.json, j.dump(2) + "\n");
  }
#endif
}

void setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  add_scene_dir_option(app, &o->scene_dir);
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
