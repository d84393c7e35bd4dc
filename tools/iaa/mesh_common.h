// Shared by `iaa mesh`, `iaa compare` and `iaa bench mesh`: loading the surface (a scene file or
// --expr/--bounds), running one of the three meshers with comparable resolutions, and turning a
// MeshReport into JSON. Header-only so that the subcommand files stay independent.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "expr/tape.h"
#include "iaa/command.h"
#include "mesh/certified_mesher.h"
#include "mesh/cgal_mesher.h"
#include "mesh/mesh_report.h"
#include "mesh/octree_mesher.h"
#ifdef IAA_HAVE_VIZ
#include "viz/vtk_mesher.h"
#endif

namespace iaa::cli::meshing {

/// The surface to mesh: from a scene, or from an expression and bounds.
struct Surface {
  std::string name;
  std::string expression;
  std::shared_ptr<const Tape> tape;
  Box3 bounds;
  std::optional<Scene> scene;
};

/// A scene path, or --expr with --bounds (and --param); exactly one of the two.
inline Surface load_surface(const std::string& scene_path, const std::string& expr,
                            const std::string& bounds, const std::vector<std::string>& params,
                            const std::vector<std::string>& sets = {}) {
  Surface s;
  if (!scene_path.empty()) {
    if (!expr.empty()) throw Error("give either a SCENE or --expr, not both");
    Scene scene = app::load_scene(scene_path, sets);
    s.name = scene.name;
    s.expression = scene.expression;
    s.tape = scene.tape;
    s.bounds = scene.bounds;
    s.scene = std::move(scene);
    return s;
  }
  if (!sets.empty()) throw Error("--set changes a scene file; it needs a SCENE");
  if (expr.empty())
    throw Error("no surface: give a SCENE file or --expr EXPR --bounds X0:X1,Y0:Y1,Z0:Z1");
  if (bounds.empty()) throw Error("--bounds X0:X1,Y0:Y1,Z0:Z1 is required with --expr");
  s.name = "expr";
  s.expression = expr;
  s.tape = std::make_shared<const Tape>(Tape::parse(expr, parse_params(params)));
  s.bounds = parse_box(bounds, "--bounds");
  for (int a = 0; a < 3; ++a) {
    if (!(s.bounds.lo[a] < s.bounds.hi[a])) throw Error("--bounds: every range must have LO < HI");
  }
  validate_surface(*s.tape, s.bounds);  // as a scene file's surface is checked
  return s;
}

enum class Method { kCertified, kOctree, kCgal, kVtk };

inline const char* method_label(Method m) {
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

/// Parses a method name; a method whose library was left out of this build is a clear error.
inline Method parse_mesh_method(const std::string& text) {
  if (text == "certified") return Method::kCertified;
  if (text == "octree") return Method::kOctree;
  if (text == "cgal") {
#ifndef IAA_HAVE_CGAL
    throw Error("--method cgal: this iaa was built without CGAL (IAA_WITH_CGAL=OFF)");
#endif
    return Method::kCgal;
  }
  if (text == "vtk") {
#ifndef IAA_HAVE_VIZ
    throw Error("--method vtk: this iaa was built without VTK (IAA_WITH_VTK=OFF)");
#endif
    return Method::kVtk;
  }
  throw Error("--method: unknown mesher '" + text + "'; use certified, octree, cgal or vtk");
}

/// Resolution settings shared by the four methods. `resolution` N means: certified cells that may
/// hold surface no longer than 2 (longest bounds edge) / N, octree leaves of a 2^ceil(log2 N) grid,
/// VTK on an N^3 grid, CGAL facets of size (longest bounds edge) / N.
struct MeshParams {
  int resolution = 256;
  int min_depth = -1;  ///< certified: splits below the root cells at least; -1: from resolution
  int max_depth = CertifiedMeshSettings{}.max_depth;  ///< certified: the certification limit
  bool strict = false;                                ///< certified: prove faces and edges too
  int depth = 0;                                      ///< octree depth; 0: from resolution
  int refine = 4;                                     ///< octree: extra levels for possible leaves
  double flat_tolerance = OctreeMeshSettings{}.flat_tolerance;  ///< octree: see the setting
  std::uint64_t max_boxes = EncloseSettings{}.max_boxes;
  double facet_size = 0;      ///< cgal; 0: from resolution
  double facet_distance = 0;  ///< cgal; 0: facet_size / 4
  double facet_angle = 25;    ///< cgal
  int grid = 0;               ///< vtk; 0: resolution

  int octree_depth() const {
    if (depth > 0) return depth;
    int d = 1;
    while ((1 << d) < resolution && d < 20) ++d;
    return d;
  }
  EncloseSettings enclose_settings(const Box3& bounds) const {
    EncloseSettings e;
    e.bounds = bounds;
    e.depth = octree_depth();
    e.refine_possible = refine;
    e.max_boxes = max_boxes;
    return e;
  }
  void validate() const {
    if (resolution < 2 || resolution > 4096) {
      throw SettingError("--resolution must be in 2..4096, got " + std::to_string(resolution));
    }
    if (depth < 0) throw SettingError("--depth must be positive (0: from --resolution)");
    if (!(facet_size >= 0) || !(facet_distance >= 0)) {
      throw SettingError(
          "--facet-size and --facet-distance must be positive lengths (0: automatic)");
    }
    if (grid < 0) throw SettingError("--grid must be in 2..2048 (0: from --resolution)");
    if (min_depth < -1) throw SettingError("--min-depth must be 0 or more (-1: from --resolution)");
    if (!(flat_tolerance >= 0 && flat_tolerance <= 1)) {
      throw SettingError("--flat-tolerance must be in 0..1 (a fraction of the leaf's edge), got " +
                         std::to_string(flat_tolerance));
    }
  }
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One mesher run: the mesh, its wall time, and what the method reports about itself.
struct MeshRun {
  TriangleSoup soup;
  double seconds = 0;
  nlohmann::json details;
  std::string summary;                       ///< one line: the method and its main settings
  std::optional<Enclosure> enclosure;        ///< the octree's own enclosure
  std::vector<UncertifiedCell> uncertified;  ///< certified: the cells it could not certify
};

/// The certified mesher's settings for these parameters (validated).
inline CertifiedMeshSettings certified_settings(const Surface& s, const MeshParams& p) {
  CertifiedMeshSettings cs;
  cs.bounds = s.bounds;
  cs.max_depth = p.max_depth;
  cs.max_boxes = p.max_boxes;
  cs.strict = p.strict;
  cs.min_depth = 0;
  cs.validate();
  cs.min_depth = p.min_depth >= 0 ? p.min_depth : certified_depth_for_resolution(cs, p.resolution);
  cs.validate();
  return cs;
}

inline void run_certified(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  const CertifiedMeshSettings cs = certified_settings(s, p);
  CertifiedMesh cm = mesh_certified(*s.tape, cs, exec);
  run.seconds = seconds_since(t0);
  run.soup = std::move(cm.soup);
  run.uncertified = std::move(cm.uncertified);
  const CertifiedMeshStats& st = cm.stats;
  run.details = {{"min_depth", cs.min_depth},
                 {"max_depth", cs.max_depth},
                 {"strict", cs.strict},
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
inline void run_octree(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
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
  run.enclosure = std::move(enc);
}

#ifdef IAA_HAVE_CGAL
/// CGAL Mesh_3; the facet size defaults to the bounds' longest edge over the resolution.
inline void run_cgal(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
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

#ifdef IAA_HAVE_VIZ
/// VTK flying edges on a grid of --grid (else --resolution) cells per axis.
inline void run_vtk(const Surface& s, const MeshParams& p, const Exec& exec, MeshRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  viz::VtkMeshSettings vs;
  vs.bounds = s.bounds;
  vs.grid = p.grid > 0 ? p.grid : p.resolution;
  run.soup = viz::mesh_vtk(*s.tape, vs, exec);
  run.seconds = seconds_since(t0);
  run.details = {{"grid", vs.grid}};
  run.summary = "vtk flying edges, grid " + std::to_string(vs.grid) + "^3";
}
#endif

inline MeshRun run_mesher(Method m, const Surface& s, const MeshParams& p, const Exec& exec) {
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
  } else {
#ifdef IAA_HAVE_VIZ
    run_vtk(s, p, exec, run);
#endif
  }
  return run;
}

inline nlohmann::json report_json(const MeshReport& r) {
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

}  // namespace iaa::cli::meshing
