// The interval Hessian evaluator (IntervalHessEval) and the centred form of the gradient built on
// it (centred_gradient), which the certified mesher uses to certify cells: hand-derived Hessians
// at points, and a property test over random expressions (every operation, kinks included),
// random boxes and endpoint-heavy sample points: the centred form over a box holds the gradient at
// every sampled point of it, and the Hessian over a box the Hessian at every sampled point.
//
// An exact derivative at a point is known only through enclosures (the evaluators over the point
// as a degenerate box), so "holds" is tested as "meets the point's enclosure": the exact value
// lies in both, so a sound pair of enclosures always meets, and a point's enclosure is a few ulps
// wide, so a bound that misses the exact value by more than that fails.
#include "expr/eval_interval_hess.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "random_expr.h"

namespace iaa {
namespace {

using iaa::testing::for_each_hard_box;
using iaa::testing::property_scale;
using iaa::testing::RandomExpr;

IBox point_box(const Vec3& p) {
  return IBox(Interval(p.x), Interval(p.y), Interval(p.z));
}

std::string describe(const std::string& expr, const IBox& b, const Vec3& p) {
  std::ostringstream os;
  os.precision(17);
  os << "f = " << expr << "\nbox = [" << b.x.lo() << ", " << b.x.hi() << "] x [" << b.y.lo() << ", "
     << b.y.hi() << "] x [" << b.z.lo() << ", " << b.z.hi() << "]\npoint = (" << p.x << ", " << p.y
     << ", " << p.z << ")";
  return os.str();
}

/// `v` within a relative 1e-12 (or 1e-300 absolute) of a point of `i`.
bool near(const Interval& i, double v) {
  const double tol = 1e-12 * std::fabs(v) + 1e-300;
  return !intersect(i, Interval(v - tol, v + tol)).is_empty();
}

TEST(IntervalHessEval, HessiansOfHandDerivedExpressionsAtPoints) {
  // f = x^2 y + sin(z) x + exp(y z) + sqrt(x) / y:
  //   f_xx = 2y - x^(-3/2) / (4y), f_xy = 2x - x^(-1/2) / (2y^2), f_xz = cos z,
  //   f_yy = z^2 exp(yz) + 2 sqrt(x) / y^3, f_yz = (1 + yz) exp(yz), f_zz = y^2 exp(yz) - x sin z.
  const Tape t = Tape::parse("x^2 * y + sin(z) * x + exp(y * z) + sqrt(x) / y");
  IntervalHessEval he(t);
  RoundingScope scope;
  for (const Vec3& p : {Vec3{0.5, 1.5, -0.3}, Vec3{2.0, -0.7, 1.1}, Vec3{1.0, 1.0, 0.0}}) {
    const IHess r = he.eval(point_box(p));
    ASSERT_FALSE(he.partial_domain());
    const double x = p.x, y = p.y, z = p.z, e = std::exp(y * z);
    const double want[6] = {2 * y - std::pow(x, -1.5) / (4 * y),
                            2 * x - 1 / (2 * std::sqrt(x) * y * y),
                            std::cos(z),
                            z * z * e + 2 * std::sqrt(x) / (y * y * y),
                            (1 + y * z) * e,
                            y * y * e - x * std::sin(z)};
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_TRUE(near(r.h[k], want[k]))
          << "entry " << k << " [" << r.h[k].lo() << ", " << r.h[k].hi() << "] wants " << want[k];
    }
    const double grad[3] = {2 * x * y + std::sin(z) + 0.5 / (std::sqrt(x) * y),
                            x * x + z * e - std::sqrt(x) / (y * y), x * std::cos(z) + y * e};
    for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(near(r.g[i], grad[i])) << "partial " << i;
  }
  // Symmetric entries by hess_index, in either order.
  EXPECT_EQ(hess_index(0, 2), hess_index(2, 0));
  EXPECT_EQ(hess_index(1, 2), 4u);
}

TEST(IntervalHessEval, KinksAndPolesLeaveTheHessianUnbounded) {
  RoundingScope scope;
  const IBox across(Interval(-0.5, 0.5), Interval(0.2, 0.3), Interval(0.0));
  for (const char* f : {"abs(x) * y", "max(x, 0) * y^2", "min(x^2, y)"}) {
    SCOPED_TRACE(f);
    const Tape t = Tape::parse(f);
    IntervalHessEval he(t);
    const IHess r = he.eval(across);
    // min(x^2, y) is decided where x^2 < 0.2 everywhere: 0.25 > 0.2 at the ends, so not here.
    EXPECT_FALSE(r.h[0].is_finite());
    const std::array<Interval, 3> c = centred_gradient(
        across, {0, 0.25, 0}, IntervalGradEval(t).eval(point_box({0, 0.25, 0})).g, r.h);
    EXPECT_FALSE(c[0].is_finite());
  }
  // A box that decides the kink has the side's Hessian: abs(x) * y = x y for x > 0.
  const Tape t = Tape::parse("abs(x) * y");
  IntervalHessEval he(t);
  const IHess r = he.eval(IBox(Interval(0.5, 1), Interval(2, 3), Interval(0.0)));
  EXPECT_EQ(r.h[hess_index(0, 1)], Interval(1.0));
  EXPECT_EQ(r.h[hess_index(0, 0)], Interval(0.0));
}

// The reason for the form: on the thin torus of issue 15, in a cell of 0.002 on its tube, the
// natural gradient is mostly overestimation (terms of size 8 cancel to 0.024), and the centred form
// close to the gradient's true range (sampled on a grid of the cell: a lower bound of it).
TEST(IntervalHessEval, CentredFormIsNarrowWhereTheNaturalGradientCancels) {
  const Tape t = Tape::parse("(x^2+y^2+z^2+0.999991)^2 - 4*(x^2+y^2)");
  const IBox b(Interval(1.001, 1.003), Interval(0.0, 0.002), Interval(0.0, 0.0015));
  const Vec3 c{1.002, 0.001, 0.00075};
  PointGradEval pg(t);
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (int i = 0; i <= 8; ++i) {
    for (int j = 0; j <= 8; ++j) {
      for (int k = 0; k <= 8; ++k) {
        const PGrad g = pg.eval({b.x.lo() + i * b.x.width() / 8, b.y.lo() + j * b.y.width() / 8,
                                 b.z.lo() + k * b.z.width() / 8});
        for (std::size_t a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], g.g[a]);
          hi[a] = std::max(hi[a], g.g[a]);
        }
      }
    }
  }
  RoundingScope scope;
  const IGrad natural = IntervalGradEval(t).eval(b);
  const std::array<Interval, 3> centred = centred_gradient(
      b, c, IntervalGradEval(t).eval(point_box(c)).g, IntervalHessEval(t).eval(b).h);
  double wn = 0, wc = 0, sampled = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    wn += natural.g[a].width();
    wc += centred[a].width();
    sampled += hi[a] - lo[a];
  }
  EXPECT_GT(wn, 3 * sampled);
  EXPECT_LT(wc, 1.2 * sampled);
}

void check(const Tape& t, const IBox& box, const std::vector<Vec3>& pts, const std::string& expr) {
  RoundingScope scope;
  IntervalHessEval he(t);
  IntervalGradEval ge(t);
  PointEval pe(t);
  const IHess over = he.eval(box);
  if (he.partial_domain()) return;  // encloses nothing
  Vec3 c;
  for (int a = 0; a < 3; ++a) c[a] = box[a].mid();
  ASSERT_TRUE(box.contains(c));
  const IGrad gc = ge.eval(point_box(c));
  const bool centred_ok = !ge.partial_domain();
  const std::array<Interval, 3> centred = centred_gradient(box, c, gc.g, over.h);
  for (const Vec3& p : pts) {
    const double v = pe.eval(p);
    if (!std::isfinite(v)) continue;
    ASSERT_TRUE(over.v.contains(v)) << describe(expr, box, p);
    const IGrad gp = ge.eval(point_box(p));
    if (ge.partial_domain()) continue;
    const IHess hp = he.eval(point_box(p));
    for (std::size_t i = 0; i < 3; ++i) {
      ASSERT_FALSE(intersect(over.g[i], gp.g[i]).is_empty()) << "partial " << i << "\n"
                                                             << describe(expr, box, p);
      if (centred_ok) {
        ASSERT_FALSE(intersect(centred[i], gp.g[i]).is_empty())
            << "centred partial " << i << " [" << centred[i].lo() << ", " << centred[i].hi()
            << "] misses [" << gp.g[i].lo() << ", " << gp.g[i].hi() << "]\n"
            << describe(expr, box, p);
      }
    }
    if (he.partial_domain()) continue;
    for (std::size_t k = 0; k < 6; ++k) {
      ASSERT_FALSE(intersect(over.h[k], hp.h[k]).is_empty()) << "Hessian entry " << k << "\n"
                                                             << describe(expr, box, p);
    }
  }
}

// 40 000 (expression, box) trials, 6 sample points each, half of them smooth expressions (where
// the Hessian is bounded and the centred form narrow), half over every operation.
TEST(IntervalHessEval, CentredGradientHoldsEveryPointGradient) {
  RandomExpr gen(0x4E55 + 131 * (property_scale() - 1));
  const int kExprs = 2000 * property_scale();
  constexpr int kBoxesPerExpr = 20;
  std::vector<Vec3> pts(6);
  for (int e = 0; e < kExprs; ++e) {
    const std::string expr = gen.make(1 + gen.pick(4), /*smooth=*/e % 2 == 0);
    if (!gen.parses(expr)) continue;
    const Tape t = Tape::parse(expr);
    for (int b = 0; b < kBoxesPerExpr; ++b) {
      const IBox box = gen.box();
      for (Vec3& p : pts) p = gen.point(box);
      check(t, box, pts, expr);
      if (HasFatalFailure()) return;
    }
  }
}

// Every operation on its own over the hard boxes (random_expr.h): near 0, poles and domain edges,
// tiny widths, huge ends.
TEST(IntervalHessEval, EachOperationOnHardBoxes) {
  const char* kExprs[] = {"x * y",         "x / y",       "x^3 * y",         "x^7",
                          "square(x) * y", "sqrt(x) * y", "exp(x * y)",      "log(x) * y",
                          "sin(x * y)",    "cos(x) * y",  "sin(x) * cos(x)", "tan(x) * y",
                          "atan(x * y)",   "abs(x) * y",  "min(x, y) * x",   "max(x * y, x)",
                          "pow(x, y)",     "pow(x, 2.5)", "x / (x - y)",     "3 * x * y / 7"};
  RandomExpr gen(11);
  std::vector<Vec3> pts(8);
  for (const char* expr : kExprs) {
    const Tape t = Tape::parse(expr);
    for_each_hard_box([&](const IBox& box) {
      if (HasFatalFailure()) return;
      for (Vec3& p : pts) p = gen.point(box);
      check(t, box, pts, expr);
    });
    if (HasFatalFailure()) return;
  }
}

}  // namespace
}  // namespace iaa
