// The octree mesher: triangles extracted from the guaranteed enclosure (enclose/octree.h).
//
// Every leaf of the enclosure (crossing leaves at the requested depth, possible leaves refined
// deeper so that thin features show a sign change) is meshed by *cubical marching squares*: the
// sign of f is certified at the corners of all leaves (by the enclosure's mean-value forms or
// interval evaluations, Cell::corner_signs, else by an interval evaluation on the degenerate box
// of the point); each face of a leaf is cut into the faces of the finer leaf on either side, and
// every edge into the corners of all leaves that touch it; on every such polygon the crossings of
// the zero set (proved sign changes) are paired, and within a leaf the pairs link into closed
// loops, each triangulated by a fan around a point pulled onto the surface (a loop of 3 or 4 by one
// or two flat triangles instead, unless the surface bends away from them: flat_tolerance). Two
// leaves that share a face see the same polygons and the same crossings, so the mesh has no cracks
// between levels; crossings are keyed by their grid edge, so vertices are welded; segments are
// oriented with the negative side of f on their left, so triangles are consistently oriented
// (normals towards increasing f) and every mesh edge inside the bounds has exactly two triangles.
//
// No global sign convention is assumed: a region is meshed where a sign change is proved. Leaves
// whose boundary shows no sign change (e.g. where f touches 0 without changing sign) are not
// meshed; they are counted and returned, never dropped silently.
#pragma once

#include <cstdint>
#include <vector>

#include "core/exec.h"
#include "enclose/octree.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa {

/// What the octree mesher computes: the enclosure to mesh, and how vertices are placed.
struct OctreeMeshSettings {
  /// The enclosure: bounds, leaf depth, extra levels for possible leaves, box limit.
  EncloseSettings enclose;
  /// Root-finding steps per crossing along its grid edge (regula falsi, bracket kept).
  int edge_steps = 8;
  /// Newton steps that pull each loop's centre vertex onto the surface (kept inside its leaf).
  int centre_steps = 3;
  /// A loop of 3 or 4 crossings is one or two flat triangles unless the surface, at the point its
  /// centre is pulled to, lies farther than this fraction of the leaf's shortest edge from the
  /// loop's mean plane (where the surface turns sharply inside the leaf, as at the rim of a thin
  /// blade) and the fan does not fold: then it is a fan around that point, like longer loops.
  /// The point stays inside the leaf, so the distance is below sqrt(3) edges: 1 bends practically
  /// no loop.
  double flat_tolerance = 0.02;

  /// Finest grid level the mesher supports (depth + refine_possible).
  static constexpr int kMaxLevel = 20;
  /// Throws SettingError naming the setting and its limits.
  void validate() const;
};

/// Counts that describe how the mesh was made; all are reported by `iaa mesh --report`.
struct OctreeMeshStats {
  std::uint64_t leaves = 0;             ///< leaves of the enclosure
  std::uint64_t crossing_leaves = 0;    ///< certified to hold surface
  std::uint64_t possible_leaves = 0;    ///< may hold surface
  std::uint64_t meshed_leaves = 0;      ///< leaves that produced at least one loop
  std::uint64_t unmeshed_possible = 0;  ///< possible leaves with no sign change on their boundary
  std::uint64_t unmeshed_crossing = 0;  ///< crossing leaves whose boundary showed no sign change
  std::uint64_t sample_points = 0;      ///< grid points whose sign was needed
  std::uint64_t known_points = 0;       ///< of those, signs proved by the enclosure's leaves
  std::uint64_t uncertain_points = 0;   ///< points whose sign intervals could not decide
  std::uint64_t open_chains = 0;        ///< segment chains that did not close (must be 0)
  std::uint64_t bent_loops = 0;         ///< loops of 3 or 4 given a centre vertex (flat_tolerance)
  std::uint64_t evaluations = 0;        ///< interval evaluations (enclosure + point signs)
  int finest_level = 0;                 ///< deepest leaf
  /// Wall time of the phases: grid points and signs, loop extraction, vertex placement.
  double seconds_signs = 0, seconds_extract = 0, seconds_vertices = 0;
};

/// The mesh and what could not be meshed.
struct OctreeMesh {
  TriangleSoup soup;
  OctreeMeshStats stats;
  /// Possible leaves not meshed: the surface may pass through them (or touch 0 there).
  std::vector<Cell> unmeshed;
};

/// Meshes the leaves of an existing enclosure of `tape`'s surface. The enclosure's cells must not
/// overlap (any mix of depths); their finest depth must be at most kMaxLevel.
OctreeMesh extract_mesh(const Tape& tape, const Enclosure& enclosure,
                        const OctreeMeshSettings& settings, const Exec& exec = {});

/// Encloses the surface (enclose()) and meshes the enclosure.
OctreeMesh mesh_octree(const Tape& tape, const OctreeMeshSettings& settings, const Exec& exec = {});

}  // namespace iaa
