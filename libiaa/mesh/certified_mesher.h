// The certified mesher: a triangle mesh isotopic to the surface f = 0 inside the cells it could
// certify, and the list of cells it could not (docs/mesh.md, "Certified meshing").
//
// An adaptive octree over a grid of near-cubic root cells is refined until every leaf is either
// *empty* (0 outside the interval value of f over the closed cell, natural or mean-value form) or
// *certified*: f is strictly monotone along one fixed direction over the cell (Plantinga and
// Vegter's test, 0 outside the dot product of two independent gradient enclosures, or 0 outside
// d.G for a fixed direction d, and then also no critical point of f on the faces that d crosses
// and f monotone on the edges not along d; the enclosure G is the natural one, intersected with
// the centred form g(c) + H(cell)(cell - c) where that pays), every face piece of its boundary
// (faces are cut where a finer neighbour touches them) shows at most two sign changes, the
// crossings on its boundary close into at most one loop, and that loop's fan around an inner point
// projects one-to-one along the loop's normal. The surface then meets each certified cell in one
// disc (or not at all) and the mesh has a vertex on each crossed edge piece, a segment across each
// crossed face piece and a fan over each loop. Closed curves of the surface inside a face, and
// double crossings of an edge, which corner signs cannot see, are excluded by proof in cells
// certified by a fixed direction (and in every cell with `strict`), and pushed across by Plantinga
// and Vegter's argument in cells certified by their cone test (the default). docs/mesh.md states
// the rules and the argument. For fidelity only, a leaf that passes every rule is split once more
// where a segment across one of its faces cuts a bent surface (a thin rim) back by more than a
// quarter of its edge (docs/mesh.md, "Fidelity split").
//
// A leaf that reaches the depth limit without either certificate is *uncertified*: meshed by the
// same rules as well as they go (never dropped) and returned, so that callers can report it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/exec.h"
#include "core/spread.h"
#include "core/vec.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa {

/// What the certified mesher computes.
struct CertifiedMeshSettings {
  Box3 bounds;
  /// Leaves that may hold surface are split at least this many times below the root cells, so
  /// that the mesh resolves the geometry and not only the topology.
  int min_depth = 3;
  /// Leaves are split at most this many times below the root cells; a leaf that needs more is
  /// uncertified.
  int max_depth = 10;
  /// Root cells per axis are powers of two chosen so that root cells are near cubes (edges within
  /// a factor 2 of each other); at most this many per axis.
  int max_roots_per_axis = 32;
  /// Upper bound on the number of leaves; exceeding it is an error with a clear message.
  std::uint64_t max_boxes = 20'000'000;
  /// Regula falsi steps (Illinois) that place each vertex on its crossed edge piece.
  int edge_steps = 24;
  /// Newton steps that pull each fan's centre towards the surface (kept inside its cell).
  int centre_steps = 3;
  /// Also prove, for every certified cell, that f has no critical point on its faces (tangential
  /// gradient) and is monotone along its edges, so that no closed curve or double crossing of the
  /// surface can hide inside a face or an edge and each cell holds exactly the disc its loop
  /// shows. Without it, cells certified by a fixed direction prove this for the faces and edges
  /// that direction does not already cover, and in cells certified by the cone test the closed
  /// curves and double crossings that corner signs cannot see are pushed across by Plantinga and
  /// Vegter's argument (docs/mesh.md). Strict mode refines much deeper where the surface is
  /// tangent to a grid plane.
  bool strict = false;
  /// Keep each thread's recent face and edge proofs for the neighbouring cells (ProofCache). The
  /// mesh and certificates are the same either way; with the cache the count of interval
  /// evaluations is lower but depends on which thread (or process) meets which cell, without it
  /// the count is the same for any number of threads and processes (for tests and comparisons).
  bool proof_cache = true;
  /// Leaves without finer neighbours (half of those holding crossings on the thin torus) take
  /// their crossings and segments from a table of the 256 cases of corner signs, made once by the
  /// rules that cut faces, instead of cutting their 6 faces. The mesh is the same either way (for
  /// the test that compares them).
  bool simple_leaves = true;
  /// Where a cell fails the cone test and f's natural interval over it overestimates (a
  /// polynomial with cancellation), bound its gradient by the centred form g(c) + H(cell)(cell - c)
  /// as well (IntervalHessEval), which certifies the thin torus in 137 036 leaves instead of
  /// 332 700. Off only for the test that compares the two.
  bool centred_gradients = true;

  /// Fine grid coordinates must fit 19 bits per axis: max_depth + log2(roots per axis) <= 19.
  static constexpr int kGridBits = 19;
  /// Throws SettingError naming the setting and its limits.
  void validate() const;
};

/// A leaf box the mesher could not certify.
struct UncertifiedCell {
  Box3 box;
  int depth = 0;  ///< splits below its root cell
  /// Why: 1 no certificate where it could not be split further (the depth limit, or a split that
  /// was undone), 2 a corner whose sign intervals could not decide.
  int reason = 1;
};

/// Counts that describe the run; all are reported by `iaa mesh --report`.
struct CertifiedMeshStats {
  std::array<int, 3> roots{1, 1, 1};   ///< root cells per axis
  std::uint64_t leaves = 0;            ///< all leaves, empty ones included
  std::uint64_t empty_leaves = 0;      ///< 0 outside F(cell)
  std::uint64_t certified_leaves = 0;  ///< certified, holding surface or not
  std::uint64_t uncertified_leaves = 0;
  std::uint64_t uncertain_corners = 0;  ///< corners whose interval value straddles 0
  std::uint64_t open_chains = 0;        ///< crossings that did not close into loops (uncertified)
  std::uint64_t rounds = 0;             ///< global rounds of splitting (faces, loops, fans)
  /// Of f, its gradient and its Hessian, over cells, faces, edges and points. Face and edge proofs
  /// are shared between neighbouring cells through a per-thread cache, so with several threads this
  /// count varies slightly from run to run (by about 1 in 10^5); the mesh and the certificates do
  /// not.
  std::uint64_t interval_evaluations = 0;
  int finest_depth = 0;  ///< deepest leaf below its root
  /// Within the certified leaves, every mesh point lies at most this far from the surface: the
  /// largest diagonal of a certified leaf that holds mesh (its triangles stay in the leaf, and a
  /// leaf with a loop holds surface).
  double mesh_to_surface = 0;
  /// Within the certified leaves, every surface point lies at most this far from the mesh. With
  /// `strict`, a certified leaf without a loop holds no surface, so it equals mesh_to_surface;
  /// by default a cap of the surface pushed across a face may lie in a leaf without mesh next to
  /// the leaf whose mesh stands for it: the largest diagonal of a certified leaf that may hold
  /// surface plus mesh_to_surface.
  double surface_to_mesh = 0;
  /// The largest diagonal of an uncertified leaf (0 when none): there the mesh may also miss or
  /// add pieces.
  double uncertified_diagonal = 0;
  /// Wall time of the phases: refinement (phase 1, and the refinement of split leaves), the table
  /// of leaf corners and their signs, extraction (pieces, loops, fans), joining the mesh.
  double seconds_refine = 0, seconds_table = 0, seconds_extract = 0, seconds_assemble = 0;
};

/// The mesh, its statistics, and the cells it could not certify.
struct CertifiedMesh {
  TriangleSoup soup;
  CertifiedMeshStats stats;
  std::vector<UncertifiedCell> uncertified;
  /// How the work was shared between processes (Exec::spread), summed over the mesher's loops
  /// (the refinement of the root cells and of split leaves, the extraction of every round);
  /// empty without a spread.
  SpreadBalance balance;
};

/// Root cells per axis for these settings: powers of two that make the root cells near cubes.
std::array<int, 3> certified_root_cells(const CertifiedMeshSettings& settings);

/// The smallest min_depth whose cells have no edge longer than `edge` (at most max_depth).
int certified_depth_for_edge(const CertifiedMeshSettings& settings, double edge);

/// The min_depth that `iaa mesh --resolution N` means: cells of at most 2 (longest side of the
/// bounds) / N. A cell's fan has about twice the triangles of a marching-cubes voxel, so cells of
/// twice the voxel's edge give meshes of about the size of a grid of N per axis.
int certified_depth_for_resolution(const CertifiedMeshSettings& settings, int resolution);

/// Meshes f = 0 in settings.bounds. The result is identical for any thread count, and, with
/// Exec::spread, for any number of processes (the refinement's subtrees and the extraction's
/// leaves are shared; the table of corners and the assembly run in every process alike).
/// Throws SettingError on invalid settings or when settings.max_boxes leaves would be exceeded.
CertifiedMesh mesh_certified(const Tape& tape, const CertifiedMeshSettings& settings,
                             const Exec& exec = {});

}  // namespace iaa
