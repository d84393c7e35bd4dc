// Checks of a Scene that concern what it describes rather than how it was written (scene.h).
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

#include "core/error.h"
#include "expr/eval_interval.h"
#include "expr/eval_point.h"

namespace iaa {

namespace {

/// Sub-boxes per axis of the first grid of undefined_everywhere, and how many boxes it may
/// evaluate in all before it gives up (a few milliseconds for a long tape).
constexpr int kDomainGrid = 8;
constexpr long kDomainBudget = 50000;

/// The kDomainGrid^3 sub-boxes of `b`. Grid edges in round-to-nearest: neighbours share one edge
/// value, the last is b.hi, so the sub-boxes cover b exactly.
std::deque<Box3> grid_of(const Box3& b) {
  double edge[3][kDomainGrid + 1];
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < kDomainGrid; ++i) {
      edge[a][i] = std::min(b.hi[a], b.lo[a] + (b.hi[a] - b.lo[a]) * i / kDomainGrid);
    }
    edge[a][kDomainGrid] = b.hi[a];
  }
  std::deque<Box3> open;
  for (int i = 0; i < kDomainGrid; ++i) {
    for (int j = 0; j < kDomainGrid; ++j) {
      for (int k = 0; k < kDomainGrid; ++k) {
        open.push_back(Box3{{edge[0][i], edge[1][j], edge[2][k]},
                            {edge[0][i + 1], edge[1][j + 1], edge[2][k + 1]}});
      }
    }
  }
  return open;
}

/// Proves that f is undefined (NaN) at every point of `b`: the number of boxes whose empty
/// interval values cover `b`, or 0 when f is defined somewhere or no proof was found in the
/// budget. A box's interval value is empty only when f is undefined at all of its points, so a
/// cover of empty boxes is a proof; a finite value at any point disproves it at once. The box is
/// cut into a kDomainGrid^3 grid, then every box that is neither empty nor shown defined at its
/// centre is halved on all axes, breadth first (one interval evaluation over the whole box misses
/// `sqrt(x - x - 1)`, whose interval over a box wider than 1 reaches above 0).
long undefined_everywhere(const Tape& tape, const Box3& b) {
  PointEval pe(tape);
  IntervalEval ie(tape);
  std::deque<Box3> open = grid_of(b);
  // Point samples first: for most expressions the first centre is finite and that settles it.
  for (const Box3& c : open) {
    if (std::isfinite(pe.eval(c.center()))) return 0;
  }
  for (int a = 0; a < 3; ++a) {
    if (std::isfinite(pe.eval(a == 0 ? b.lo : a == 1 ? b.hi : b.center()))) return 0;
  }
  long empty = 0, evaluated = 0;
  while (!open.empty()) {
    if (++evaluated > kDomainBudget) return 0;
    const Box3 c = open.front();
    open.pop_front();
    if (ie.eval(c).is_empty()) {
      ++empty;
      continue;
    }
    const Vec3 m = c.center();
    if (std::isfinite(pe.eval(m))) return 0;
    // Halve on every axis; a box too small to split (m equal to an end) stays unproved.
    for (int a = 0; a < 3; ++a) {
      if (!(c.lo[a] < m[a] && m[a] < c.hi[a])) return 0;
    }
    for (int q = 0; q < 8; ++q) {
      Box3 h = c;
      for (int a = 0; a < 3; ++a) (((q >> a) & 1) ? h.lo : h.hi)[a] = m[a];
      open.push_back(h);
    }
  }
  return empty;
}

}  // namespace

void validate_surface(const Tape& tape, const Box3& bounds) {
  if (const long boxes = undefined_everywhere(tape, bounds); boxes > 0) {
    throw Error("f is undefined (NaN) everywhere in the bounds (proved on " +
                std::to_string(boxes) + " sub-boxes); there is no surface to show");
  }
}

}  // namespace iaa
