// Shared helpers of the enclosure tests: the test surfaces (read from data/scenes), a lookup of
// leaves by index, and a certified 1D root search along segments.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/error.h"
#include "core/interval.h"
#include "core/vec.h"
#include "enclose/octree.h"
#include "expr/eval_interval.h"
#include "expr/tape.h"
#include "test_scenes.h"

namespace iaa::test {

/// A surface of the enclosure tests: the expression and bounding box of a bundled scene.
struct TestSurface {
  std::string name;
  std::string expr;
  Box3 bounds;
};

/// The scene data/scenes/NAME.toml of the source tree as a test surface. Its expression takes no
/// parameters, since the tests compile `expr` alone.
inline TestSurface load_test_surface(const std::string& name) {
  const Scene scene = bundled_scene(name);
  if (!scene.params.empty()) throw Error(name + ": a test surface takes no parameters");
  return {name, scene.expression, scene.bounds};
}

/// The test surfaces.
inline const std::vector<TestSurface>& test_surfaces() {
  static const std::vector<TestSurface> all = [] {
    std::vector<TestSurface> v;
    for (const char* name : {"teardrop", "chubs", "tritrumpet", "barth_sextic", "twist", "blobby",
                             "steiner_roman", "gyroid", "heart"}) {
      v.push_back(load_test_surface(name));
    }
    return v;
  }();
  return all;
}

/// The test surface called `name`; throws iaa::Error when there is none.
inline const TestSurface& test_surface(const std::string& name) {
  for (const TestSurface& s : test_surfaces()) {
    if (s.name == name) return s;
  }
  throw Error("no test surface '" + name + "'");
}

/// The set of leaves of an enclosure, looked up by (depth, index).
class LeafSet {
 public:
  explicit LeafSet(const Enclosure& e) : enc_(e) {
    for (const Cell& c : e.cells) set_.insert(key(c.depth, c.index));
  }
  bool has(int depth, const std::array<std::uint32_t, 3>& idx) const {
    return set_.count(key(depth, idx)) != 0;
  }

  /// True when a leaf's box (exactly as evaluated, Enclosure::box) meets the closed box p. The
  /// candidates are found by index at every depth, from the grid lines around p.
  bool meets(const Box3& p) const {
    const int max_depth = static_cast<int>(enc_.counts_by_depth.size()) - 1;
    for (int d = 1; d <= max_depth; ++d) {
      std::array<std::uint32_t, 3> lo{}, hi{};
      for (int a = 0; a < 3; ++a) {
        const double b0 = enc_.bounds.lo[a], b1 = enc_.bounds.hi[a];
        const double n = std::ldexp(1.0, d);
        // A generous index range from the real-valued position, then exact tests on the boxes.
        const double t0 = (p.lo[a] - b0) / (b1 - b0) * n, t1 = (p.hi[a] - b0) / (b1 - b0) * n;
        lo[a] = static_cast<std::uint32_t>(std::clamp(std::floor(t0) - 1, 0.0, n - 1));
        hi[a] = static_cast<std::uint32_t>(std::clamp(std::floor(t1) + 1, 0.0, n - 1));
      }
      for (std::uint32_t i = lo[0]; i <= hi[0]; ++i) {
        for (std::uint32_t j = lo[1]; j <= hi[1]; ++j) {
          for (std::uint32_t k = lo[2]; k <= hi[2]; ++k) {
            if (!has(d, {i, j, k})) continue;
            Cell c{{i, j, k}, static_cast<std::uint8_t>(d), CellClass::kPossible, 0, Interval()};
            const Box3 b = enc_.box(c);
            bool meet = true;
            for (int a = 0; a < 3; ++a) meet = meet && b.lo[a] <= p.hi[a] && p.lo[a] <= b.hi[a];
            if (meet) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  static std::uint64_t key(int depth, const std::array<std::uint32_t, 3>& i) {
    // Depth <= 29 (5 bits); indices below 2^19 suffice for the depths used in tests.
    return static_cast<std::uint64_t>(depth) << 59 ^ static_cast<std::uint64_t>(i[0]) << 38 ^
           static_cast<std::uint64_t>(i[1]) << 19 ^ i[2];
  }
  const Enclosure& enc_;
  std::unordered_set<std::uint64_t> set_;
};

/// Sign of f at point p proved by an interval evaluation on the degenerate box: +1, -1 or 0.
inline int proved_sign(IntervalEval& ie, const Vec3& p) {
  const Interval v = ie.eval(IBox(Interval(p.x), Interval(p.y), Interval(p.z)));
  if (ie.partial_domain()) return 0;
  return v.certainly_positive() ? 1 : (v.certainly_negative() ? -1 : 0);
}

/// Certified roots along the segment a -> b: small boxes, each holding two points at which f has
/// proved opposite signs and on whose straight segment f is continuous (no partial domain), so
/// that each box holds a root of f. Pieces of the segment where the interval value excludes 0 are
/// discarded; the search stops after `budget` evaluations. A RoundingScope must be open.
inline std::vector<Box3> certified_roots(IntervalEval& ie, const Vec3& a, const Vec3& b,
                                         int budget = 4000) {
  std::vector<Box3> roots;
  struct Piece {
    double t0, t1;
  };
  const auto point = [&](double t) { return a + t * (b - a); };
  const auto hull = [](const Vec3& p, const Vec3& q) {
    Box3 r;
    for (int i = 0; i < 3; ++i) {
      r.lo[i] = std::fmin(p[i], q[i]);
      r.hi[i] = std::fmax(p[i], q[i]);
    }
    return r;
  };
  std::vector<Piece> stack{{0.0, 1.0}};
  while (!stack.empty() && budget-- > 0) {
    const Piece pc = stack.back();
    stack.pop_back();
    const Vec3 p0 = point(pc.t0), p1 = point(pc.t1);
    // The segment p0 -> p1 lies in the box of its end points: F over that box bounds f on it.
    const Box3 box = hull(p0, p1);
    const Interval f = ie.eval(IBox(box));
    if (!f.contains_zero()) continue;
    const bool continuous = !ie.partial_domain();
    if (pc.t1 - pc.t0 < 1e-3 && continuous) {
      const int s0 = proved_sign(ie, p0), s1 = proved_sign(ie, p1);
      if (s0 * s1 < 0) {
        // Narrow by bisection on proved signs; stop when the middle's sign is not proved.
        Vec3 q0 = p0, q1 = p1;
        double u0 = pc.t0, u1 = pc.t1;
        for (int it = 0; it < 60; ++it) {
          const double um = 0.5 * (u0 + u1);
          if (!(um > u0 && um < u1)) break;
          const Vec3 qm = point(um);
          const int sm = proved_sign(ie, qm);
          if (sm == 0) break;
          if (sm == s0) {
            u0 = um;
            q0 = qm;
          } else {
            u1 = um;
            q1 = qm;
          }
        }
        roots.push_back(hull(q0, q1));
        continue;
      }
      if (pc.t1 - pc.t0 < 1e-9) continue;  // 0 in F but no proved sign change: not certified
    }
    const double tm = 0.5 * (pc.t0 + pc.t1);
    stack.push_back({tm, pc.t1});
    stack.push_back({pc.t0, tm});
  }
  return roots;
}

}  // namespace iaa::test
