// Shared helpers of the mesh tests: a small, self-contained enclosure (so the mesher's extraction
// is tested independently of enclose()), with optional forced refinement to mix cell depths; and
// the check that two meshes are the same, vertex for vertex and triangle for triangle.
#pragma once

#include <gtest/gtest.h>

#include <functional>

#include "enclose/octree.h"
#include "expr/eval_interval.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa::test {

/// The same triangles and the same vertices, bit for bit.
inline void expect_same_soup(const TriangleSoup& a, const TriangleSoup& b) {
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]);
}

/// Splits the bounds to `depth`, discards cells with 0 outside F, classifies leaves by certified
/// corner signs, refines possible leaves up to `refine` levels further, and additionally splits
/// any kept cell for which `force_split(box, depth)` is true (to mix depths), down to `max_depth`.
inline Enclosure local_enclose(const Tape& tape, const Box3& bounds, int depth, int refine,
                               std::function<bool(const Box3&, int)> force_split = {},
                               int max_depth = 0) {
  Enclosure e;
  e.bounds = bounds;
  IntervalEval ie(tape);
  RoundingScope scope;
  const int deepest = std::max(depth + refine, max_depth);
  std::function<void(int, std::array<std::uint32_t, 3>)> visit =
      [&](int d, std::array<std::uint32_t, 3> idx) {
        Cell c{idx, static_cast<std::uint8_t>(d), CellClass::kPossible, 0, {}};
        Box3 b;
        {
          const int saved = std::fegetround();
          std::fesetround(FE_TONEAREST);
          const double n = std::ldexp(1.0, d);
          for (int a = 0; a < 3; ++a) {
            const double s = bounds.hi[a] - bounds.lo[a];
            b.lo[a] = bounds.lo[a] + s * (idx[std::size_t(a)] / n);
            b.hi[a] = idx[std::size_t(a)] + 1 == n
                          ? bounds.hi[a]
                          : bounds.lo[a] + s * ((idx[std::size_t(a)] + 1) / n);
          }
          std::fesetround(saved);
        }
        const Interval f = ie.eval(IBox(b));
        ++e.evaluations;
        if (!f.contains_zero()) return;
        c.f = f;
        const bool partial = ie.partial_domain();
        bool crossing = false;
        if (d >= depth) {
          bool pos = false, neg = false;
          for (int k = 0; k < 8; ++k) {
            const Interval v = ie.eval(IBox(Interval((k & 1) ? b.hi.x : b.lo.x),
                                            Interval((k & 2) ? b.hi.y : b.lo.y),
                                            Interval((k & 4) ? b.hi.z : b.lo.z)));
            pos |= v.certainly_positive();
            neg |= v.certainly_negative();
          }
          crossing = pos && neg && !partial;
        }
        const bool forced = force_split && d < max_depth && force_split(b, d);
        const bool split = d < depth || forced || (!crossing && d < depth + refine);
        if (!split) {
          c.cls = crossing ? CellClass::kCrossing : CellClass::kPossible;
          e.cells.push_back(c);
          return;
        }
        for (int k = 0; k < 8; ++k) {
          visit(d + 1,
                {2 * idx[0] + (k & 1), 2 * idx[1] + ((k >> 1) & 1), 2 * idx[2] + ((k >> 2) & 1)});
        }
      };
  (void)deepest;
  visit(0, {0, 0, 0});
  return e;
}

}  // namespace iaa::test
