// Containment property test, one typed suite run against every evaluator (docs/design.md, "How the
// guarantees are tested"): random expressions over every operation, random boxes, endpoint-heavy
// sample points. For each (expression, box) trial every point value must lie in the interval value
// over the box, and every point gradient in the interval gradient. Points where f is undefined
// (non-finite point value) are skipped: they are not points of any surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "random_expr.h"

namespace iaa {
namespace {

using iaa::testing::for_each_hard_box;
using iaa::testing::property_scale;
using iaa::testing::RandomExpr;

std::string describe(const std::string& expr, const IBox& b, const Vec3& p) {
  std::ostringstream os;
  os.precision(17);
  os << "f = " << expr << "\nbox = [" << b.x.lo() << ", " << b.x.hi() << "] x [" << b.y.lo() << ", "
     << b.y.hi() << "] x [" << b.z.lo() << ", " << b.z.hi() << "]\npoint = (" << p.x << ", " << p.y
     << ", " << p.z << ")\nreproduce: iaa eval '" << expr << "' --box " << b.x.lo() << ":"
     << b.x.hi() << "," << b.y.lo() << ":" << b.y.hi() << "," << b.z.lo() << ":" << b.z.hi()
     << " --at " << p.x << "," << p.y << "," << p.z;
  return os.str();
}

// Each mode checks its own evaluator against the others on one trial.
struct PointMode {
  static constexpr const char* kName = "point";
  // Point values lie in the interval over the box and in the interval over the point itself.
  static void check(const Tape& t, const IBox& box, const std::vector<Vec3>& pts,
                    const std::string& expr) {
    PointEval pe(t);
    IntervalEval ie(t);
    const Interval over_box = ie.eval(box);
    for (const Vec3& p : pts) {
      const double v = pe.eval(p);
      if (!std::isfinite(v)) continue;
      ASSERT_TRUE(over_box.contains(v))
          << v << " not in [" << over_box.lo() << ", " << over_box.hi() << "]\n"
          << describe(expr, box, p);
      const Interval at_point = ie.eval(IBox(Interval(p.x), Interval(p.y), Interval(p.z)));
      ASSERT_TRUE(at_point.contains(v)) << describe(expr, box, p);
    }
  }
};

struct IntervalMode {
  static constexpr const char* kName = "interval";
  // The interval over the box holds the interval over every sub-box around a sample (isotone),
  // and the point value there.
  static void check(const Tape& t, const IBox& box, const std::vector<Vec3>& pts,
                    const std::string& expr) {
    PointEval pe(t);
    IntervalEval ie(t);
    const Interval over_box = ie.eval(box);
    for (const Vec3& p : pts) {
      IBox sub;
      for (int i = 0; i < 3; ++i)
        sub[i] = intersect(box[i], Interval(p[i]) + Interval(-1e-3, 1e-3));
      const Interval over_sub = ie.eval(sub);
      const double v = pe.eval(p);
      if (std::isfinite(v)) {
        ASSERT_TRUE(over_sub.contains(v)) << describe(expr, box, p);
      }
      if (!over_sub.is_empty() && over_sub.is_finite()) {
        ASSERT_TRUE(over_box.contains(over_sub)) << describe(expr, box, p);
      }
    }
  }
};

struct PointGradMode {
  static constexpr const char* kName = "point+gradient";
  // Values equal the point evaluator's; gradients lie in the interval gradient over the box.
  static void check(const Tape& t, const IBox& box, const std::vector<Vec3>& pts,
                    const std::string& expr) {
    PointEval pe(t);
    PointGradEval pg(t);
    IntervalGradEval ig(t);
    const IGrad over_box = ig.eval(box);
    for (const Vec3& p : pts) {
      const PGrad g = pg.eval(p);
      const double v = pe.eval(p);
      if (!std::isfinite(v)) continue;
      ASSERT_EQ(g.v, v) << describe(expr, box, p);
      ASSERT_TRUE(over_box.v.contains(g.v)) << describe(expr, box, p);
      for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(g.g[i])) continue;
        ASSERT_TRUE(over_box.g[static_cast<std::size_t>(i)].contains(g.g[i]))
            << "d/d"
            << "xyz"[i] << " = " << g.g[i] << " not in ["
            << over_box.g[static_cast<std::size_t>(i)].lo() << ", "
            << over_box.g[static_cast<std::size_t>(i)].hi() << "]\n"
            << describe(expr, box, p);
      }
    }
  }
};

struct IntervalGradMode {
  static constexpr const char* kName = "interval+gradient";
  // Its value part encloses the point values and agrees with the interval evaluator's range.
  static void check(const Tape& t, const IBox& box, const std::vector<Vec3>& pts,
                    const std::string& expr) {
    PointEval pe(t);
    IntervalGradEval ig(t);
    const IGrad over_box = ig.eval(box);
    for (const Vec3& p : pts) {
      const double v = pe.eval(p);
      if (!std::isfinite(v)) continue;
      ASSERT_TRUE(over_box.v.contains(v)) << describe(expr, box, p);
      // The gradient over the degenerate box at p encloses the point gradient too.
      const IGrad at_p = ig.eval(IBox(Interval(p.x), Interval(p.y), Interval(p.z)));
      PointGradEval pg(t);
      const PGrad g = pg.eval(p);
      for (int i = 0; i < 3; ++i) {
        if (std::isfinite(g.g[i])) {
          ASSERT_TRUE(at_p.g[static_cast<std::size_t>(i)].contains(g.g[i]))
              << describe(expr, box, p);
        }
      }
    }
  }
};

template <class Mode>
class Containment : public ::testing::Test {};

using Modes = ::testing::Types<PointMode, IntervalMode, PointGradMode, IntervalGradMode>;
TYPED_TEST_SUITE(Containment, Modes);

// 100 000 (expression, box) trials per evaluator, 6 sample points each.
TYPED_TEST(Containment, PointValuesLieInIntervalValues) {
  RandomExpr gen(0xC0FFEE + std::hash<std::string>{}(TypeParam::kName) +
                 977 * (property_scale() - 1));
  const int kExprs = 5000 * property_scale();
  constexpr int kBoxesPerExpr = 20;
  std::vector<Vec3> pts(6);
  for (int e = 0; e < kExprs; ++e) {
    const std::string expr = gen.make(1 + gen.pick(4));
    if (!gen.parses(expr)) continue;  // e.g. pow(x, 1000): an integer power above the limit
    const Tape t = Tape::parse(expr);
    for (int b = 0; b < kBoxesPerExpr; ++b) {
      const IBox box = gen.box();
      for (Vec3& p : pts) p = gen.point(box);
      TypeParam::check(t, box, pts, expr);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

// Every operation on its own over hand-picked hard boxes (poles, domain edges, zero widths).
TYPED_TEST(Containment, EachOperationOnHardBoxes) {
  const char* kExprs[] = {"x + y", "x - y", "x * y", "x / y", "-x", "x^3", "x^4", "x^(-3)",
                          "pow(x, y)", "pow(x, 2.5)", "square(x)", "sqrt(x)", "exp(x)", "log(x)",
                          "sin(x)", "cos(x)", "tan(x)", "atan(x)", "abs(x)", "min(x, y)",
                          "max(x, y)", "x / (x - y)", "sqrt(x*x - 1)", "log(abs(x) - 0.5)",
                          // Integer powers by repeated squaring, the scale and divide-by-constant
                          // fast paths, and sin/cos sharing one sincos in the gradient modes.
                          "x^5", "x^6", "x^7", "x^8", "(x - 0.5)^6", "(y - x)^7", "3 * x",
                          "x * (-0.1)", "x / 3", "x / (-7.25)", "sin(x) * cos(x)", "cos(3 * x)"};
  RandomExpr gen(7);
  std::vector<Vec3> pts(8);
  for (const char* expr : kExprs) {
    const Tape t = Tape::parse(expr);
    for_each_hard_box([&](const IBox& box) {
      if (::testing::Test::HasFatalFailure()) return;
      for (Vec3& p : pts) p = gen.point(box);
      TypeParam::check(t, box, pts, expr);
    });
    if (::testing::Test::HasFatalFailure()) return;
  }
}

}  // namespace
}  // namespace iaa
