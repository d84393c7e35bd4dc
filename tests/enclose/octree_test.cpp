// The enclosure octree's guarantees: every certified root lies in a leaf (containment), crossing
// leaves have corners of proved opposite signs, deeper enclosures nest in shallower ones, the
// result does not depend on the thread count, and bad settings are clear errors.
#include "enclose/octree.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

#include "core/error.h"
#include "enclose_support.h"
#include "expr/eval_interval.h"
#include "test_progress.h"

namespace iaa {
namespace {

using test::LeafSet;
using test::test_surface;
using test::test_surfaces;

Enclosure run(const std::string& expr, const Box3& b, int depth, int refine = 0, int threads = 2) {
  const Tape tape = Tape::parse(expr);
  EncloseSettings s;
  s.bounds = b;
  s.depth = depth;
  s.refine_possible = refine;
  Exec exec;
  exec.threads = threads;
  return enclose(tape, s, exec);
}

const Box3 kUnit{{-1, -1, -1}, {1, 1, 1}};

TEST(EncloseSettings, RejectsBadValuesWithTheirLimits) {
  EncloseSettings s;
  s.bounds = kUnit;
  EXPECT_NO_THROW(s.validate());
  for (int d : {0, 22, 30, -1}) {
    s.depth = d;
    try {
      s.validate();
      FAIL() << "depth " << d << " accepted";
    } catch (const SettingError& e) {
      EXPECT_NE(std::string(e.what()).find("between 1 and 21"), std::string::npos) << e.what();
    }
  }
  s.depth = 5;
  s.refine_possible = 9;
  EXPECT_THROW(s.validate(), SettingError);
  s.refine_possible = 0;
  s.max_boxes = 0;
  EXPECT_THROW(s.validate(), SettingError);
  s.max_boxes = 10;
  s.bounds = Box3{{0, 0, 0}, {1, 0, 1}};  // empty y range
  EXPECT_THROW(s.validate(), SettingError);
  s.bounds = Box3{{0, 0, 0}, {1, 1, -1}};  // inverted z range
  try {
    s.validate();
    FAIL();
  } catch (const SettingError& e) {
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
  s.bounds = Box3{{0, 0, 0}, {1, 1, Interval::kInf}};
  EXPECT_THROW(s.validate(), SettingError);
}

TEST(Enclose, MaxBoxesExceededIsAClearError) {
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.5");
  EncloseSettings s;
  s.bounds = kUnit;
  s.depth = 6;
  s.max_boxes = 100;
  try {
    enclose(tape, s);
    FAIL() << "no error";
  } catch (const SettingError& e) {
    EXPECT_NE(std::string(e.what()).find("max_boxes"), std::string::npos) << e.what();
  }
  s.max_boxes = 1'000'000;
  EXPECT_GT(enclose(tape, s).cells.size(), 100u);
  // The deepest settings stop as soon as the limit is passed (the breadth-first start is bounded).
  s.depth = EncloseSettings::kMaxDepth;
  s.refine_possible = EncloseSettings::kMaxRefine;
  s.max_boxes = 10'000;
  EXPECT_THROW(enclose(tape, s), SettingError);
}

TEST(Enclose, NoZeroInTheBoxGivesAValidEmptyResult) {
  const Enclosure e = run("x^2 + y^2 + z^2 + 1", kUnit, 6);
  EXPECT_TRUE(e.cells.empty());
  EXPECT_EQ(e.count(CellClass::kCrossing) + e.count(CellClass::kPossible), 0u);
  EXPECT_GE(e.evaluations, 1u);
  EXPECT_EQ(e.counts_by_depth.size(), 7u);
  // f undefined everywhere: nothing to enclose either.
  EXPECT_TRUE(run("sqrt(-1 - x^2)", kUnit, 4).cells.empty());
}

TEST(Enclose, GridCoordinatesNestAndTileTheBounds) {
  const double lo = -1.05, hi = 1.0;
  EXPECT_EQ(grid_coordinate(lo, hi, 0, 7), lo);
  EXPECT_EQ(grid_coordinate(lo, hi, 128, 7), hi);
  for (std::uint64_t i = 0; i < 128; ++i) {
    EXPECT_EQ(grid_coordinate(lo, hi, i, 7), grid_coordinate(lo, hi, 2 * i, 8));
    EXPECT_EQ(grid_coordinate(lo, hi, i, 7), grid_coordinate(lo, hi, 8 * i, 10));
    EXPECT_LT(grid_coordinate(lo, hi, i, 7), grid_coordinate(lo, hi, i + 1, 7));
  }
  // Same value whatever the caller's rounding mode.
  const double outside = grid_coordinate(lo, hi, 37, 7);
  RoundingScope scope;
  EXPECT_EQ(grid_coordinate(lo, hi, 37, 7), outside);
}

TEST(Enclose, SphereLeavesHugTheSphereAndCrossingsAreProved) {
  const double r = 0.7;
  const Enclosure e = run("x^2 + y^2 + z^2 - 0.49", kUnit, 6);
  ASSERT_FALSE(e.cells.empty());
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.49");
  IntervalEval ie(tape);
  RoundingScope scope;
  const double diag = std::sqrt(3.0) * 2.0 / 64;
  for (const Cell& c : e.cells) {
    EXPECT_EQ(c.depth, 6);
    const Box3 b = e.box(c);
    // The leaf is near the sphere: its centre within a cell diagonal of radius r.
    EXPECT_NEAR(length(b.center()), r, diag);
    EXPECT_TRUE(c.f.contains_zero());
    if (c.cls == CellClass::kCrossing) {
      bool pos = false, neg = false;
      for (int k = 0; k < 8; ++k) {
        const Vec3 p{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                     (k & 4) ? b.hi.z : b.lo.z};
        const int s = test::proved_sign(ie, p);
        pos |= s > 0;
        neg |= s < 0;
      }
      EXPECT_TRUE(pos && neg) << "crossing leaf without proved corner signs";
    }
  }
  // A smooth sphere is certified almost everywhere.
  EXPECT_GT(e.count(CellClass::kCrossing), 9 * e.count(CellClass::kPossible));
}

// Corner signs recorded in the leaves are proofs: a sign recorded as negative (positive) is never
// contradicted by the interval evaluation of the corner point. With all_corner_signs every corner
// sign that the point evaluation proves is recorded on crossing leaves, and the leaves, their
// order and classes are the same as without it.
TEST(Enclose, RecordedCornerSignsAreProvedAndComplete) {
  for (const auto& s : test_surfaces()) {
    const Tape tape = Tape::parse(s.expr);
    EncloseSettings es;
    es.bounds = s.bounds;
    es.depth = 5;
    es.refine_possible = 2;
    const Enclosure plain = enclose(tape, es);
    es.all_corner_signs = true;
    const Enclosure all = enclose(tape, es);
    ASSERT_EQ(plain.cells.size(), all.cells.size()) << s.name;
    IntervalEval ie(tape);
    RoundingScope scope;
    std::uint64_t recorded = 0;
    for (std::size_t i = 0; i < all.cells.size(); ++i) {
      const Cell& c = all.cells[i];
      ASSERT_EQ(c.index, plain.cells[i].index) << s.name;
      ASSERT_EQ(c.cls, plain.cells[i].cls) << s.name;
      // What the plain run recorded, the full run records too.
      EXPECT_EQ(plain.cells[i].corner_signs & ~c.corner_signs, 0) << s.name << " cell " << i;
      const Box3 b = all.box(c);
      for (int k = 0; k < 8; ++k) {
        const Vec3 p{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                     (k & 4) ? b.hi.z : b.lo.z};
        const int bits = (c.corner_signs >> (2 * k)) & 3;
        ASSERT_NE(bits, 3) << s.name << ": both signs recorded";
        const int proved = test::proved_sign(ie, p);
        if (bits == 1) {
          EXPECT_NE(proved, 1) << s.name << " cell " << i << " corner " << k;
        }
        if (bits == 2) {
          EXPECT_NE(proved, -1) << s.name << " cell " << i << " corner " << k;
        }
        // A leaf where f is defined on the whole cell records every sign the point proves.
        if (bits == 0 && c.cls == CellClass::kCrossing) {
          EXPECT_EQ(proved, 0) << s.name << " cell " << i << " corner " << k;
        }
        recorded += bits != 0;
      }
    }
    EXPECT_GT(recorded, 0u) << s.name;
  }
}

TEST(Enclose, CanonicalOrderAndNoDuplicates) {
  const auto& s = test_surface("teardrop");  // with refinement: several depths
  const Enclosure e = run(s.expr, s.bounds, 5, 3);
  ASSERT_GT(e.cells.size(), 100u);
  for (std::size_t i = 1; i < e.cells.size(); ++i) {
    EXPECT_TRUE(canonical_less(e.cells[i - 1], e.cells[i])) << "cells " << i - 1 << " and " << i;
  }
  std::uint64_t total = 0;
  for (const auto& c : e.counts_by_depth) total += c[0] + c[1];
  EXPECT_EQ(total, e.cells.size());
}

TEST(Enclose, SameResultForAnyThreadCount) {
  for (const char* name : {"chubs", "twist"}) {
    const auto& s = test_surface(name);
    const Enclosure a = run(s.expr, s.bounds, 6, 1, 1);
    for (int threads : {2, 3}) {
      const Enclosure b = run(s.expr, s.bounds, 6, 1, threads);
      ASSERT_EQ(a.cells.size(), b.cells.size()) << name;
      for (std::size_t i = 0; i < a.cells.size(); ++i) {
        ASSERT_EQ(a.cells[i].index, b.cells[i].index) << name << " cell " << i;
        ASSERT_EQ(a.cells[i].depth, b.cells[i].depth);
        ASSERT_EQ(a.cells[i].cls, b.cells[i].cls);
        ASSERT_EQ(a.cells[i].f, b.cells[i].f);
      }
      EXPECT_EQ(a.evaluations, b.evaluations);
      EXPECT_EQ(a.corner_evaluations, b.corner_evaluations);
    }
  }
}

// Without the mean-value form, a leaf's f is the natural interval value over its box, which the
// octree takes from the batched evaluator (a cell's children in one pass, eval_batch.h): the same
// doubles as IntervalEval's, bit for bit.
TEST(Enclose, NaturalIntervalLeavesHoldTheIntervalEvalValue) {
  for (const char* name : {"chubs", "teardrop", "steiner_roman", "blobby", "gyroid"}) {
    const auto& ts = test_surface(name);
    const Tape tape = Tape::parse(ts.expr);
    EncloseSettings s;
    s.bounds = ts.bounds;
    s.depth = 5;
    s.refine_possible = 1;
    s.centered_form = false;
    Exec exec;
    exec.threads = 2;
    const Enclosure e = enclose(tape, s, exec);
    ASSERT_FALSE(e.cells.empty()) << name;
    IntervalEval ie(tape);
    for (const Cell& c : e.cells) {
      const Interval want = ie.eval(e.box(c));
      ASSERT_EQ(std::bit_cast<std::uint64_t>(c.f.lo()), std::bit_cast<std::uint64_t>(want.lo()))
          << name;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(c.f.hi()), std::bit_cast<std::uint64_t>(want.hi()))
          << name;
    }
  }
}

// Every leaf of a deeper enclosure lies in a leaf of a shallower one, and refinement only removes
// volume.
TEST(Enclose, DeeperEnclosuresNestInShallowerOnes) {
  for (const char* name : {"teardrop", "chubs", "tritrumpet", "gyroid"}) {
    const auto& s = test_surface(name);
    const Enclosure shallow = run(s.expr, s.bounds, 4);
    const LeafSet in_shallow(shallow);
    for (int depth : {5, 6}) {
      for (int refine : {0, 2}) {
        const Enclosure deep = run(s.expr, s.bounds, depth, refine);
        for (const Cell& c : deep.cells) {
          const int up = c.depth - 4;
          const std::array<std::uint32_t, 3> anc{c.index[0] >> up, c.index[1] >> up,
                                                 c.index[2] >> up};
          ASSERT_TRUE(in_shallow.has(4, anc))
              << name << ": depth " << depth << " refine " << refine << " leaf at depth "
              << int(c.depth) << " (" << c.index[0] << "," << c.index[1] << "," << c.index[2]
              << ") is outside the depth-4 enclosure";
        }
      }
    }
    // With refinement, each refined leaf descends from a possible leaf of the unrefined one, and
    // the crossing leaves of depth 6 are kept as they are.
    const Enclosure plain = run(s.expr, s.bounds, 6);
    const Enclosure refined = run(s.expr, s.bounds, 6, 2);
    const LeafSet in_plain(plain);
    for (const Cell& c : refined.cells) {
      const int up = c.depth - 6;
      const std::array<std::uint32_t, 3> anc{c.index[0] >> up, c.index[1] >> up, c.index[2] >> up};
      ASSERT_TRUE(in_plain.has(6, anc)) << name;
    }
    EXPECT_EQ(refined.counts_by_depth[6][0], plain.counts_by_depth[6][0]) << name;
    EXPECT_EQ(refined.counts_by_depth[6][1], 0u) << name;
  }
}

// The guarantee itself: roots found by certified 1D searches along random segments all lie in
// the union of the leaves. A root box touching a shared face may belong to either neighbour, so
// the check is whether a leaf's exact box meets the (few-ulp) root box.
TEST(Enclose, CertifiedRootsOnRandomSegmentsLieInTheLeaves) {
  std::mt19937_64 rng(20261122);
  int surfaces = 0;
  for (const auto& s : test_surfaces()) {
    const Tape tape = Tape::parse(s.expr);
    for (int refine : {0, 2}) {
      const Enclosure e = run(s.expr, s.bounds, 5, refine);
      const LeafSet leaves(e);
      IntervalEval ie(tape);
      RoundingScope scope;
      std::uniform_real_distribution<double> u(0.0, 1.0);
      const auto random_point = [&] {
        Vec3 p;
        for (int a = 0; a < 3; ++a)
          p[a] = s.bounds.lo[a] + u(rng) * (s.bounds.hi[a] - s.bounds.lo[a]);
        return p;
      };
      int roots = 0;
      const int segments = refine == 0 ? 1500 : 500;
      for (int k = 0; k < segments; ++k) {
        const Vec3 a = random_point(), b = random_point();
        for (const Box3& r : test::certified_roots(ie, a, b)) {
          ++roots;
          ASSERT_TRUE(leaves.meets(r))
              << s.name << " (refine " << refine << "): certified root near (" << r.lo.x << ", "
              << r.lo.y << ", " << r.lo.z << ") on segment " << k << " is in no leaf";
        }
      }
      EXPECT_GT(roots, segments / 4) << s.name << ": too few roots to test anything";
      // Every crossing leaf has corners of proved opposite signs.
      for (const Cell& c : e.cells) {
        if (c.cls != CellClass::kCrossing) continue;
        const Box3 b = e.box(c);
        bool pos = false, neg = false;
        for (int k = 0; k < 8; ++k) {
          const int sign = test::proved_sign(
              ie,
              {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z});
          pos |= sign > 0;
          neg |= sign < 0;
        }
        ASSERT_TRUE(pos && neg) << s.name << ": crossing leaf without proved corner signs";
      }
    }
    ++surfaces;
  }
  EXPECT_GE(surfaces, 6);
}

// A surface with no sign change at all, (|p|^2 - 1/4)^2 = 0: nothing can be certified, yet every
// point of the sphere must be enclosed (no algorithm may rely on a sign change).
TEST(Enclose, SurfaceWithoutSignChangeIsEnclosedAsPossible) {
  const Enclosure e = run("(x^2 + y^2 + z^2 - 0.25)^2", kUnit, 5, 2);
  ASSERT_FALSE(e.cells.empty());
  EXPECT_EQ(e.count(CellClass::kCrossing), 0u);
  const LeafSet leaves(e);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    Vec3 u{n(rng), n(rng), n(rng)};
    u = 0.5 * normalize(u);
    // u is within a few ulps of the sphere; a tiny box around it holds a point of it.
    const Box3 b{u - Vec3{1e-12, 1e-12, 1e-12}, u + Vec3{1e-12, 1e-12, 1e-12}};
    ASSERT_TRUE(leaves.meets(b)) << "sphere point (" << u.x << ", " << u.y << ", " << u.z << ")";
  }
}

// The teardrop's neck is thinner than a depth-5 cell: the search along the x axis (where the
// neck is) still finds roots, and they are enclosed; refinement keeps the neck connected.
TEST(Enclose, TeardropNeckIsEnclosed) {
  const auto& s = test_surface("teardrop");
  const Enclosure e = run(s.expr, s.bounds, 6, 4);
  const LeafSet leaves(e);
  const Tape tape = Tape::parse(s.expr);
  IntervalEval ie(tape);
  RoundingScope scope;
  int roots = 0;
  for (int k = 0; k < 200; ++k) {
    const double x = -0.2 + 0.4 * k / 199.0;
    // Radial segments across the neck at x.
    const double ang = 0.1 * k;
    const Vec3 a{x, 0, 0}, b{x, 0.05 * std::cos(ang), 0.05 * std::sin(ang)};
    for (const Box3& r : test::certified_roots(ie, a, b)) {
      ++roots;
      ASSERT_TRUE(leaves.meets(r)) << "neck root at x = " << x;
    }
  }
  EXPECT_GT(roots, 100);
}

TEST(Enclose, CancelStopsWithAnError) {
  test::CancelAtStart progress;
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 - 0.5");
  EncloseSettings s;
  s.bounds = kUnit;
  s.depth = 8;
  Exec exec;
  exec.progress = &progress;
  EXPECT_THROW(enclose(tape, s, exec), Error);
}

}  // namespace
}  // namespace iaa
