// SpecializingEval: min/max pruning by regions gives the whole tape's results.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "expr/specialize.h"
#include "random_expr.h"

namespace iaa {
namespace {

/// The same number, or both NaN. (The sign of a zero may differ: a partial derivative that is
/// structurally zero in the shorter tape is not computed there, where the whole tape adds a 0
/// rounded downward, -0. [-0, a] and [0, a] are the same interval.)
bool same(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}
bool same(const Interval& a, const Interval& b) {
  return same(a.lo(), b.lo()) && same(a.hi(), b.hi());
}

/// A random box inside `b`: each side a random sub-interval (sometimes the whole side, sometimes
/// a point, sometimes an end).
IBox sub_box(iaa::testing::RandomExpr& gen, const IBox& b) {
  IBox out;
  for (int i = 0; i < 3; ++i) {
    const double lo = b[i].lo(), hi = b[i].hi();
    double u = gen.uniform(lo, hi), v = gen.uniform(lo, hi);
    switch (gen.pick(5)) {
      case 0:
        u = lo, v = hi;
        break;
      case 1:
        v = u;
        break;
      case 2:
        u = lo;
        break;
      default:
        break;
    }
    out[i] = Interval(std::fmin(u, v), std::fmax(u, v));
  }
  return out;
}

/// A random expression with a min or max at the top, usually more inside.
std::string min_max_expression(iaa::testing::RandomExpr& gen) {
  return std::string(gen.pick(2) ? "min(" : "max(") + gen.make(3) + ", " + gen.make(3) + ") + " +
         gen.make(2);
}

TEST(Specialize, SameResultsAsTheWholeTapeOnNestedBoxes) {
  iaa::testing::RandomExpr gen(20261201);
  std::uint64_t specialized = 0, compared = 0;
  RoundingScope scope;
  for (int e = 0; e < 3000; ++e) {
    const std::string text = min_max_expression(gen);
    if (!gen.parses(text)) continue;
    const Tape t = Tape::parse(text);
    IntervalEval ie(t);
    IntervalGradEval ig(t);
    PointEval pe(t);
    PointGradEval pg(t);
    SpecializingEval se(t);
    for (int chain = 0; chain < 4; ++chain) {
      IBox box = gen.box();
      for (int level = 0; level < 6; ++level) {
        const bool grad = gen.pick(2) == 0;
        if (grad) {
          const IGrad want = ig.eval(box), got = se.eval_grad(box);
          ASSERT_TRUE(same(want.v, got.v)) << text;
          for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(same(want.g[i], got.g[i])) << text;
          ASSERT_EQ(ig.partial_domain(), se.partial_domain()) << text;
        } else {
          const Interval want = ie.eval(box), got = se.eval(box);
          ASSERT_TRUE(same(want, got)) << text << " on box " << box.x.lo() << " " << box.x.hi();
          ASSERT_EQ(ie.partial_domain(), se.partial_domain()) << text;
        }
        for (int k = 0; k < 3; ++k) {
          const Vec3 p = gen.point(box);
          ASSERT_TRUE(same(pe.eval(p), se.eval_point(p))) << text;
          const PGrad want = pg.eval(p), got = se.eval_point_grad(p);
          ASSERT_TRUE(same(want.v, got.v)) << text;
          for (int i = 0; i < 3; ++i) ASSERT_TRUE(same(want.g[i], got.g[i])) << text;
        }
        ++compared;
        box = sub_box(gen, box);
      }
    }
    specialized += se.specialized_evals();
  }
  // The test has to reach the specialized tapes to mean anything.
  EXPECT_GT(compared, 30000u);
  EXPECT_GT(specialized, compared / 10);
}

// The batches evaluate up to kBatch boxes with the tape of a region that holds them all: each
// box's result is the whole tape's (values and flags as IntervalEval's, gradients as
// IntervalGradEval's up to the signs of zeros), with the SSE2 and the AVX2 code.
TEST(Specialize, BatchesGiveTheWholeTapesResultsOnNestedBoxes) {
  iaa::testing::RandomExpr gen(20261204);
  std::uint64_t compared = 0, specialized = 0;
  RoundingScope scope;
  for (int e = 0; e < 1500; ++e) {
    const std::string text = min_max_expression(gen);
    if (!gen.parses(text)) continue;
    const Tape t = Tape::parse(text);
    IntervalEval ie(t);
    IntervalGradEval ig(t);
    SpecializingEval se(t);
    se.use_baseline(e % 2 == 1);
    for (int chain = 0; chain < 3; ++chain) {
      IBox box = gen.box();
      for (int level = 0; level < 6; ++level) {
        se.eval(box);  // makes the regions the batches then find
        const int n = 1 + gen.pick(SpecializingEval::kBatch);
        IBox boxes[SpecializingEval::kBatch];
        // Mostly boxes inside the region, now and then one elsewhere (the whole tape then).
        for (int j = 0; j < n; ++j) boxes[j] = gen.pick(4) == 0 ? gen.box() : sub_box(gen, box);
        const std::uint64_t s0 = se.specialized_evals();
        Interval f[SpecializingEval::kBatch];
        IGrad g[SpecializingEval::kBatch];
        bool pf[SpecializingEval::kBatch], pg[SpecializingEval::kBatch];
        se.eval_batch(boxes, n, f, pf);
        se.eval_grad_batch(boxes, n, g, pg);
        specialized += se.specialized_evals() - s0;
        for (int j = 0; j < n; ++j) {
          ASSERT_TRUE(same(ie.eval(boxes[j]), f[j])) << text;
          ASSERT_EQ(ie.partial_domain(), pf[j]) << text;
          const IGrad want = ig.eval(boxes[j]);
          ASSERT_TRUE(same(want.v, g[j].v)) << text;
          for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(same(want.g[i], g[j].g[i])) << text;
          ASSERT_EQ(ig.partial_domain(), pg[j]) << text;
          ++compared;
        }
        box = sub_box(gen, box);
      }
    }
  }
  // The batches have to reach the specialized tapes to mean anything.
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(specialized, compared / 10);
}

TEST(Specialize, TwistBladePrunesTheOtherBlade) {
  // The twist scene: min of two crossed blades. Near blade A, far from the axis, B is far larger.
  const Tape t = Tape::parse(
      "min((x*cos(1.2*z) + y*sin(1.2*z))^4 + ((y*cos(1.2*z) - x*sin(1.2*z))/0.03)^4 + (z/1.5)^4 "
      "- 1, ((x*cos(1.2*z) + y*sin(1.2*z))/0.03)^4 + (y*cos(1.2*z) - x*sin(1.2*z))^4 + "
      "(z/1.5)^4 - 1)");
  RoundingScope scope;
  SpecializingEval se(t);
  IntervalEval ie(t);
  const IBox region(Interval(0.5, 0.52), Interval(0.0, 0.02), Interval(0.0, 0.01));
  EXPECT_TRUE(same(se.eval(region), ie.eval(region)));
  EXPECT_EQ(se.specialized_evals(), 0u);
  EXPECT_EQ(se.variants(), 1);
  const IBox inside(Interval(0.505, 0.51), Interval(0.001, 0.002), Interval(0.0, 0.005));
  EXPECT_TRUE(same(se.eval(inside), ie.eval(inside)));
  EXPECT_EQ(se.specialized_evals(), 1u);
  // A box outside the region uses the whole tape again (and makes a region of its own).
  const IBox outside(Interval(0.6, 0.61), Interval(0.0, 0.01), Interval(0.0, 0.01));
  EXPECT_TRUE(same(se.eval(outside), ie.eval(outside)));
  EXPECT_EQ(se.specialized_evals(), 1u);
  EXPECT_EQ(se.variants(), 1);  // the same choice: the same specialized tape
}

TEST(Specialize, BoxesWithAnEmptySideUseTheWholeTape) {
  // An empty interval counts as inside every interval; such a box must not take a region's tape.
  const Tape t = Tape::parse("min(x, y + 10)");
  RoundingScope scope;
  SpecializingEval se(t);
  IntervalEval ie(t);
  se.eval(IBox(Interval(0, 1), Interval(0, 1), Interval(0)));  // a region: min takes x
  const IBox empty_y(Interval(0.5), Interval::empty(), Interval(0));
  EXPECT_TRUE(same(se.eval(empty_y), ie.eval(empty_y)));
  EXPECT_EQ(se.specialized_evals(), 0u);
}

TEST(Specialize, APointMakesNoRegion) {
  // A point box decides min(x, y + 10) but would only ever contain itself.
  const Tape t = Tape::parse("min(x, y + 10)");
  RoundingScope scope;
  SpecializingEval se(t);
  const IBox p(Interval(0.5), Interval(0.25), Interval(0));
  se.eval(p);
  se.eval(p);
  EXPECT_EQ(se.specialized_evals(), 0u);
  EXPECT_EQ(se.variants(), 0);
}

TEST(Specialize, AtMostKMaxVariantsTapesAndResetForgetsThem) {
  // Each box [a + 0.1, a + 0.2] x [b + 0.1, b + 0.2] decides all sixteen mins one way for each
  // (a, b): 81 different specializations, more than are kept.
  std::string text;
  for (int c = 1; c <= 8; ++c) {
    text += (c > 1 ? " + " : "") + std::string("min(x, ") + std::to_string(c) + ") + min(y, " +
            std::to_string(c) + ")";
  }
  const Tape t = Tape::parse(text);
  RoundingScope scope;
  SpecializingEval se(t), fresh(t);
  IntervalEval ie(t);
  const auto sweep = [&](SpecializingEval& e) {
    for (int a = 0; a <= 8; ++a) {
      for (int b = 0; b <= 8; ++b) {
        const IBox box(Interval(a + 0.1, a + 0.2), Interval(b + 0.1, b + 0.2), Interval(0));
        const IBox inside(Interval(a + 0.15), Interval(b + 0.15, b + 0.16), Interval(0));
        ASSERT_TRUE(same(e.eval(box), ie.eval(box)));
        ASSERT_TRUE(same(e.eval(inside), ie.eval(inside)));
      }
    }
  };
  sweep(se);
  EXPECT_EQ(se.variants(), SpecializingEval::kMaxVariants);
  EXPECT_EQ(se.specialized_evals(), std::uint64_t(SpecializingEval::kMaxVariants));
  se.reset();
  EXPECT_EQ(se.variants(), 0);
  // After reset() the same evaluations specialize exactly as a new evaluator's do.
  const std::uint64_t before = se.specialized_evals();
  sweep(se);
  sweep(fresh);
  EXPECT_EQ(se.specialized_evals() - before, fresh.specialized_evals());
}

TEST(Specialize, NoRegionFromAPartialDomain) {
  // min takes x on the box, but sqrt(y) is undefined on part of it: leaving sqrt out would lose
  // the partial-domain flag on boxes inside, so no region is made.
  const Tape t = Tape::parse("min(x, sqrt(y)) + 1");
  RoundingScope scope;
  SpecializingEval se(t);
  se.eval(IBox(Interval(-5, -4), Interval(-1, 1), Interval(0)));
  EXPECT_TRUE(se.partial_domain());
  se.eval(IBox(Interval(-5, -4.5), Interval(-0.5, 0.5), Interval(0)));
  EXPECT_TRUE(se.partial_domain());
  EXPECT_EQ(se.specialized_evals(), 0u);
  EXPECT_EQ(se.variants(), 0);
}

TEST(Specialize, TiesGoToTheFirstArgument) {
  // Where the enclosures of min(a, b) touch, a tie is possible, and the point rule takes a there:
  // the box must choose a too (or nothing), never b, or a tape specialized to b would differ.
  using detail::max_choice;
  using detail::min_choice;
  EXPECT_EQ(min_choice(Interval(0, 1), Interval(1, 2)), 1);
  EXPECT_EQ(min_choice(Interval(1, 2), Interval(0, 1)), 0);  // tie at 1: not b
  EXPECT_EQ(min_choice(Interval(1, 2), Interval(0, 0.5)), 2);
  EXPECT_EQ(min_choice(Interval(0, 2), Interval(1, 3)), 0);
  EXPECT_EQ(max_choice(Interval(1, 2), Interval(0, 1)), 1);
  EXPECT_EQ(max_choice(Interval(0, 1), Interval(1, 2)), 0);  // tie at 1: not b
  EXPECT_EQ(max_choice(Interval(0, 0.5), Interval(1, 2)), 2);
  EXPECT_EQ(max_choice(Interval(0, 2), Interval(1, 3)), 0);
}

}  // namespace
}  // namespace iaa
