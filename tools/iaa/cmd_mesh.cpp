// `iaa mesh`: meshes a surface with the certified mesher (ours, isotopic to the surface inside
// the cells it certifies; the default), the octree mesher (ours, from the guaranteed enclosure),
// CGAL Mesh_3 or VTK flying edges, writes the mesh through OpenMesh (PLY/OBJ/OFF/STL), and reports
// its topology and fit (--report) and the cells it could not certify (--uncertified).
#include <cstdio>
#include <memory>

#include "app/balance.h"
#include "app/files.h"
#include "app/progress_bar.h"
#include "core/error.h"
#include "dist/world.h"
#include "iaa/command.h"
#include "iaa/command_spread.h"
#include "iaa/mesh_common.h"
#include "mesh/mesh_io.h"
#ifdef IAA_HAVE_VIZ
#include "iaa/viz_plugin.h"
#endif

namespace iaa::cli {
namespace {

struct MeshOptions {
  std::string scene;
  std::string expr;
  std::string bounds;
  std::vector<std::string> params;
  std::vector<std::string> sets;
  std::string method = "certified";
  std::string output;
  bool binary = false;
  std::string report;
  std::string uncertified;
  meshing::MeshParams p;
  int threads = 0;
  bool quiet = false;
};

// Everything from here to run() writes or reports a mesh, which needs OpenMesh; without it `iaa
// mesh` only fails cleanly (run()), and these would be unused functions.
#ifdef IAA_HAVE_OPENMESH
void check_uncertified_option(const MeshOptions& o, meshing::Method method) {
  if (o.uncertified.empty()) return;
  if (method != meshing::Method::kCertified) {
    throw Error("--uncertified: only --method certified reports uncertified cells");
  }
  if (app::extension_of(o.uncertified) != "vtu") {
    throw Error("--uncertified: the boxes are written as a .vtu file, got '" + o.uncertified + "'");
  }
#ifndef IAA_HAVE_VIZ
  throw Error("--uncertified: this iaa was built without VTK (IAA_WITH_VTK=OFF)");
#else
  viz_plugin("--uncertified");  // a missing plugin is said before the work
#endif
}

void write_uncertified(const std::string& path, const meshing::MeshRun& run,
                       const meshing::Surface& surface) {
#ifdef IAA_HAVE_VIZ
  std::vector<viz::LabelledBox> boxes;
  for (const UncertifiedCell& c : run.uncertified) boxes.push_back({c.box, c.depth, c.reason});
  const viz::PluginApi& vtk = viz_plugin("--uncertified");
  app::write_atomically(
      path, [&](const std::string& tmp) { vtk.write_boxes_vtu(tmp, boxes, surface.expression); });
#else
  (void)path, (void)run, (void)surface;
#endif
}

void print_certificate(const meshing::MeshRun& run) {
  const nlohmann::json& d = run.details;
  if (run.uncertified.empty()) {
    std::printf("certified    topology certified: every cell holding surface passed\n");
  } else {
    std::printf(
        "uncertified  %zu cells reached depth %s without a certificate (meshed best-effort)\n",
        run.uncertified.size(), d["max_depth"].dump().c_str());
  }
  std::printf(
      "distance     inside certified cells: mesh to surface <= %.3g, surface to mesh <= %.3g\n",
      d["distance_bound"]["mesh_to_surface"].get<double>(),
      d["distance_bound"]["surface_to_mesh"].get<double>());
}

/// The output checks that need no surface: the --report name and --uncertified's use.
void check_outputs(const MeshOptions& o, meshing::Method method) {
  if (!o.report.empty() && app::extension_of(o.report) != "json") {
    throw Error("--report: the report must be a .json file, got '" + o.report + "'");
  }
  check_uncertified_option(o, method);
}

/// Fails, writing nothing, when the mesher produced no triangle, saying which cells or leaves may
/// still hold surface.
void check_found_surface(const meshing::MeshRun& run, meshing::Method method) {
  const std::string why = app::meshing::no_surface_reason(run, method);
  if (!why.empty()) throw Error(why + "; no file was written");
}

/// Writes the mesh file and, with --uncertified, the boxes of the uncertified cells.
void write_files(const MeshOptions& o, MeshFormat format, const Mesh& mesh,
                 const meshing::MeshRun& run, const meshing::Surface& surface) {
  const std::string bytes = encode_mesh(mesh, format, o.binary);
  app::write_text_atomically(o.output, bytes);
  if (!o.uncertified.empty()) write_uncertified(o.uncertified, run, surface);
}

/// The mesh's topology and fit; checked against the enclosure only for a --report (and never for
/// the certified mesher, which reports its own certificate instead).
MeshReport analyze(const MeshOptions& o, meshing::Method method, const meshing::Surface& surface,
                   const TriangleSoup& soup, CoordinatePrecision precision, meshing::MeshRun& run,
                   const Exec& exec) {
  const EncloseSettings check = o.p.enclose_settings(surface.bounds);
  return app::meshing::analyze_run(method, surface, soup, precision, run, exec,
                                   o.report.empty() ? nullptr : &check);
}

/// The summary on stdout: the surface, the mesher, the mesh's topology and fit, the certificate
/// (certified mesher) and what was written.
void print_summary(const MeshOptions& o, meshing::Method method, const meshing::Surface& surface,
                   const meshing::MeshRun& run, const MeshReport& rep, std::size_t duplicated) {
  std::printf("surface      %s\n", surface.expression.c_str());
  std::printf("method       %s\n", run.summary.c_str());
  std::printf("time         %.3f s\n", run.seconds);
  std::printf(
      "mesh         %llu vertices, %llu triangles, %llu components, Euler characteristic %lld\n",
      (unsigned long long)rep.vertices, (unsigned long long)rep.triangles,
      (unsigned long long)rep.components, (long long)rep.euler);
  std::printf("edges        %llu boundary, %llu non-manifold, %llu inconsistently oriented\n",
              (unsigned long long)rep.boundary_edges, (unsigned long long)rep.nonmanifold_edges,
              (unsigned long long)rep.inconsistent_edges);
  std::printf("fit          max |f| at vertices %.3g", rep.max_abs_f);
  if (rep.outside_enclosure >= 0)
    std::printf(", %lld vertices outside the enclosure", (long long)rep.outside_enclosure);
  std::printf("\n");
  if (run.details.contains("unmeshed_possible_leaves") &&
      run.details["unmeshed_possible_leaves"] > 0) {
    std::printf("unmeshed     %s possible leaves show no sign change: surface may touch 0 there\n",
                run.details["unmeshed_possible_leaves"].dump().c_str());
  }
  if (method == meshing::Method::kCertified) print_certificate(run);
  if (!run.balance.ranks.empty())
    std::printf("MPI          %s\n", app::balance_summary(run.balance).c_str());
  if (duplicated) {
    std::printf("note         %zu vertices duplicated to write non-manifold triangles\n",
                duplicated);
  }
  std::printf("wrote        %s\n", o.output.c_str());
}

/// The --report JSON: the summary's figures, the mesher's settings, the self-intersections and
/// how the file holds the coordinates.
void write_report(const MeshOptions& o, meshing::Method method, MeshFormat format,
                  const meshing::Surface& surface, const meshing::MeshRun& run,
                  const MeshReport& rep, const TriangleSoup& soup, std::size_t duplicated) {
  nlohmann::json j = app::meshing::mesh_report_json(method, surface, run, rep, soup, duplicated);
  j["mesh_file"] = o.output;
  j["mesh_file_coordinates"] = format == MeshFormat::kPly
                                   ? "float x y z, and exact double x_double y_double z_double"
                                   : "float x y z (rounded from the mesher's double)";
  app::write_text_atomically(o.report, j.dump(2) + "\n");
  std::printf("report       %s\n", o.report.c_str());
}
#endif

void run(const MeshOptions& o) {
  if (o.threads < 0)
    throw SettingError("--threads must be 0 (all) or more, got " + std::to_string(o.threads));
  [[maybe_unused]] const meshing::Method method = meshing::parse_mesh_method(o.method);
#ifndef IAA_HAVE_OPENMESH
  throw Error(
      "this iaa was built without OpenMesh (IAA_WITH_OPENMESH=OFF): meshes cannot be written");
#else
  const MeshFormat format = mesh_format_from_extension(app::extension_of(o.output));
  check_outputs(o, method);
  const meshing::Surface surface =
      meshing::load_surface(o.scene, o.expr, o.bounds, o.params, o.sets);
  o.p.validate();
  // Under mpirun the processes share the certified mesher's refinement and extraction, and the
  // enclosures (the octree mesher's, the report's check); every process ends with the same mesh
  // and the lead writes (docs/distributed.md).
  dist::World* world = dist::World::current();
  const bool lead = !world || world->lead();
  if (world) world->agree_input();

  app::ProgressBar bar(o.quiet || !lead);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const std::unique_ptr<Spread> spread = command_spread(world);
  exec.spread = spread.get();
  meshing::MeshRun run = meshing::run_mesher(method, surface, o.p, exec);
  check_found_surface(run, method);
  // One OpenMesh TriMesh (double points) from here on: the report is computed on it and the file
  // written from it. The report judges the mesher's double coordinates; a PLY file holds them
  // exactly (x_double ...), an OBJ or OFF file their float rounding (mesh_io.h).
  const Mesh mesh = Mesh::from_triangles(run.soup);
  run.soup = {};
  const std::size_t duplicated = mesh.duplicated_vertices();
  // The TriMesh as plain triangles (vertex copies merged back) once, for the report and the
  // self-intersection count.
  const TriangleSoup soup = mesh.triangles();
  const MeshReport rep = analyze(o, method, surface, soup, mesh.precision(), run, exec);
  bar.finish();
  // Every process finished its share (the report's enclosure is shared too): only then does the
  // lead write.
  if (world) world->agree_done();
  if (!lead) return;
  write_files(o, format, mesh, run, surface);

  print_summary(o, method, surface, run, rep, duplicated);
  if (!o.report.empty()) write_report(o, method, format, surface, run, rep, soup, duplicated);
#endif
}

void setup(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  app.add_option("scene", o->scene, "scene file (TOML); or use --expr and --bounds");
  app.add_option("--expr", o->expr, "the surface f(x,y,z) = 0");
  app.add_option("--bounds", o->bounds, "X0:X1,Y0:Y1,Z0:Z1, required with --expr");
  app.add_option("-p,--param", o->params, "a named parameter NAME=VALUE (repeatable)");
  app.add_option("--set", o->sets,
                 "override a scene key, e.g. 'surface.min=[-1,-1,-1]' (repeatable)");
  app.add_option("--method", o->method,
                 "certified (ours: isotopic inside certified cells), octree (ours, from the "
                 "guaranteed enclosure), cgal or vtk")
      ->capture_default_str();
  app.add_option("-o,--output", o->output, "mesh file: .ply, .obj, .off or .stl")->required();
  app.add_flag("--binary", o->binary, "write binary PLY or STL (ASCII otherwise)");
  app.add_option("--report", o->report,
                 "write a JSON report (topology, fit; the certificate for certified, the enclosure "
                 "check for the others)");
  app.add_option("--resolution", o->p.resolution,
                 "N: certified cells of at most 2 edge/N, octree leaves of a 2^ceil(log2 N) grid, "
                 "VTK grid N^3, CGAL facet size edge/N")
      ->capture_default_str();
  app.add_option("--depth", o->p.depth, "octree: leaf depth (overrides --resolution)");
  app.add_option("--min-depth", o->p.min_depth,
                 "certified: splits below the root cells at least for cells that may hold "
                 "surface (default: from --resolution)");
  app.add_option("--max-depth", o->p.max_depth,
                 "certified: splits below the root cells at most; deeper cells are uncertified")
      ->capture_default_str();
  app.add_flag("--strict", o->p.strict,
               "certified: also prove every face free of critical points and every edge "
               "monotone (slower; see docs/mesh.md)");
  app.add_flag("!--no-proof-cache", o->p.proof_cache,
               "certified: prove every face and edge afresh instead of reusing a neighbour's "
               "proof: the same mesh, more work, but an evaluation count that is the same for "
               "any number of threads or processes (for comparisons)");
  app.add_option("--uncertified", o->uncertified,
                 "certified: write the boxes of the uncertified cells (.vtu)");
  app.add_option("--refine", o->p.refine, "octree: extra levels for possible leaves (0..8)")
      ->capture_default_str();
  app.add_option("--flat-tolerance", o->p.flat_tolerance,
                 "octree: a loop of 3 or 4 crossings gets a centre vertex on the surface where "
                 "the surface lies farther than this fraction of the leaf's edge from the loop's "
                 "plane (0..1; 0: nearly every loop, 1: practically none)")
      ->capture_default_str();
  app.add_option("--max-boxes", o->p.max_boxes, "certified, octree: limit on leaves")
      ->capture_default_str();
  app.add_option("--facet-size", o->p.facet_size,
                 "cgal: facet circumradius bound (overrides --resolution)");
  app.add_option("--facet-distance", o->p.facet_distance,
                 "cgal: facet distance bound (default size/4)");
  app.add_option("--facet-angle", o->p.facet_angle, "cgal: minimum facet angle, degrees")
      ->capture_default_str();
  app.add_option("--grid", o->p.grid, "vtk: grid cells per axis (overrides --resolution)");
  app.add_option("--threads", o->threads, "worker threads, 0 = all (per process under mpirun)")
      ->capture_default_str();
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.footer(
      "Examples:\n"
      "  iaa mesh data/scenes/teardrop.toml -o teardrop.ply\n"
      "  iaa mesh data/scenes/teardrop.toml --method cgal --resolution 128 -o teardrop-cgal.ply\n"
      "  iaa mesh data/scenes/chubs.toml --binary -o chubs.stl            # for a 3D printer\n"
      "  iaa mesh --expr 'x^2 + y^2 + z^2 - 1' --bounds -1.2:1.2,-1.2:1.2,-1.2:1.2 \\\n"
      "           --method vtk --grid 64 -o sphere.obj --report sphere.json\n"
      "  iaa mesh data/scenes/thin_torus.toml -o torus.ply --uncertified unc.vtu --report "
      "torus.json\n"
      "Triangles are oriented with normals towards increasing f. With --method certified (the\n"
      "default) the mesh is isotopic to the surface inside the certified cells; cells that reach\n"
      "--max-depth without a certificate are meshed best-effort, counted, and written by\n"
      "--uncertified. With --method octree, leaves that may hold surface but show no sign change\n"
      "are counted, never dropped silently.\n"
      "Under mpirun (mpirun -np 4 iaa mesh ... --threads 1) the processes share the certified\n"
      "mesher's refinement and extraction (octree: its enclosure); the mesh and report are one\n"
      "process's (docs/distributed.md).");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{
    {"mesh", "mesh a surface (certified, octree, cgal, vtk) to PLY/OBJ/OFF/STL", 40, setup, true}};

}  // namespace
}  // namespace iaa::cli
