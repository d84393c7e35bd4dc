// BatchIntervalEvalK against IntervalEval: every lane's interval must be the same pair of doubles
// (bit for bit, signs of zeros included) and its partial-domain flag the same, for random
// expressions over every operation, endpoint-heavy boxes (unbounded, empty, degenerate, touching
// or straddling 0), every batch size from 1 to K, with the baseline (SSE2) code and, where the
// processor has it, the AVX2 code. BatchIntervalGradEvalK likewise against IntervalGradEval: the
// value and the three partials, with every set of wanted partials. BatchPointEvalK against
// PointEval: every lane's value the same double (NaN where PointEval gives NaN).
#include <gtest/gtest.h>

#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_batch_point.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/random_expr.h"

namespace iaa {
namespace {

using testing::RandomExpr;

/// A box side that the interval rules treat specially now and then: unbounded, empty, a point,
/// a signed zero, a side ending at 0; otherwise the generator's own sides.
Interval odd_side(RandomExpr& r, const Interval& usual) {
  const double inf = Interval::kInf;
  switch (r.pick(14)) {
    case 0:
      return Interval(-inf, r.uniform(-2, 2));
    case 1:
      return Interval(r.uniform(-2, 2), inf);
    case 2:
      return Interval::whole();
    case 3:
      return Interval::empty();
    case 4:
      return Interval(-0.0, 0.0);
    case 5:
      return Interval(-0.0);
    case 6:
      return Interval(0.0, r.uniform(0, 3));
    case 7:
      return Interval(r.uniform(-3, 0), -0.0);
    case 8:
      return Interval(r.uniform(-3, 3));
    case 9:
      return Interval(1e300, 1e308);
    default:
      return usual;
  }
}

IBox random_box(RandomExpr& r) {
  IBox b = r.box();
  if (r.pick(3) == 0) {
    for (int a = 0; a < 3; ++a) b[a] = odd_side(r, b[a]);
  }
  return b;
}

std::uint64_t bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}

/// The intervals of a result: an interval, or the value and the partials of an IGrad.
std::vector<Interval> parts(const Interval& v) {
  return {v};
}
std::vector<Interval> parts(const IGrad& r) {
  return {r.v, r.g[0], r.g[1], r.g[2]};
}

/// Evaluates `boxes` in one batch of `be` and each box with the scalar evaluator `se`
/// (IntervalEval, IntervalGradEval); reports the first difference.
template <class Batch, class Scalar>
::testing::AssertionResult same_as_scalar(Batch& be, Scalar& se, const std::vector<IBox>& boxes) {
  constexpr int K = Batch::kLanes;
  const int n = static_cast<int>(boxes.size());
  decltype(se.eval(boxes[0])) out[K];
  {
    RoundingScope scope;
    be.eval(boxes.data(), n, out);
  }
  for (int j = 0; j < n; ++j) {
    const auto want = parts(se.eval(boxes[static_cast<std::size_t>(j)]));
    const bool want_partial = se.partial_domain();
    const auto got = parts(out[j]);
    for (std::size_t c = 0; c < want.size(); ++c) {
      if (bits(got[c].lo()) == bits(want[c].lo()) && bits(got[c].hi()) == bits(want[c].hi()) &&
          be.partial_domain(j) == want_partial) {
        continue;
      }
      const IBox& b = boxes[static_cast<std::size_t>(j)];
      const char* what[] = {"value", "d/dx", "d/dy", "d/dz"};
      char msg[512];
      std::snprintf(msg, sizeof msg,
                    "lane %d of %d (K=%d, %s), %s: batch [%a, %a] partial %d, scalar [%a, %a] "
                    "partial %d; box [%a,%a]x[%a,%a]x[%a,%a]",
                    j, n, K, be.isa(), what[c], got[c].lo(), got[c].hi(), int(be.partial_domain(j)),
                    want[c].lo(), want[c].hi(), int(want_partial), b.x.lo(), b.x.hi(), b.y.lo(),
                    b.y.hi(), b.z.lo(), b.z.hi());
      return ::testing::AssertionFailure() << msg << "\n" << be.tape().to_text();
    }
  }
  return ::testing::AssertionSuccess();
}

/// Every batch size 1..K on fresh random boxes, with both instruction sets.
template <class Batch, class Scalar>
::testing::AssertionResult check_batches(Batch& be, Scalar& se, RandomExpr& r, int rounds) {
  for (int baseline = 0; baseline < 2; ++baseline) {
    be.use_baseline(baseline != 0);
    for (int round = 0; round < rounds; ++round) {
      for (int n = 1; n <= Batch::kLanes; ++n) {
        std::vector<IBox> boxes;
        for (int j = 0; j < n; ++j) boxes.push_back(random_box(r));
        auto res = same_as_scalar(be, se, boxes);
        if (!res) return res;
      }
    }
  }
  return ::testing::AssertionSuccess();
}

template <int K>
::testing::AssertionResult check_tape(const Tape& tape, RandomExpr& r, int rounds) {
  BatchIntervalEvalK<K> be(tape);
  IntervalEval ie(tape);
  return check_batches(be, ie, r, rounds);
}

/// The same for the interval + gradient evaluators, with the partials `wanted`.
template <int K>
::testing::AssertionResult check_grad_tape(const Tape& tape, RandomExpr& r, int rounds,
                                           detail::VarMask wanted = detail::kAllVars) {
  BatchIntervalGradEvalK<K> be(tape, wanted);
  IntervalGradEval ie(tape, wanted);
  return check_batches(be, ie, r, rounds) << " (wanted partials " << int(wanted) << ")";
}

// One expression per operation (scale and divc from products and quotients by constants, sincos
// from sin and cos of one argument), and a few whose partials combine several rules.
const char* const kEveryOperation[] = {
    "x + y",
    "x - y",
    "x * y",
    "2.5 * x",
    "x * (-3)",
    "x / y",
    "x / 3",
    "x / (-0.7)",
    "-x",
    "x^0",
    "x^1",
    "x^2",
    "x^3",
    "x^4",
    "x^7",
    "x^8",
    "x^23",
    "square(x)",
    "sqrt(x)",
    "exp(x)",
    "log(x)",
    "sin(x)",
    "cos(x)",
    "sin(x) * cos(x)",
    "tan(x)",
    "atan(x)",
    "abs(x)",
    "min(x, y)",
    "max(x, y)",
    "pow(x, y)",
    "x^0.5",
    "x * x * y - z",
    "1 / x",
    "x^(-2)",
    "x",
    "7",
    "(x*y)^3 - square(y + z) * x",
    "(x + y*z)^0 * z",
    "-(x*y) / 3 + 2 * (y*z)^2",
};

/// Runs `check(tape)` on each of kEveryOperation and checks that they cover every operation of
/// IAA_OPCODES that an instruction can be.
template <class Check>
void check_every_operation(Check check) {
  std::set<Op> seen;
  for (const char* e : kEveryOperation) {
    const Tape tape = Tape::parse(e);
    for (int i = tape.first_op(); i < tape.size(); ++i) seen.insert(tape.instrs()[i].op);
    SCOPED_TRACE(e);
    check(tape);
  }
  for (int op = static_cast<int>(Op::kAdd); op < kOpCount; ++op) {
    EXPECT_TRUE(seen.count(static_cast<Op>(op))) << "not covered: " << info(Op(op)).text;
  }
}

/// Runs `check(tape, r, n)` on random expressions over every operation of the language, n
/// counting them from 1.
template <class Check>
void check_random_expressions(unsigned seed, int count, Check check) {
  const int scale = testing::property_scale();
  RandomExpr r(seed + static_cast<unsigned>(scale));
  int tapes = 0;
  while (tapes < count * scale) {
    const std::string text = r.make(5);
    if (!RandomExpr::parses(text)) continue;
    const Tape tape = Tape::parse(text);
    check(tape, r, ++tapes);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// Each operation on endpoint-heavy boxes.
TEST(BatchIntervalEval, EveryOperationMatchesTheScalarEvaluator) {
  RandomExpr r(16);
  check_every_operation([&](const Tape& tape) {
    EXPECT_TRUE(check_tape<8>(tape, r, 40));
    EXPECT_TRUE(check_tape<4>(tape, r, 10));
  });
}

// Random expressions, every batch size, K = 2, 4, 8, 16.
TEST(BatchIntervalEval, RandomExpressionsMatchTheScalarEvaluator) {
  check_random_expressions(1601u, 300, [](const Tape& tape, RandomExpr& r, int n) {
    ASSERT_TRUE(check_tape<8>(tape, r, 2));
    if (n % 4 == 0) {
      ASSERT_TRUE(check_tape<2>(tape, r, 1));
      ASSERT_TRUE(check_tape<4>(tape, r, 1));
      ASSERT_TRUE(check_tape<16>(tape, r, 1));
    }
  });
}

/// Checks that a batched evaluator opens its own RoundingScope, as the scalar one does.
template <class Batch, class Scalar>
void check_own_rounding_scope() {
  const Tape tape = Tape::parse("x^3 - y * z + 0.1");
  Batch be(tape);
  Scalar se(tape);
  const std::vector<IBox> boxes = {IBox(Interval(0.1, 0.3), Interval(-1, 2), Interval(0.7, 0.71)),
                                   IBox(Interval(-3, -2), Interval(0.5), Interval(-1, 1))};
  decltype(se.eval(boxes[0])) out[2];
  be.eval(boxes.data(), 2, out);  // no RoundingScope here
  for (std::size_t j = 0; j < 2; ++j) {
    const auto got = parts(out[j]), want = parts(se.eval(boxes[j]));
    for (std::size_t c = 0; c < want.size(); ++c) {
      EXPECT_EQ(bits(got[c].lo()), bits(want[c].lo()));
      EXPECT_EQ(bits(got[c].hi()), bits(want[c].hi()));
    }
  }
}

TEST(BatchIntervalEval, OpensItsOwnRoundingScope) {
  check_own_rounding_scope<BatchIntervalEval, IntervalEval>();
}

/// Both interval batches (4 lanes, SSE2 and AVX2) against the scalar evaluators on each
/// expression, over boxes whose sides are taken from `sides` in a fixed shuffle.
void check_sides_in_both_batches(const std::vector<Interval>& sides,
                                 std::initializer_list<const char*> exprs) {
  for (const char* e : exprs) {
    const Tape tape = Tape::parse(e);
    BatchIntervalEvalK<4> be(tape);
    IntervalEval ie(tape);
    BatchIntervalGradEvalK<4> bg(tape);
    IntervalGradEval ig(tape);
    for (int baseline = 0; baseline < 2; ++baseline) {
      be.use_baseline(baseline != 0);
      bg.use_baseline(baseline != 0);
      for (std::size_t i = 0; i + 4 <= sides.size(); i += 4) {
        std::vector<IBox> boxes;
        for (std::size_t j = 0; j < 4; ++j) {
          boxes.push_back(IBox(sides[i + j], sides[(i + 5 * j + 1) % sides.size()],
                               sides[(i + 11 * j + 2) % sides.size()]));
        }
        ASSERT_TRUE(same_as_scalar(be, ie, boxes)) << e;
        ASSERT_TRUE(same_as_scalar(bg, ig, boxes)) << e;
      }
    }
  }
}

// sin and cos run on vectors in both interval batches: the same bounds as the scalar rules for
// boxes that end at, just before or just after the multiples of pi/4 (where an extremum enters
// the range, or a reduction changes quadrant), narrow and wide, and beyond the kernels' range.
TEST(BatchIntervalEval, SinAndCosMatchTheScalarRulesAcrossQuadrants) {
  std::vector<Interval> sides;
  const double widths[] = {0.0, 1e-300, 1e-12, 1e-3, 0.5, 1.6, 3.2, 6.3};
  for (int k = -12; k <= 12; ++k) {
    const double q = k * 0.7853981633974483;
    for (const double at : {q, std::nextafter(q, 1e9), std::nextafter(q, -1e9)}) {
      for (const double w : widths) {
        sides.push_back(Interval(at, at + w));
        sides.push_back(Interval(at - w, at));
      }
    }
  }
  for (const double big : {999999.0, 1e6, 1.0000001e6}) sides.push_back(Interval(big - 1, big));
  check_sides_in_both_batches(sides,
                              {"sin(x)", "cos(x)", "sin(x) * cos(x)", "sin(x) * y - cos(z) * x"});
}

/// Arguments of exp where its rules change: the kernel's range ends (+-708 and the doubles
/// around them, beyond which glibc's exp is used, and overflow near 709.8), the reduction's
/// switches k ln2/32 and (k + 1/2) ln2/32 and an ulp either side, zeros and tiny values.
std::vector<double> exp_arguments() {
  std::vector<double> xs = {0.0,   -0.0,   5e-324, -1e-310, 1e-8,  -0.5,
                            700.0, -745.0, 709.7,  709.8,   -708.5};
  for (const double e : {708.0, -708.0}) {
    xs.insert(xs.end(), {e, std::nextafter(e, 1e9), std::nextafter(e, -1e9)});
  }
  for (int k = -300; k <= 300; k += 7) {
    for (const double h : {0.0, 0.5}) {
      const double x = (k + h) * 0.6931471805599453 / 32;
      xs.insert(xs.end(), {x, std::nextafter(x, 1e9), std::nextafter(x, -1e9)});
    }
  }
  RandomExpr r(23);
  for (int i = 0; i < 100; ++i) xs.push_back(r.uniform(-708, 708));
  return xs;
}

// exp runs on vectors in both interval batches: the same bounds as the scalar rules for boxes
// whose ends fall where its rules change (exp_arguments), narrow and wide, and unbounded.
TEST(BatchIntervalEval, ExpMatchesTheScalarRulesAcrossItsRange) {
  const std::vector<double> xs = exp_arguments();
  std::vector<Interval> sides;
  for (const double x : xs) {
    for (const double w : {0.0, 1e-12, 0.3, 20.0}) sides.push_back(Interval(x, x + w));
  }
  sides.push_back(Interval(-Interval::kInf, 1.0));
  sides.push_back(Interval(1.0, Interval::kInf));
  sides.push_back(Interval::whole());
  sides.push_back(Interval::empty());
  check_sides_in_both_batches(sides, {"exp(x)", "exp(x) * y", "exp(x * y) - exp(-z)"});
}

// --- The interval + gradient evaluator ---

// Each operation, with all partials and with each smaller set.
TEST(BatchIntervalGradEval, EveryOperationMatchesTheScalarEvaluator) {
  RandomExpr r(17);
  check_every_operation([&](const Tape& tape) {
    EXPECT_TRUE(check_grad_tape<8>(tape, r, 20));
    EXPECT_TRUE(check_grad_tape<4>(tape, r, 5));
    for (detail::VarMask w = 0; w < detail::kAllVars; ++w) {
      EXPECT_TRUE(check_grad_tape<8>(tape, r, 3, w));
    }
  });
}

// Random expressions, every batch size, K = 2, 4, 8, 16, all partials and smaller sets.
TEST(BatchIntervalGradEval, RandomExpressionsMatchTheScalarEvaluator) {
  check_random_expressions(1602u, 200, [](const Tape& tape, RandomExpr& r, int n) {
    ASSERT_TRUE(check_grad_tape<8>(tape, r, 2));
    ASSERT_TRUE(check_grad_tape<8>(tape, r, 1, detail::VarMask(1 + n % 6)));
    if (n % 4 == 0) {
      ASSERT_TRUE(check_grad_tape<2>(tape, r, 1));
      ASSERT_TRUE(check_grad_tape<4>(tape, r, 1));
      ASSERT_TRUE(check_grad_tape<16>(tape, r, 1));
    }
  });
}

// Signed zeros: a product of intervals with 0 at an end may give -0 or +0 by the order of its
// products, so the product rule must multiply in IntervalGradRules' order (a' * b, then b' * a).
// Every box of sides ending at a signed zero, in batches of 8, for products whose partials and
// values both end at 0 there.
TEST(BatchIntervalGradEval, SignedZerosMatchTheScalarEvaluator) {
  const Interval sides[] = {Interval::raw(-1, -0.0), Interval::raw(-1, 0.0),
                            Interval::raw(-0.0, 1),  Interval::raw(0.0, 2),
                            Interval::raw(-2, -0.0), Interval::raw(-0.0, 0.0),
                            Interval::raw(0.0, 0.0), Interval::raw(-0.0, -0.0)};
  std::vector<IBox> all;
  for (const Interval& x : sides) {
    for (const Interval& y : sides) {
      for (const Interval& z : sides) all.push_back(IBox(x, y, z));
    }
  }
  for (const char* e :
       {"x * y", "(x * y) * (x * z)", "(x * y) * (y * z) - x^3 * z", "square(x * y)", "(x * y)^3",
        "(x*y - y*z) * (x*z) / 3", "-(x * y) * 2.5 * (x + z)"}) {
    const Tape tape = Tape::parse(e);
    for (detail::VarMask w = 1; w <= detail::kAllVars; ++w) {
      BatchIntervalGradEvalK<8> be(tape, w);
      IntervalGradEval ie(tape, w);
      for (int baseline = 0; baseline < 2; ++baseline) {
        be.use_baseline(baseline != 0);
        for (std::size_t i = 0; i < all.size(); i += 8) {
          const std::vector<IBox> boxes(all.begin() + static_cast<std::ptrdiff_t>(i),
                                        all.begin() + static_cast<std::ptrdiff_t>(i + 8));
          ASSERT_TRUE(same_as_scalar(be, ie, boxes)) << e;
        }
      }
    }
  }
}

TEST(BatchIntervalGradEval, OpensItsOwnRoundingScope) {
  check_own_rounding_scope<BatchIntervalGradEval, IntervalGradEval>();
}

// --- The point evaluator ---

/// A point coordinate that the point rules treat specially now and then: a signed zero, an
/// infinity, a huge or tiny value, NaN; otherwise one taken from the generator's box.
double odd_coordinate(RandomExpr& r, const Interval& side) {
  switch (r.pick(16)) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return Interval::kInf;
    case 3:
      return -Interval::kInf;
    case 4:
      return 1e300;
    case 5:
      return -1e-310;
    case 6:
      return std::numeric_limits<double>::quiet_NaN();
    case 7:
      return std::round(r.uniform(-3, 3));
    default:
      return r.uniform(side.lo(), side.hi());
  }
}

/// Every batch size 1..K, with both instruction sets, in both rounding modes the renderer uses
/// (point values are computed under upward rounding inside a RoundingScope, and to nearest).
template <int K>
::testing::AssertionResult check_point_tape(const Tape& tape, RandomExpr& r, int rounds) {
  BatchPointEvalK<K> be(tape);
  PointEval pe(tape);
  for (int mode = 0; mode < 2; ++mode) {
    std::optional<RoundingScope> upward;
    if (mode == 1) upward.emplace();
    for (int baseline = 0; baseline < 2; ++baseline) {
      be.use_baseline(baseline != 0);
      for (int round = 0; round < rounds; ++round) {
        for (int n = 1; n <= K; ++n) {
          Vec3 p[K];
          for (int j = 0; j < n; ++j) {
            const IBox b = r.box();
            p[j] = {odd_coordinate(r, b.x), odd_coordinate(r, b.y), odd_coordinate(r, b.z)};
          }
          double out[K];
          be.eval(p, n, out);
          for (int j = 0; j < n; ++j) {
            const double want = pe.eval(p[j]);
            if (bits(out[j]) == bits(want) || (out[j] != out[j] && want != want)) continue;
            char msg[256];
            std::snprintf(msg, sizeof msg,
                          "lane %d of %d (K=%d, %s, %s): batch %a, scalar %a at (%a, %a, %a)", j, n,
                          K, be.isa(), mode ? "upward" : "nearest", out[j], want, p[j].x, p[j].y,
                          p[j].z);
            return ::testing::AssertionFailure() << msg << "\n" << tape.to_text();
          }
        }
      }
    }
  }
  return ::testing::AssertionSuccess();
}

// Each operation at endpoint-heavy points.
TEST(BatchPointEval, EveryOperationMatchesTheScalarEvaluator) {
  RandomExpr r(18);
  check_every_operation([&](const Tape& tape) {
    EXPECT_TRUE(check_point_tape<4>(tape, r, 40));
    EXPECT_TRUE(check_point_tape<8>(tape, r, 10));
  });
}

// Random expressions, every batch size, K = 4 and 8.
TEST(BatchPointEval, RandomExpressionsMatchTheScalarEvaluator) {
  check_random_expressions(1603u, 300, [](const Tape& tape, RandomExpr& r, int n) {
    ASSERT_TRUE(check_point_tape<4>(tape, r, 2));
    if (n % 4 == 0) {
      ASSERT_TRUE(check_point_tape<8>(tape, r, 1));
    }
  });
}

/// The point batch (16 lanes, SSE2 and AVX2) against PointEval on each expression, bit for bit,
/// in all four rounding modes, at points whose coordinates are taken from `xs` in a fixed
/// shuffle (z times `z_scale`).
void check_points_in_every_mode(const std::vector<double>& xs,
                                std::initializer_list<const char*> exprs, double z_scale) {
  const int modes[] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  for (const char* e : exprs) {
    const Tape tape = Tape::parse(e);
    BatchPointEvalK<16> be(tape);
    PointEval pe(tape);
    for (int baseline = 0; baseline < 2; ++baseline) {
      be.use_baseline(baseline != 0);
      for (const int mode : modes) {
        const int saved = std::fegetround();
        std::fesetround(mode);
        for (std::size_t i = 0; i + 16 <= xs.size(); i += 16) {
          Vec3 p[16];
          for (std::size_t j = 0; j < 16; ++j) {
            p[j] = {xs[i + j], xs[(i + j * 7) % xs.size()], xs[(i + j * 13) % xs.size()] * z_scale};
          }
          double out[16];
          be.eval(p, 16, out);
          for (std::size_t j = 0; j < 16; ++j) {
            const double want = pe.eval(p[j]);
            EXPECT_EQ(bits(out[j]), bits(want)) << e << " at (" << p[j].x << ", " << p[j].y << ", "
                                                << p[j].z << "), mode " << mode << ", " << be.isa();
          }
        }
        std::fesetround(saved);
      }
    }
  }
}

// sin and cos run elementary.h's kernels on vectors: the same doubles as the scalar kernels at
// arguments across the range (quadrant boundaries k pi/4 and a few ulps around them, large
// multiples near the range's end, tiny and subnormal ones, signed zeros), in all four rounding
// modes, with both instruction sets.
TEST(BatchPointEval, SinAndCosMatchTheScalarKernelsInEveryRoundingMode) {
  std::vector<double> xs = {0.0, -0.0, 5e-324,   -1e-310,   1e-8, 0.5, -0.7853981633974483,
                            1e6, -1e6, 999999.9, 123456.789};
  for (int k = -40; k <= 40; ++k) {
    const double q = k * 0.7853981633974483;
    xs.insert(xs.end(), {q, std::nextafter(q, 1e9), std::nextafter(q, -1e9)});
  }
  RandomExpr r(19);
  for (int i = 0; i < 200; ++i) xs.push_back(r.uniform(-1e6, 1e6));
  for (int i = 0; i < 200; ++i) xs.push_back(r.uniform(-10, 10));
  check_points_in_every_mode(
      xs, {"sin(x)", "cos(x)", "sin(x) * cos(x)", "sin(x) - cos(y) * sin(z)"}, 1.0);
}

// exp runs elementary.h's kernel on vectors where every lane is in its range: the same doubles
// as the scalar kernel (and libm's beyond the range: 709, -745, NaN) in all four rounding modes,
// with both instruction sets.
TEST(BatchPointEval, ExpMatchesTheScalarKernelInEveryRoundingMode) {
  // Most batches have every lane in the kernel's range; those with one of the first arguments
  // (709.7, -745, ...) or NaN take libm's path.
  std::vector<double> xs = exp_arguments();
  xs.push_back(std::numeric_limits<double>::quiet_NaN());
  xs.push_back(-Interval::kInf);
  check_points_in_every_mode(xs, {"exp(x)", "exp(x) * y", "exp(x) - exp(y) * exp(-z)"}, 0.25);
}

}  // namespace
}  // namespace iaa
