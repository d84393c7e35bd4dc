// The kernels of core/elementary.h against MPFR: on random and hard arguments, in each of the four
// rounding modes, |v - f(x)| must stay within half the bound the interval rules widen by
// (kRelErr |v| + the absolute term), so that the bound holds with a margin of 2. Then the
// interval rules built on them (sin, cos, sincos, exp, log of interval.h) must contain f at both
// ends and take +-1 exactly where a multiple of pi/2 lies inside. IAA_MPFR_CASES sets the number of
// arguments per kernel and mode (default 25 000: 10^5 per kernel).
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cfenv>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "core/elementary.h"
#include "core/interval.h"

namespace iaa {
namespace {

namespace el = elementary;

long cases() {
  const char* s = std::getenv("IAA_MPFR_CASES");
  return s ? std::max(1L, std::atol(s)) : 25000L;
}

using Fn = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);

/// |v - f(x)| over the allowed bound, computed with 256-bit MPFR (the error of that computation
/// is far below the doubles' ulps).
class Checker {
 public:
  Checker() { mpfr_inits2(256, x_, f_, d_, nullptr); }
  ~Checker() { mpfr_clears(x_, f_, d_, nullptr); }
  Checker(const Checker&) = delete;
  Checker& operator=(const Checker&) = delete;

  /// The error of v = kernel(x) as a fraction of the bound kRelErr |v| + abs.
  double ratio(Fn f, double x, double v, double abs) {
    mpfr_set_d(x_, x, MPFR_RNDN);
    f(f_, x_, MPFR_RNDN);
    mpfr_set_d(d_, v, MPFR_RNDN);
    mpfr_sub(d_, d_, f_, MPFR_RNDN);
    const double err = std::fabs(mpfr_get_d(d_, MPFR_RNDU));
    const double bound = el::kRelErr * std::fabs(v) + abs;
    return err == 0 ? 0.0 : err / bound;  // exact (log 1 = 0 has the bound 0)
  }
  /// True when the double interval [lo, hi] contains f(x).
  bool contains(Fn f, double x, double lo, double hi) {
    mpfr_set_d(x_, x, MPFR_RNDN);
    f(f_, x_, MPFR_RNDN);
    return mpfr_cmp_d(f_, lo) >= 0 && mpfr_cmp_d(f_, hi) <= 0;
  }

 private:
  mpfr_t x_, f_, d_;
};

constexpr int kModes[] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};

/// Random arguments of a kernel: uniform over [-max, max], log-uniform magnitudes from 2^-60 to
/// max with either sign, and `hard` ones given by the caller.
std::vector<double> arguments(std::mt19937_64& rng, double max, const std::vector<double>& hard) {
  std::vector<double> xs = hard;
  std::uniform_real_distribution<double> uni(-max, max), expo(-60.0, std::log2(max));
  const long n = cases();
  while (static_cast<long>(xs.size()) < n) {
    xs.push_back(uni(rng));
    const double m = std::exp2(expo(rng));
    xs.push_back(rng() & 1 ? m : -m);
  }
  xs.resize(static_cast<std::size_t>(std::max<long>(n, static_cast<long>(hard.size()))));
  return xs;
}

/// Doubles nearest to multiples k pi/2 (up to the reduction's limit) and a few ulps around them:
/// where the reduced argument cancels most, and where the quadrant changes.
std::vector<double> near_half_pi_multiples(std::mt19937_64& rng) {
  std::vector<double> xs = {0.0,          -0.0,         0x1p-1074, -0x1p-1022, 0.7853981633974483,
                            el::kTrigMax, -el::kTrigMax};
  mpfr_t t;
  mpfr_init2(t, 256);
  std::uniform_int_distribution<long> kd(-636619, 636619);  // |k pi/2| <= 1e6
  for (int i = 0; i < 2000; ++i) {
    const long k = i < 200 ? i - 100 : kd(rng);
    mpfr_const_pi(t, MPFR_RNDN);
    mpfr_mul_si(t, t, k, MPFR_RNDN);
    mpfr_div_2ui(t, t, 1, MPFR_RNDN);
    double x = mpfr_get_d(t, MPFR_RNDN);
    for (int s = 0; s < 3; ++s) x = std::nextafter(x, -HUGE_VAL);
    for (int s = 0; s < 7; ++s, x = std::nextafter(x, HUGE_VAL)) xs.push_back(x);
  }
  mpfr_clear(t);
  return xs;
}

std::vector<double> exp_hard() {
  std::vector<double> xs = {0.0, -0.0, 0x1p-1074, -0x1p-60, el::kExpMax, -el::kExpMax};
  for (int k = -32686; k <= 32686; k += 37) {
    // Near k ln2/32 and (k + 1/2) ln2/32, where the reduction's k changes.
    for (double h : {0.0, 0.5}) {
      double x = (k + h) * 0.6931471805599453 / 32;
      if (std::fabs(x) > el::kExpMax) continue;
      for (int s = 0; s < 2; ++s) x = std::nextafter(x, -HUGE_VAL);
      for (int s = 0; s < 5; ++s, x = std::nextafter(x, HUGE_VAL)) xs.push_back(x);
    }
  }
  return xs;
}

/// Runs `kernel` on every argument in every rounding mode; returns the largest error ratio.
template <class Kernel>
double worst_ratio(Checker& ck, Fn f, const std::vector<double>& xs, Kernel kernel) {
  double worst = 0;
  for (int mode : kModes) {
    std::fesetround(mode);
    for (double x : xs) {
      double v = 0, abs = 0;
      kernel(x, &v, &abs);
      std::fesetround(FE_TONEAREST);
      const double r = ck.ratio(f, x, v, abs);
      std::fesetround(mode);
      EXPECT_LE(r, 0.5) << "x = " << x << " (" << std::hexfloat << x << std::defaultfloat
                        << "), v = " << v << ", mode " << mode;
      worst = std::max(worst, r);
    }
  }
  std::fesetround(FE_TONEAREST);
  return worst;
}

TEST(ElementaryMpfr, SinAndCosKernelsWithinHalfTheirBound) {
  std::mt19937_64 rng(16);
  Checker ck;
  const std::vector<double> xs = arguments(rng, el::kTrigMax, near_half_pi_multiples(rng));
  const double ws = worst_ratio(ck, mpfr_sin, xs, [](double x, double* v, double* abs) {
    const el::Quadrant q = el::reduce_half_pi(x);
    *v = el::sin_of(q.k, el::sin_poly(q.r), el::cos_poly(q.r));
    *abs = el::trig_abs_err(q);
  });
  const double wc = worst_ratio(ck, mpfr_cos, xs, [](double x, double* v, double* abs) {
    const el::Quadrant q = el::reduce_half_pi(x);
    *v = el::sin_of(q.k + 1, el::sin_poly(q.r), el::cos_poly(q.r));
    *abs = el::trig_abs_err(q);
  });
  std::printf("sin: worst error %.3f of the bound, cos: %.3f (%zu arguments, 4 modes)\n", ws, wc,
              xs.size());
}

std::uint64_t bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}

/// Runs `same(a, b)` on pairs of the arguments (each with another of them) in every rounding
/// mode; fails at the first pair where it is false (a paired kernel against the scalar one).
template <class Same>
void for_pairs_in_every_mode(const std::vector<double>& xs, Same same) {
  for (int mode : kModes) {
    std::fesetround(mode);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double a = xs[i], b = xs[(i * 7 + 1) % xs.size()];
      const bool ok = same(a, b);
      if (!ok) std::fesetround(FE_TONEAREST);
      ASSERT_TRUE(ok) << "x = " << std::hexfloat << a << ", " << b << ", mode " << mode;
    }
  }
  std::fesetround(FE_TONEAREST);
}

/// The interval rules take both ends of an argument through reduce_sin_cos2 (two lanes at once),
/// point sincos takes sin r and cos r from sin_cos_poly (one pass): both must give the scalar
/// kernels' doubles bit for bit, in every rounding mode, so that the bounds proved above hold for
/// them. (IntervalRulesContainTheEndsAndTheExtrema checks that the interval sincos, which runs
/// the ends in lanes, equals sin and cos, which run them one at a time.)
TEST(ElementaryMpfr, PairedTrigKernelIsTheScalarOne) {
  std::mt19937_64 rng(19);
  const std::vector<double> xs = arguments(rng, el::kTrigMax, near_half_pi_multiples(rng));
  for_pairs_in_every_mode(xs, [](double a, double b) {
    el::ReducedTrig ra, rb;
    el::reduce_sin_cos2(a, b, &ra, &rb);
    for (const auto& [x, r] : {std::pair{a, ra}, std::pair{b, rb}}) {
      const el::Quadrant q = el::reduce_half_pi(x);
      const double s = el::sin_poly(q.r), c = el::cos_poly(q.r);
      double s1 = 0, c1 = 0;  // point sincos's one-pass polynomials
      el::sin_cos_poly(q.r, &s1, &c1);
      if (!(q.k == r.q.k && bits(q.r) == bits(r.q.r) && bits(s) == bits(r.s) &&
            bits(c) == bits(r.c) && bits(s) == bits(s1) && bits(c) == bits(c1)))
        return false;
    }
    return true;
  });
}

TEST(ElementaryMpfr, ExpKernelWithinHalfItsBound) {
  std::mt19937_64 rng(17);
  Checker ck;
  const std::vector<double> xs = arguments(rng, el::kExpMax, exp_hard());
  const double w = worst_ratio(ck, mpfr_exp, xs, [](double x, double* v, double* abs) {
    *v = el::exp_kernel(x);
    *abs = 0;
  });
  std::printf("exp: worst error %.3f of the bound (%zu arguments, 4 modes)\n", w, xs.size());
}

/// The interval rule of exp takes both ends through exp_kernel2 (two lanes at once), and the
/// batched evaluators run exp_kernel_lanes over 2 or 4 lanes: the scalar kernel's doubles bit for
/// bit, in every rounding mode, so that the bound proved above holds for them.
TEST(ElementaryMpfr, PairedExpKernelIsTheScalarOne) {
#ifdef IAA_ELEMENTARY_LANES
  std::mt19937_64 rng(23);
  const std::vector<double> xs = arguments(rng, el::kExpMax, exp_hard());
  for_pairs_in_every_mode(xs, [](double a, double b) {
    const el::V2d v = el::exp_kernel2(el::V2d{a, b});
    return bits(v[0]) == bits(el::exp_kernel(a)) && bits(v[1]) == bits(el::exp_kernel(b));
  });
#else
  GTEST_SKIP() << "no vector extension: the interval rule calls the scalar kernel";
#endif
}

TEST(ElementaryMpfr, ExpTableIsRoundedToNearest) {
  mpfr_t t;
  mpfr_init2(t, 256);
  for (int j = 0; j < 32; ++j) {
    mpfr_set_si(t, j, MPFR_RNDN);
    mpfr_div_2ui(t, t, 5, MPFR_RNDN);
    mpfr_exp2(t, t, MPFR_RNDN);
    EXPECT_EQ(el::kExp2Table[j], mpfr_get_d(t, MPFR_RNDN)) << j;
  }
  mpfr_clear(t);
}

/// Arguments of log: the hard ones (1 and its neighbours, the ends of the reduction's cells
/// (2k + 1)/128 and the switch at 1.5 in every binade's mantissa, powers of 2, subnormals, the
/// largest double), then log-uniform magnitudes over every double and uniform ones in [0.5, 2].
std::vector<double> log_arguments(std::mt19937_64& rng) {
  std::vector<double> xs = {1.0, DBL_MIN, DBL_MAX, 0x1p-1074, 0x1.8p-1074, 0x1p-1060, 0.75, 1.5};
  const auto around = [&](double x, int n) {
    for (int s = 0; s < n; ++s) x = std::nextafter(x, 0.0);
    for (int s = 0; s < 2 * n + 1; ++s, x = std::nextafter(x, HUGE_VAL)) {
      if (x > 0) xs.push_back(x);
    }
  };
  around(1.0, 50);
  for (int k = 95; k <= 193; k += 2) around(k / 128.0, 3);  // cell ends, 0.74 .. 1.51
  for (int e = -1074; e <= 1023; e += 7) {
    around(std::ldexp(1.0, e), 2);
    if (e > -1022) around(std::ldexp(1.5, e), 2);
  }
  std::uniform_real_distribution<double> expo(-1074.0, 1024.0), near_one(0.5, 2.0);
  const long n = cases(), hard = static_cast<long>(xs.size());
  while (static_cast<long>(xs.size()) < n) {
    const double m = std::exp2(expo(rng));
    if (m > 0 && m <= DBL_MAX) xs.push_back(m);
    xs.push_back(near_one(rng));
  }
  xs.resize(static_cast<std::size_t>(std::max(n, hard)));
  return xs;
}

TEST(ElementaryMpfr, LogKernelWithinHalfItsBound) {
  std::mt19937_64 rng(19);
  Checker ck;
  const std::vector<double> xs = log_arguments(rng);
  const double w = worst_ratio(ck, mpfr_log, xs, [](double x, double* v, double* abs) {
    *v = el::log_kernel(x);
    *abs = el::log_abs_err(x);
  });
  std::printf("log: worst error %.3f of the bound (%zu arguments, 4 modes)\n", w, xs.size());
  EXPECT_EQ(el::log_kernel(1.0), 0.0);
}

TEST(ElementaryMpfr, LogTableIsDoubleDouble) {
  // hi is log(j/64) rounded to nearest, lo the rest rounded to nearest.
  mpfr_t t;
  mpfr_init2(t, 300);
  for (int j = 48; j <= 96; ++j) {
    mpfr_set_si(t, j, MPFR_RNDN);
    mpfr_div_2ui(t, t, 6, MPFR_RNDN);
    mpfr_log(t, t, MPFR_RNDN);
    const double hi = mpfr_get_d(t, MPFR_RNDN);
    EXPECT_EQ(el::kLogTable[j - 48][0], hi) << j;
    mpfr_sub_d(t, t, hi, MPFR_RNDN);
    EXPECT_EQ(el::kLogTable[j - 48][1], mpfr_get_d(t, MPFR_RNDN)) << j;
  }
  mpfr_clear(t);
}

TEST(ElementaryMpfr, PointValuesAreTheKernels) {
  // Beyond the kernels' ranges the point functions are libm's; NaN stays NaN.
  EXPECT_EQ(el::sin(1e7), std::sin(1e7));
  EXPECT_EQ(el::exp(710.0), std::exp(710.0));
  EXPECT_TRUE(std::isnan(el::sin(NAN)));
  EXPECT_TRUE(std::isnan(el::exp(NAN)));
  EXPECT_EQ(el::log(0.0), -HUGE_VAL);
  EXPECT_EQ(el::log(HUGE_VAL), HUGE_VAL);
  EXPECT_TRUE(std::isnan(el::log(-1.0)));
  EXPECT_TRUE(std::isnan(el::log(NAN)));
  EXPECT_EQ(el::log(2.5), el::log_kernel(2.5));
  double s = 0, c = 0;
  el::sincos(2.5, &s, &c);
  EXPECT_EQ(s, el::sin(2.5));
  EXPECT_EQ(c, el::cos(2.5));
}

/// The interval rules: random intervals (short ones near multiples of pi/2 among them) contain f
/// at both ends and at their multiples of pi/2, where the bound must be exactly +-1.
TEST(ElementaryMpfr, IntervalRulesContainTheEndsAndTheExtrema) {
  std::mt19937_64 rng(18);
  Checker ck;
  const RoundingScope scope;
  const std::vector<double> ends = near_half_pi_multiples(rng);
  std::uniform_real_distribution<double> width(0.0, 3.0);
  std::uniform_int_distribution<std::size_t> pick(0, ends.size() - 1);
  const long n = cases();
  for (long i = 0; i < n; ++i) {
    const double a = ends[pick(rng)];
    const double b = (i & 1) ? ends[pick(rng)] : a + (i & 2 ? width(rng) : 1e-9 * width(rng));
    const Interval x(std::min(a, b), std::max(a, b));
    Interval s, c;
    sincos(x, &s, &c);
    EXPECT_EQ(s, sin(x));
    EXPECT_EQ(c, cos(x));
    for (double e : {x.lo(), x.hi()}) {
      ASSERT_TRUE(ck.contains(mpfr_sin, e, s.lo(), s.hi())) << x.lo() << " " << x.hi();
      ASSERT_TRUE(ck.contains(mpfr_cos, e, c.lo(), c.hi())) << x.lo() << " " << x.hi();
    }
    if (x.mag() > el::kTrigMax || x.width() >= 6.3) continue;
    // Every multiple m pi/2 inside x (decided with MPFR) puts +-1 in the results.
    mpfr_t t;
    mpfr_init2(t, 256);
    const long k0 = static_cast<long>(std::floor(x.lo() / 1.5707963267948966)) - 1;
    for (long m = k0; m <= k0 + 6; ++m) {
      mpfr_const_pi(t, MPFR_RNDN);
      mpfr_mul_si(t, t, m, MPFR_RNDN);
      mpfr_div_2ui(t, t, 1, MPFR_RNDN);
      if (mpfr_cmp_d(t, x.lo()) < 0 || mpfr_cmp_d(t, x.hi()) > 0) continue;
      const long q = ((m % 4) + 4) % 4;
      const double extremum[4] = {c.hi(), s.hi(), -c.lo(), -s.lo()};  // +-1 at q = 0 .. 3
      EXPECT_EQ(extremum[q], 1.0) << "multiple " << m << " of pi/2";
    }
    mpfr_clear(t);
  }
  // exp: both ends inside, over the kernel's range and beyond it (libm there).
  std::uniform_real_distribution<double> ex(-750.0, 750.0);
  for (long i = 0; i < n; ++i) {
    const double a = ex(rng), b = (i & 1) ? ex(rng) : a + 1e-6 * width(rng);
    const Interval x(std::min(a, b), std::max(a, b));
    const Interval e = exp(x);
    for (double v : {x.lo(), x.hi()}) {
      ASSERT_TRUE(ck.contains(mpfr_exp, v, e.lo(), e.hi())) << x.lo() << " " << x.hi();
    }
    EXPECT_GE(e.lo(), 0.0);
  }
  // log: both ends inside, over every binade (subnormals, 1, the largest double included).
  const std::vector<double> lx = log_arguments(rng);
  std::uniform_int_distribution<std::size_t> lpick(0, lx.size() - 1);
  for (long i = 0; i < n; ++i) {
    const double a = lx[lpick(rng)], b = (i & 1) ? lx[lpick(rng)] : a * (1 + 1e-6 * width(rng));
    const Interval x(std::min(a, b), std::max(a, b));
    Domain dom = Domain::kFull;
    const Interval l = log(x, &dom);
    EXPECT_EQ(dom, Domain::kFull);
    for (double v : {x.lo(), x.hi()}) {
      if (v > DBL_MAX) continue;
      ASSERT_TRUE(ck.contains(mpfr_log, v, l.lo(), l.hi())) << x.lo() << " " << x.hi();
    }
  }
  Domain dom = Domain::kFull;
  EXPECT_EQ(log(Interval(1.0), &dom), Interval(0.0));
}

}  // namespace
}  // namespace iaa
