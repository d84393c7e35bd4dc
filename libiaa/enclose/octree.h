// Guaranteed enclosure of a surface by an interval octree (docs/design.md, "Enclosure").
//
// The bounds are split recursively; every cell whose interval value excludes 0 is discarded (it
// holds no point of the surface). The leaves kept at the requested depth together contain every
// point of the surface inside the bounds: that is the guarantee. Each leaf is classified:
// - kCrossing: f has corner values of both strict signs and is continuous on the cell (no partial
//   domain), so the surface certainly passes through it;
// - kPossible: 0 is in F(cell) but no sign change was seen: it may or may not hold surface.
// F is the intersection of the natural interval value and the mean-value form (see
// EncloseSettings::centered_form); corner signs are proved by interval evaluations on the
// degenerate boxes of the corners.
// Possible leaves may be refined a few levels deeper (refine_possible) so that thin features are
// either certified or excluded.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "core/exec.h"
#include "core/interval.h"
#include "core/spread.h"
#include "core/vec.h"
#include "expr/tape.h"

namespace iaa {

enum class CellClass : std::uint8_t { kCrossing = 1, kPossible = 2 };

/// A leaf of the enclosure. Its box is bounds split `depth` times along every axis, at integer
/// position `index` (0 <= index[i] < 2^depth), so cells of different depths can be compared and
/// neighbours found exactly.
struct Cell {
  std::array<std::uint32_t, 3> index;
  std::uint8_t depth;
  CellClass cls;
  /// Proved signs of f at the cell's corners (corner k = x bit 0, y bit 1, z bit 2 of k): bit 2k
  /// set when f < 0 there is proved, bit 2k+1 when f > 0 is; neither when it is not known (not
  /// looked at, or not provable). All 8 are looked at with EncloseSettings::all_corner_signs.
  /// Fills the padding before `f`: a cell stays 32 bytes.
  std::uint16_t corner_signs = 0;
  /// An enclosure of f over the cell: the natural interval value and/or a mean-value form (the
  /// parent's expansion, for crossing leaves; their intersection with the cell's own otherwise).
  Interval f;
};

/// What to compute.
struct EncloseSettings {
  Box3 bounds;
  /// Depth of the leaves (1..kMaxDepth): cells are bounds / 2^depth per axis.
  int depth = 7;
  /// Extra levels below `depth` for possible leaves (0..kMaxRefine).
  int refine_possible = 0;
  /// Upper bound on the number of leaves; exceeding it is an error with a clear message.
  std::uint64_t max_boxes = 20'000'000;
  /// Also bound f on each cell by its mean-value form f(c) + G(cell).(cell - c) and keep the
  /// intersection with the natural interval (both are sound). Costs a gradient evaluation per
  /// kept cell and removes most cells that the natural interval cannot exclude near the surface.
  bool centered_form = true;
  /// Prove the signs of all 8 corners of every leaf (Cell::corner_signs), not only until a sign
  /// change is seen. For the mesher, which needs them all; most come from the parent's expansion
  /// at the cost of a few interval additions.
  bool all_corner_signs = false;

  static constexpr int kMaxDepth = 21;
  static constexpr int kMaxRefine = 8;
  /// Throws SettingError naming the setting and its limits.
  void validate() const;
};

/// The result: leaves in canonical order (by depth, then Morton order of index), identical for
/// any thread count.
struct Enclosure {
  Box3 bounds;
  std::vector<Cell> cells;
  std::uint64_t evaluations = 0;  ///< interval evaluations of f over cells
  /// Interval evaluations of f at grid points (degenerate boxes): cell corners for the crossing
  /// test and cell centres for the mean-value form. Each point is evaluated at most once per
  /// parallel subtree.
  std::uint64_t corner_evaluations = 0;
  /// Corner signs proved by the parent cell's mean-value expansion alone (no evaluation of f).
  std::uint64_t expansion_signs = 0;
  /// Number of leaves per depth (index) and class ([0] crossing, [1] possible); its size is
  /// depth + refine_possible + 1 of the settings that produced it.
  std::vector<std::array<std::uint64_t, 2>> counts_by_depth;
  /// How the subtrees were shared between processes (Exec::spread); empty without a spread.
  SpreadBalance balance;

  /// The box of a cell: exactly the box (bit for bit) that f was evaluated on. Neighbouring cells
  /// share their faces exactly and the leaves of one depth tile `bounds` without gaps.
  Box3 box(const Cell& c) const;
  /// Number of leaves of a class.
  std::uint64_t count(CellClass cls) const;
};

/// Coordinate of grid line `i` (0 <= i <= 2^depth) when [lo, hi] is split 2^depth times. Line 0 is
/// lo and line 2^depth is hi exactly; the function is monotone in i and line 2i at depth+1 equals
/// line i at depth, so cells of different depths nest exactly. Computed with upward rounding (a
/// RoundingScope is opened when none is active) so that every caller gets the same double.
double grid_coordinate(double lo, double hi, std::uint64_t i, int depth);

/// grid_coordinate for callers that hold a RoundingScope (not checked): the hot-loop version.
inline double grid_coordinate_upward(double lo, double hi, std::uint64_t i, int depth) {
  if (i == 0) return lo;
  if (i >= (std::uint64_t{1} << depth)) return hi;
  // i * 2^-depth is exact (2^-depth built from its exponent bits, no division); the product and
  // the sum round upward, which keeps the map monotone.
  const double inv = std::bit_cast<double>(static_cast<std::uint64_t>(1023 - depth) << 52);
  return lo + (static_cast<double>(i) * inv) * (hi - lo);
}

/// Canonical order of cells: by depth, then by Morton order of the index (x the least significant
/// bit of each octal digit, then y, then z), which is the depth-first order of the octree.
bool canonical_less(const Cell& a, const Cell& b);

/// Computes the enclosure of f = 0 in settings.bounds. Throws SettingError on invalid settings
/// or when max_boxes is exceeded.
Enclosure enclose(const Tape& tape, const EncloseSettings& settings, const Exec& exec = {});

}  // namespace iaa
