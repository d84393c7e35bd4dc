// Gradients against central finite differences on smooth random expressions, and evaluator basics.
#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "random_expr.h"

namespace iaa {
namespace {

TEST(Gradient, MatchesFiniteDifferences) {
  iaa::testing::RandomExpr gen(42);
  int checked = 0;
  for (int e = 0; e < 3000; ++e) {
    const std::string expr = gen.make(3, /*smooth=*/true);
    if (!gen.parses(expr)) continue;
    const Tape t = Tape::parse(expr);
    PointEval pe(t);
    PointGradEval pg(t);
    for (int k = 0; k < 5; ++k) {
      const Vec3 p{gen.uniform(-2, 2), gen.uniform(-2, 2), gen.uniform(-2, 2)};
      const PGrad g = pg.eval(p);
      if (!std::isfinite(g.v) || std::fabs(g.v) > 1e6) continue;
      for (int i = 0; i < 3; ++i) {
        const double h = 1e-6;
        Vec3 a = p, b = p;
        a[i] -= h;
        b[i] += h;
        const double fa = pe.eval(a), fb = pe.eval(b);
        const double fd = (fb - fa) / (2 * h);
        if (!std::isfinite(fd) || !std::isfinite(g.g[i]) || std::fabs(g.g[i]) > 1e4) continue;
        // A smooth function: the central difference agrees to O(h^2) plus cancellation error.
        // Skip points near a singularity, where the second difference is large.
        Vec3 a2 = p, b2 = p;
        a2[i] -= 2 * h;
        b2[i] += 2 * h;
        const double fd2 = (pe.eval(b2) - pe.eval(a2)) / (4 * h);
        if (!std::isfinite(fd2) || std::fabs(fd2 - fd) > 1e-4 * (1 + std::fabs(fd))) continue;
        EXPECT_NEAR(g.g[i], fd, 1e-4 * (1 + std::fabs(fd))) << expr << " at axis " << i;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 10000);
}

// At a min that the box does not decide, the gradient is the hull of both sides. A side whose
// derivative rule meets a pole (a^(b-1) at a = 0 with b < 1) must not be dropped from that hull:
// in min(2x, (0x)^y) over x in [0, 1e-12], y in [0.9, 1], the second side (exactly 0 for x > 0)
// is taken wherever x > 0, so d/dx takes the value 0 there, and 2 at x = 0.
TEST(Gradient, AKinkKeepsASideWhoseDerivativeHasAPole) {
  RoundingScope scope;
  for (const char* expr : {"min(x + x, pow(0, y))", "min(x + x, pow(x * 0, y))"}) {
    const Tape t = Tape::parse(expr);
    IntervalGradEval ig(t);
    const IGrad g = ig.eval(IBox(Interval(0, 1e-12), Interval(0.9, 1), Interval(0, 1)));
    EXPECT_TRUE(g.g[0].contains(0.0)) << expr << ": " << g.g[0].lo() << ", " << g.g[0].hi();
    EXPECT_TRUE(g.g[0].contains(2.0)) << expr;
  }
}

TEST(Gradient, KnownValues) {
  const Tape t = Tape::parse("x^2*y + sin(z)");
  PointGradEval pg(t);
  const PGrad g = pg.eval({2, 3, 0});
  EXPECT_EQ(g.v, 12);
  EXPECT_EQ(g.g.x, 12);
  EXPECT_EQ(g.g.y, 4);
  EXPECT_EQ(g.g.z, 1);
}

TEST(Evaluators, MinMaxChoicesSimplifyTheTape) {
  const Tape t = Tape::parse("min(x + 10, y^2) + max(z, 0)");
  IntervalEval ie(t);
  RoundingScope scope;
  const IBox box(Interval(0, 1), Interval(0, 1), Interval(-2, -1));
  const Interval full = ie.eval(box);
  const Tape s = t.simplify(ie.choices());
  EXPECT_FALSE(s.has_min_max());
  EXPECT_LT(s.op_count(), t.op_count());
  IntervalEval se(s);
  EXPECT_TRUE(full.contains(se.eval(box)));
  PointEval a(t), b(s);
  EXPECT_EQ(a.eval(0.5, 0.5, -1.5), b.eval(0.5, 0.5, -1.5));
}

TEST(Evaluators, SimplifyingAwayHalfOfASincosPairKeepsTheOtherHalf) {
  // The min certainly takes y^2 on the box, so one half of the sin/cos pair of x goes.
  for (const char* e : {"min(sin(x) + 10, y^2) + cos(x)", "min(cos(x) + 10, y^2) + sin(x)"}) {
    const Tape t = Tape::parse(e);
    IntervalEval ie(t);
    RoundingScope scope;
    const IBox box(Interval(0, 1), Interval(0, 1), Interval(0));
    const Interval full = ie.eval(box);
    const Tape s = t.simplify(ie.choices());
    for (const Instr& in : s.instrs()) {
      EXPECT_NE(in.op, Op::kSinCos) << e << "\n" << s.listing();
      EXPECT_NE(in.op, Op::kPairedCos) << e << "\n" << s.listing();
    }
    IntervalEval se(s);
    EXPECT_TRUE(full.contains(se.eval(box))) << e;
    PointEval a(t), b(s);
    EXPECT_EQ(a.eval(0.5, 0.5, 0), b.eval(0.5, 0.5, 0)) << e;
  }
}

TEST(Evaluators, PartialDomainIsReported) {
  const Tape t = Tape::parse("sqrt(x) - 1");
  IntervalEval ie(t);
  ie.eval(IBox(Interval(-1, 4), Interval(0), Interval(0)));
  EXPECT_TRUE(ie.partial_domain());
  ie.eval(IBox(Interval(1, 4), Interval(0), Interval(0)));
  EXPECT_FALSE(ie.partial_domain());
  const Tape u = Tape::parse("1 / x");
  IntervalEval ue(u);
  // Corners of both signs but a pole between: partial, so no root may be claimed.
  const Interval v = ue.eval(IBox(Interval(-1, 1), Interval(0), Interval(0)));
  EXPECT_TRUE(ue.partial_domain());
  EXPECT_TRUE(v.contains_zero());
}

TEST(Evaluators, ConstantAndVariableRoots) {
  const Tape c = Tape::parse("3"), y = Tape::parse("y");
  EXPECT_EQ(PointEval(c).eval(0, 0, 0), 3);
  EXPECT_EQ(PointEval(y).eval(1, 2, 3), 2);
  // Evaluators keep a pointer to their tape, so they cannot be built from a temporary.
  static_assert(!std::is_constructible_v<PointEval, Tape&&>);
  static_assert(!std::is_constructible_v<IntervalEval, Tape&&>);
}

}  // namespace
}  // namespace iaa
