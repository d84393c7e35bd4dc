// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// Meshing as `iaa mesh`, `iaa compare`, `iaa bench mesh` and the Python module's mesh() run it:
// the surface, the four meshers (certified, octree, CGAL Mesh_3, VTK flying edges) with comparable
// resolutions, and the JSON report of a mesh. VTK lives above this layer (viz/), so its mesher
// comes in as a function pointer (VtkMesher) from whoever links viz.
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/exec.h"
#include "enclose/octree.h"
#include "expr/tape.h"
#include "mesh/certified_mesher.h"
#include "mesh/mesh_report.h"
#include "mesh/octree_mesher.h"
#include "mesh/triangle_soup.h"
#include "scene/scene.h"

namespace iaa::app::meshing {

/// The surface to mesh: from a scene, or from an expression and bounds.
struct Surface {
  std::string name;
  std::string expression;
  std::shared_ptr<const Tape> tape;
  Box3 bounds;
};

/// The surface of a scene.
Surface surface_of(const Scene& scene);

enum class Method { kCertified, kOctree, kCgal, kVtk };

/// The method's name as `--method` takes it.
const char* method_label(Method m);

/// A mesher that lives above this layer (VTK's flying edges, viz/vtk_mesher.h): fills the run's
/// soup, seconds, details and summary.
struct MeshParams;
struct MeshRun;
using VtkMesher = void (*)(const Surface&, const MeshParams&, const Exec&, MeshRun&);

/// Parses a method name; a method whose library was left out of this build (CGAL; VTK when `vtk`
/// is null) is a clear error.
Method parse_mesh_method(const std::string& text, VtkMesher vtk);

/// Resolution settings shared by the four methods. `resolution` N means: certified cells that may
/// hold surface no longer than 2 (longest bounds edge) / N, octree leaves of a 2^ceil(log2 N) grid,
/// VTK on an N^3 grid, CGAL facets of size (longest bounds edge) / N.
struct MeshParams {
  int resolution = 256;
  int min_depth = -1;  ///< certified: splits below the root cells at least; -1: from resolution
  int max_depth = CertifiedMeshSettings{}.max_depth;  ///< certified: the certification limit
  bool strict = false;                                ///< certified: prove faces and edges too
  bool proof_cache = true;  ///< certified: reuse neighbours' proofs (CertifiedMeshSettings)
  int depth = 0;            ///< octree depth; 0: from resolution
  int refine = 4;           ///< octree: extra levels for possible leaves
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
  /// Throws SettingError naming the command-line option and its limits.
  void validate() const;
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
  /// Under mpirun: how the shared loops were balanced (certified: its refinement; octree: its
  /// enclosure); empty otherwise.
  SpreadBalance balance;
};

/// Validates the parameters and runs one mesher; `vtk` runs Method::kVtk (null: not built).
MeshRun run_mesher(Method m, const Surface& s, const MeshParams& p, const Exec& exec,
                   VtkMesher vtk);

/// Why the run found no surface ("" when it has triangles): no sign change of f was seen, and how
/// many uncertified cells or possible leaves may still hold surface.
std::string no_surface_reason(const MeshRun& run, Method method);

/// The mesh's topology and fit (mesh_report.h) of `soup`, the run's triangles as the mesh holds
/// them. With `check` (MeshParams::enclose_settings), a mesher other than the certified one (which
/// reports its own certificate instead) is also checked against the guaranteed enclosure: its own
/// (the octree's) or one computed here with those settings.
MeshReport analyze_run(Method method, const Surface& surface, const TriangleSoup& soup,
                       CoordinatePrecision precision, MeshRun& run, const Exec& exec,
                       const EncloseSettings* check);

/// The numbers of a MeshReport as JSON.
nlohmann::json report_json(const MeshReport& r);

/// The JSON report of `iaa mesh --report` without its two file keys (mesh_file and
/// mesh_file_coordinates): the report's numbers, the method, surface, time and settings, the
/// vertices duplicated to hold non-manifold triangles, the self-intersections (CGAL; null without
/// it) and, for the certified mesher, its certificate.
nlohmann::json mesh_report_json(Method method, const Surface& surface, const MeshRun& run,
                                const MeshReport& report, const TriangleSoup& soup,
                                std::size_t duplicated);

}  // namespace iaa::app::meshing
