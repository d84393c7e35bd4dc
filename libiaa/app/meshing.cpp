// Meshing as the commands and the Python module run it (meshing.h).
#include "app/meshing.h"

#include <cmath>
#include <cstdio>

#include "app/balance.h"
#include "core/error.h"
#include "mesh/cgal_mesher.h"
#ifdef IAA_HAVE_CGAL
#include "mesh/self_intersections.h"
#endif

namespace iaa::app::meshing {
namespace {

/// The certified mesher's settings for these parameters (validated).
CertifiedMeshSettings certified_settings(const Surface& s, const MeshParams& p) {
  CertifiedMeshSettings cs;
  cs.bounds = s.bounds;
  cs.max_depth = p.max_depth;
  cs.max_boxes = p.max_boxes;
  cs.strict = p.strict;
  cs.proof_cache = p.proof_cache;
  cs.min_depth = 0;
  cs.validate();
  cs.min_depth = p.min_depth >= 0 ? p.min_depth : certified_depth_for_resolution(cs, p.resolution);
  cs.validate();
  return cs;
}

void run_certified(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  const CertifiedMeshSettings cs = certified_settings(s, p);
  CertifiedMesh cm = mesh_certified(*s.tape, cs, exec);
  run.seconds = seconds_since(t0);
  run.soup = std::move(cm.soup);
  run.uncertified = std::move(cm.uncertified);
  run.balance = std::move(cm.balance);
  const CertifiedMeshStats& st = cm.stats;
  run.details = {{"min_depth", cs.min_depth},
                 {"max_depth", cs.max_depth},
                 {"strict", cs.strict},
                 {"proof_cache", cs.proof_cache},
                 {"root_cells", st.roots},
                 {"leaves", st.leaves},
                 {"empty_leaves", st.empty_leaves},
                 {"certified_leaves", st.certified_leaves},
                 {"uncertified_leaves", st.uncertified_leaves},
                 {"uncertain_corners", st.uncertain_corners},
                 {"open_chains", st.open_chains},
                 {"rounds", st.rounds},
                 {"interval_evaluations", st.interval_evaluations},
                 {"finest_depth", st.finest_depth},
                 {"seconds_refine", st.seconds_refine},
                 {"seconds_table", st.seconds_table},
                 {"seconds_extract", st.seconds_extract},
                 {"seconds_assemble", st.seconds_assemble}};
  run.details["distance_bound"] = {
      {"mesh_to_surface", st.mesh_to_surface},
      {"surface_to_mesh", st.surface_to_mesh},
      {"uncertified_cell_diagonal", st.uncertified_diagonal},
      {"meaning",
       "within the certified cells, every mesh point lies within mesh_to_surface of the surface "
       "(the largest diagonal of a certified cell holding mesh) and every surface point within "
       "surface_to_mesh of the mesh (the same with --strict; by default plus the largest "
       "diagonal of a certified cell that may hold surface, for caps pushed across a face); in "
       "uncertified cells the mesh may miss or add pieces"}};
  run.summary = "certified, depth " + std::to_string(cs.min_depth) + ".." +
                std::to_string(cs.max_depth) + " below " + std::to_string(st.roots[0]) + "x" +
                std::to_string(st.roots[1]) + "x" + std::to_string(st.roots[2]) +
                " root cells: " + std::to_string(st.leaves) + " leaves, " +
                std::to_string(st.uncertified_leaves) + " uncertified";
}

/// The octree mesher, from its own guaranteed enclosure (kept in the run for the report).
void run_octree(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  OctreeMeshSettings os;
  os.enclose = p.enclose_settings(s.bounds);
  os.flat_tolerance = p.flat_tolerance;
  os.validate();
  Enclosure enc = enclose(*s.tape, os.enclose, exec);
  const double enclose_seconds = seconds_since(t0);
  OctreeMesh om = extract_mesh(*s.tape, enc, os, exec);
  run.seconds = seconds_since(t0);
  run.soup = std::move(om.soup);
  const OctreeMeshStats& st = om.stats;
  run.details = {{"depth", os.enclose.depth},
                 {"refine_possible", os.enclose.refine_possible},
                 {"flat_tolerance", os.flat_tolerance},
                 {"leaves", st.leaves},
                 {"crossing_leaves", st.crossing_leaves},
                 {"possible_leaves", st.possible_leaves},
                 {"meshed_leaves", st.meshed_leaves},
                 {"unmeshed_possible_leaves", st.unmeshed_possible},
                 {"unmeshed_crossing_leaves", st.unmeshed_crossing},
                 {"sample_points", st.sample_points},
                 {"uncertain_points", st.uncertain_points},
                 {"open_chains", st.open_chains},
                 {"bent_loops", st.bent_loops},
                 {"finest_level", st.finest_level},
                 {"seconds_enclose", enclose_seconds},
                 {"seconds_signs", st.seconds_signs},
                 {"seconds_extract", st.seconds_extract},
                 {"seconds_vertices", st.seconds_vertices}};
  run.summary =
      "octree, depth " + std::to_string(os.enclose.depth) + " (possible leaves refined to depth " +
      std::to_string(os.enclose.depth + os.enclose.refine_possible) +
      "): " + std::to_string(st.leaves) + " leaves, " + std::to_string(st.crossing_leaves) +
      " crossing, " + std::to_string(st.possible_leaves) + " possible";
  run.balance = enc.balance;
  run.enclosure = std::move(enc);
}

#ifdef IAA_HAVE_CGAL
/// CGAL Mesh_3; the facet size defaults to the bounds' longest edge over the resolution.
void run_cgal(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  const double edge = std::fmax(s.bounds.size().x, std::fmax(s.bounds.size().y, s.bounds.size().z));
  CgalMeshSettings cs;
  cs.bounds = s.bounds;
  cs.facet_size = p.facet_size > 0 ? p.facet_size : edge / p.resolution;
  cs.facet_distance = p.facet_distance > 0 ? p.facet_distance : cs.facet_size / 4;
  cs.facet_angle = p.facet_angle;
  CgalMeshStats st;
  run.soup = mesh_cgal(*s.tape, cs, exec, &st);
  run.seconds = seconds_since(t0);
  run.details = {{"facet_size", cs.facet_size},
                 {"facet_distance", cs.facet_distance},
                 {"facet_angle", cs.facet_angle},
                 {"facets", st.facets},
                 {"bound_facets_removed", st.bound_facets}};
  char b[160];
  std::snprintf(b, sizeof b, "cgal Mesh_3, facet size %.4g, distance %.4g, angle %.4g",
                cs.facet_size, cs.facet_distance, cs.facet_angle);
  run.summary = b;
}
#endif

/// Adds the certified mesher's certificate to a report.
void add_certificate(nlohmann::json& j, const MeshRun& run) {
  j["topology_certified"] = run.uncertified.empty();
  j["uncertified_cells"] = run.uncertified.size();
  j["distance_bound"] = run.details["distance_bound"];
}

}  // namespace

Surface surface_of(const Scene& scene) {
  Surface s;
  s.name = scene.name;
  s.expression = scene.expression;
  s.tape = scene.tape;
  s.bounds = scene.bounds;
  return s;
}

const char* method_label(Method m) {
  switch (m) {
    case Method::kCertified:
      return "certified";
    case Method::kOctree:
      return "octree";
    case Method::kCgal:
      return "cgal";
    default:
      return "vtk";
  }
}

Method parse_mesh_method(const std::string& text, VtkMesher vtk) {
  if (text == "certified") return Method::kCertified;
  if (text == "octree") return Method::kOctree;
  if (text == "cgal") {
#ifndef IAA_HAVE_CGAL
    throw Error("--method cgal: this iaa was built without CGAL (IAA_WITH_CGAL=OFF)");
#endif
    return Method::kCgal;
  }
  if (text == "vtk") {
    if (!vtk) throw Error("--method vtk: this iaa was built without VTK (IAA_WITH_VTK=OFF)");
    return Method::kVtk;
  }
  throw Error("--method: unknown mesher '" + text + "'; use certified, octree, cgal or vtk");
}

void MeshParams::validate() const {
  if (resolution < 2 || resolution > 4096) {
    throw SettingError("--resolution must be in 2..4096, got " + std::to_string(resolution));
  }
  if (depth < 0) throw SettingError("--depth must be positive (0: from --resolution)");
  if (!(facet_size >= 0) || !(facet_distance >= 0)) {
    throw SettingError("--facet-size and --facet-distance must be positive lengths (0: automatic)");
  }
  if (grid < 0) throw SettingError("--grid must be in 2..2048 (0: from --resolution)");
  if (min_depth < -1) throw SettingError("--min-depth must be 0 or more (-1: from --resolution)");
  if (!(flat_tolerance >= 0 && flat_tolerance <= 1)) {
    throw SettingError("--flat-tolerance must be in 0..1 (a fraction of the leaf's edge), got " +
                       std::to_string(flat_tolerance));
  }
}

MeshRun run_mesher(Method m, const Surface& s, const MeshParams& p, const Exec& exec,
                   VtkMesher vtk) {
  p.validate();
  MeshRun run;
  if (m == Method::kCertified) {
    run_certified(s, p, exec, run);
  } else if (m == Method::kOctree) {
    run_octree(s, p, exec, run);
  } else if (m == Method::kCgal) {
#ifdef IAA_HAVE_CGAL
    run_cgal(s, p, exec, run);
#endif
  } else if (vtk) {
    vtk(s, p, exec, run);
  }
  return run;
}

std::string no_surface_reason(const MeshRun& run, Method method) {
  if (!run.soup.triangles.empty()) return "";
  std::string why = "the " + std::string(method_label(method)) +
                    " mesher found no surface (no sign change of f was seen)";
  if (!run.uncertified.empty()) {
    why += "; " + std::to_string(run.uncertified.size()) +
           " uncertified cells may hold surface where f touches 0 without changing sign";
  }
  if (run.details.contains("unmeshed_possible_leaves") &&
      run.details["unmeshed_possible_leaves"] > 0) {
    why += "; " + run.details["unmeshed_possible_leaves"].dump() +
           " possible leaves may hold surface where f touches 0 without changing sign";
  }
  return why;
}

MeshReport analyze_run(Method method, const Surface& surface, const TriangleSoup& soup,
                       CoordinatePrecision precision, MeshRun& run, const Exec& exec,
                       const EncloseSettings* check) {
  std::optional<Enclosure> enc = std::move(run.enclosure);
  if (check && method != Method::kCertified) {
    if (!enc) enc = enclose(*surface.tape, *check, exec);
    return analyze_mesh(soup, surface.tape.get(), &*enc, precision);
  }
  return analyze_mesh(soup, surface.tape.get(), nullptr, precision);
}

nlohmann::json report_json(const MeshReport& r) {
  nlohmann::json j = {{"vertices", r.vertices},
                      {"triangles", r.triangles},
                      {"edges", r.edges},
                      {"boundary_edges", r.boundary_edges},
                      {"nonmanifold_edges", r.nonmanifold_edges},
                      {"inconsistently_oriented_edges", r.inconsistent_edges},
                      {"degenerate_triangles", r.degenerate_triangles},
                      {"unused_vertices", r.unused_vertices},
                      {"components", r.components},
                      {"euler_characteristic", r.euler},
                      {"area", r.area},
                      {"signed_volume", r.volume},
                      {"max_abs_f_at_vertices", r.max_abs_f},
                      {"undefined_vertices", r.undefined_vertices}};
  j["vertices_outside_enclosure"] =
      r.outside_enclosure < 0 ? nlohmann::json(nullptr) : nlohmann::json(r.outside_enclosure);
  // Per component, and the genus of each closed, consistently oriented one.
  nlohmann::json genus = nlohmann::json::array();
  nlohmann::json comps = nlohmann::json::array();
  for (const ComponentTopology& c : r.component_topology) {
    if (c.genus >= 0) genus.push_back(c.genus);
    comps.push_back({{"triangles", c.triangles},
                     {"euler_characteristic", c.euler},
                     {"boundary_edges", c.boundary_edges},
                     {"nonmanifold_edges", c.nonmanifold_edges},
                     {"inconsistently_oriented_edges", c.inconsistent_edges},
                     {"genus", c.genus >= 0 ? nlohmann::json(c.genus) : nlohmann::json(nullptr)}});
  }
  j["genus_of_closed_components"] = genus;
  j["component_topology"] = comps;
  return j;
}

nlohmann::json mesh_report_json(Method method, const Surface& surface, const MeshRun& run,
                                const MeshReport& rep, const TriangleSoup& soup,
                                std::size_t duplicated) {
  nlohmann::json j = report_json(rep);
  j["method"] = method_label(method);
  j["surface"] = surface.expression;
  j["seconds"] = run.seconds;
  j["settings"] = run.details;
  j["vertices_duplicated_on_write"] = duplicated;
#ifdef IAA_HAVE_CGAL
  j["self_intersections"] = count_self_intersections(soup);
#else
  (void)soup;
  j["self_intersections"] = nullptr;  // counted with CGAL, left out of this build
#endif
  if (method == Method::kCertified) add_certificate(j, run);
  if (!run.balance.ranks.empty()) j["mpi"] = balance_json(run.balance);
  return j;
}

}  // namespace iaa::app::meshing
