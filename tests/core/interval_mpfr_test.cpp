// The interval rules of sin, cos, tan, atan, exp, log, sqrt and the powers, checked against MPFR.
// For each argument interval X the rule's result must contain the true range f(X): the values at
// the ends of X, rounded outward to doubles by MPFR (which rounds correctly), and the extrema,
// poles and domain edges that lie inside X, decided exactly with MPFR at high precision. Only
// the public functions of core/interval.h are called, so any implementation of them is held to
// the same standard. Arguments are random (every binade, either sign) and hard: near multiples
// of pi/2 up to and beyond the 1e6 limit of the trigonometric rules, subnormals, the overflow and
// underflow edges of exp and pow, zero crossings, huge and tiny powers, negative bases of integer
// powers. IAA_MPFR_CASES sets the number of cases, split over the rules (default 100 000;
// tools/soak.sh runs 10^7 with other seeds).
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "core/interval.h"

namespace iaa {
namespace {

constexpr double kInf = Interval::kInf;

/// Number of cases of one rule: IAA_MPFR_CASES (default 10^5) shared by the 11 rules.
long cases_per_rule() {
  const char* s = std::getenv("IAA_MPFR_CASES");
  const long total = s ? std::max(11L, std::atol(s)) : 100000L;
  return total / 11;
}

/// Reals from lo to hi as doubles; lo > hi is the empty range.
struct Range {
  double lo = kInf, hi = -kInf;
  bool empty() const { return lo > hi; }
  void add(const Range& o) {
    lo = std::min(lo, o.lo);
    hi = std::max(hi, o.hi);
  }
};

using Fn1 = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);

/// The MPFR side: correctly rounded values and exact decisions about critical points.
class Mp {
 public:
  Mp() {
    mpfr_inits2(53, r_, nullptr);
    mpfr_inits2(64, a_, b_, nullptr);
    mpfr_inits2(kWide, pi_half_, t_, u_, nullptr);
    mpfr_const_pi(pi_half_, MPFR_RNDN);
    mpfr_div_2ui(pi_half_, pi_half_, 1, MPFR_RNDN);
  }
  ~Mp() { mpfr_clears(r_, a_, b_, pi_half_, t_, u_, nullptr); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;

  /// [RD f(x), RU f(x)]. Rounding to 53 bits and then to a double (subnormal or not) in the same
  /// direction is one directed rounding: the doubles are a subset of the 53-bit numbers.
  Range f1(Fn1 f, double x) {
    mpfr_set_d(a_, x, MPFR_RNDN);  // exact
    return both([&](mpfr_rnd_t rnd) { f(r_, a_, rnd); });
  }
  /// [RD x^y, RU x^y] with IEEE's special values (0^-1 = inf, 0^0 = 1).
  Range pow(double x, double y) {
    mpfr_set_d(a_, x, MPFR_RNDN);
    mpfr_set_d(b_, y, MPFR_RNDN);
    return both([&](mpfr_rnd_t rnd) { mpfr_pow(r_, a_, b_, rnd); });
  }
  /// [RD x^n, RU x^n].
  Range pow_int(double x, unsigned long n) {
    mpfr_set_d(a_, x, MPFR_RNDN);
    return both([&](mpfr_rnd_t rnd) { mpfr_pow_ui(r_, a_, n, rnd); });
  }
  /// True when some point (offset + period k) pi/2, k an integer, lies in [lo, hi]. An
  /// unbounded end holds them all. t = (x / (pi/2) - offset) / period is computed with 1200
  /// bits: a double below 2^1024 is at least ~2^-62 from every multiple of pi/2 other than 0
  /// (and exactly at 0 only when it is 0), far above the error.
  bool hits(double lo, double hi, int offset, int period) {
    if (!std::isfinite(lo) || !std::isfinite(hi)) return true;
    position(lo, offset, period, t_);
    mpfr_ceil(t_, t_);
    position(hi, offset, period, u_);
    mpfr_floor(u_, u_);
    return mpfr_cmp(t_, u_) <= 0;
  }

  /// The double nearest to k pi/2.
  double multiple_of_half_pi(long k) {
    mpfr_mul_si(t_, pi_half_, k, MPFR_RNDN);
    return mpfr_get_d(t_, MPFR_RNDN);
  }

 private:
  static constexpr mpfr_prec_t kWide = 1200;

  template <class F>
  Range both(F&& f) {
    Range out;
    f(MPFR_RNDD);
    out.lo = mpfr_get_d(r_, MPFR_RNDD);
    f(MPFR_RNDU);
    out.hi = mpfr_get_d(r_, MPFR_RNDU);
    return out;
  }
  void position(double x, int offset, int period, mpfr_ptr out) {
    mpfr_set_d(out, x, MPFR_RNDN);
    mpfr_div(out, out, pi_half_, MPFR_RNDN);
    mpfr_sub_si(out, out, offset, MPFR_RNDN);
    mpfr_div_si(out, out, period, MPFR_RNDN);
  }

  mpfr_t r_, a_, b_, pi_half_, t_, u_;
};

/// Random and hard arguments.
class Args {
 public:
  explicit Args(const std::string& rule)
      : rng_(std::hash<std::string>{}(rule) + 7919 * static_cast<std::uint64_t>(cases_per_rule())) {
  }

  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  long integer(long lo, long hi) { return std::uniform_int_distribution<long>(lo, hi)(rng_); }
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  /// Any finite double, every binade (subnormals included) equally likely, either sign.
  double any() {
    const std::uint64_t exponent = std::uniform_int_distribution<std::uint64_t>(0, 2046)(rng_);
    const std::uint64_t mantissa = rng_() & ((std::uint64_t{1} << 52) - 1);
    const double v = std::bit_cast<double>(exponent << 52 | mantissa);
    return pick(2) ? v : -v;
  }
  /// A positive double with a binary exponent in [lo, hi].
  double binade(int lo, int hi) {
    return std::ldexp(uniform(1.0, 2.0), std::uniform_int_distribution<int>(lo, hi)(rng_));
  }
  /// v moved by k ulps (k < 0: down).
  static double ulps(double v, int k) {
    for (; k > 0; --k) v = std::nextafter(v, kInf);
    for (; k < 0; ++k) v = std::nextafter(v, -kInf);
    return v;
  }
  /// An interval at or near c: the point, a few ulps either side, or a width from 1e-300 to 8
  /// (absolute or relative to c) on one or both sides.
  Interval around(double c) {
    static const double kWidths[] = {1e-300, 1e-30, 1e-15, 1e-9, 1e-6, 1e-3, 0.1,
                                     0.5,    1.0,   1.5,   3.0,  3.2,  6.3,  8.0};
    const double w = kWidths[pick(14)];
    switch (pick(6)) {
      case 0:
        return Interval(c);
      case 1:
        return Interval(ulps(c, -pick(17)), ulps(c, pick(17)));
      case 2:
        return span(c, c + w);
      case 3:
        return span(c - w, c);
      case 4:
        return span(c - w / 2, c + w / 2);
      default: {
        const double r = std::fabs(c) * std::ldexp(1.0, -pick(53));
        return span(c - r, c + r);
      }
    }
  }
  /// [min(a, b), max(a, b)].
  static Interval span(double a, double b) { return Interval(std::min(a, b), std::max(a, b)); }

 private:
  std::mt19937_64 rng_;
};

std::string show(const Interval& x) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%a, %a]", x.lo(), x.hi());
  return buf;
}

/// The arguments of a rule as text: "(x)", "(x, y)" or "(x, n)" (one snprintf: GCC 12 warns
/// wrongly about chains of std::string operator+).
std::string call(const Interval& x, const Interval* y = nullptr, int n = -1) {
  char buf[256];
  if (y) {
    std::snprintf(buf, sizeof buf, "([%a, %a], [%a, %a])", x.lo(), x.hi(), y->lo(), y->hi());
  } else if (n >= 0) {
    std::snprintf(buf, sizeof buf, "([%a, %a], %d)", x.lo(), x.hi(), n);
  } else {
    std::snprintf(buf, sizeof buf, "([%a, %a])", x.lo(), x.hi());
  }
  return buf;
}

/// Passes when `got` contains `want` (is empty when `want` is), and a partial domain was
/// reported when `partial_needed`.
::testing::AssertionResult encloses(const Interval& got, const Range& want, bool partial_needed,
                                    Domain dom) {
  const bool ok =
      want.empty() ? got.is_empty() : !got.is_empty() && got.lo() <= want.lo && want.hi <= got.hi();
  if (ok && (!partial_needed || dom == Domain::kPartial)) return ::testing::AssertionSuccess();
  char buf[160];
  std::snprintf(buf, sizeof buf, "true range [%a, %a]%s", want.lo, want.hi,
                partial_needed && dom != Domain::kPartial ? ", partial domain not reported" : "");
  return ::testing::AssertionFailure() << "result " << show(got) << ", " << buf;
}

/// Runs `cases` checks of one rule; `one` draws an argument, checks it and returns the check.
template <class F>
void run_rule(const char* rule, F one) {
  Args args(rule);
  Mp mp;
  const long n = cases_per_rule();
  for (long i = 0; i < n; ++i) {
    std::string what;
    const ::testing::AssertionResult r = one(args, mp, &what);
    ASSERT_TRUE(r) << rule << what << " (case " << i << " of " << n << ")";
  }
}

/// The value of a rule on its arguments, computed in upward rounding as the evaluators do.
template <class F>
Interval upward(F&& f) {
  const RoundingScope scope;
  return f();
}

// --- sin, cos, tan ---------------------------------------------------------------------------

/// A trigonometric argument: near a multiple of pi/2 (up to the 1e6 limit mostly, sometimes far
/// beyond), uniform, small, subnormal, anywhere, or unbounded.
Interval trig_arg(Args& a, Mp& mp) {
  switch (a.pick(8)) {
    case 0:
    case 1:
    case 2: {
      const long limit = a.pick(4) == 0 ? 8 : (a.pick(8) == 0 ? 1L << 40 : 636620);
      const double c = mp.multiple_of_half_pi(a.integer(-limit, limit));
      return a.around(Args::ulps(c, a.pick(9) - 4));
    }
    case 3:
      return a.around(a.uniform(-1e6, 1e6));
    case 4:
      return a.around(a.uniform(-10, 10));
    case 5:
      return a.around(a.pick(2) ? a.binade(-1074, -1) : -a.binade(-1074, -1));
    case 6:
      return a.pick(16) == 0 ? Interval(a.uniform(-5, 5), kInf) : a.around(a.any());
    default:
      return Args::span(a.uniform(-1e6, 1e6), a.uniform(-1e6, 1e6));
  }
}

/// The true range of sin (max_at 1) or cos (max_at 0) over x: the values at the ends, 1 where a
/// maximum (max_at + 4k) pi/2 lies inside, -1 where a minimum (max_at + 2 + 4k) pi/2 does.
Range sin_cos_range(Mp& mp, const Interval& x, Fn1 f, int max_at) {
  if (!x.is_finite()) return {-1, 1};
  Range r = mp.f1(f, x.lo());
  r.add(mp.f1(f, x.hi()));
  if (mp.hits(x.lo(), x.hi(), max_at, 4)) r.hi = 1;
  if (mp.hits(x.lo(), x.hi(), max_at + 2, 4)) r.lo = -1;
  return r;
}

TEST(IntervalMpfr, Sin) {
  run_rule("sin", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = trig_arg(a, mp);
    *what = call(x);
    return encloses(upward([&] { return sin(x); }), sin_cos_range(mp, x, mpfr_sin, 1), false,
                    Domain::kFull);
  });
}

TEST(IntervalMpfr, Cos) {
  run_rule("cos", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = trig_arg(a, mp);
    *what = call(x);
    return encloses(upward([&] { return cos(x); }), sin_cos_range(mp, x, mpfr_cos, 0), false,
                    Domain::kFull);
  });
}

TEST(IntervalMpfr, SinCosTogether) {
  run_rule("sincos", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = trig_arg(a, mp);
    Interval s, c;
    upward([&] {
      sincos(x, &s, &c);
      return s;
    });
    *what = call(x) + " sin";
    const auto sr = encloses(s, sin_cos_range(mp, x, mpfr_sin, 1), false, Domain::kFull);
    if (!sr) return sr;
    *what = call(x) + " cos";
    return encloses(c, sin_cos_range(mp, x, mpfr_cos, 0), false, Domain::kFull);
  });
}

TEST(IntervalMpfr, Tan) {
  run_rule("tan", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = trig_arg(a, mp);
    *what = call(x);
    // Increasing between the poles (1 + 2k) pi/2; a pole inside makes the range the whole line.
    const bool pole = mp.hits(x.lo(), x.hi(), 1, 2);
    Range want{-kInf, kInf};
    if (!pole) {
      want = mp.f1(mpfr_tan, x.lo());
      want.add(mp.f1(mpfr_tan, x.hi()));
    }
    Domain dom = Domain::kFull;
    const Interval got = upward([&] { return tan(x, &dom); });
    return encloses(got, want, pole, dom);
  });
}

// --- atan, exp, log, sqrt ------------------------------------------------------------------

/// [f(lo), f(hi)] for an increasing f, with MPFR's values at infinite ends.
Range increasing_range(Mp& mp, Fn1 f, double lo, double hi) {
  Range r = mp.f1(f, lo);
  r.hi = mp.f1(f, hi).hi;
  return r;
}

TEST(IntervalMpfr, Atan) {
  run_rule("atan", [](Args& a, Mp& mp, std::string* what) {
    Interval x;
    switch (a.pick(5)) {
      case 0:
        x = a.around(a.pick(2) ? a.binade(-1074, -20) : -a.binade(-1074, -20));
        break;
      case 1:
        x = a.around(a.pick(2) ? a.binade(20, 1023) : -a.binade(20, 1023));
        break;
      case 2:
        x = a.pick(2) ? Interval(a.uniform(-4, 4), kInf) : Interval(-kInf, a.uniform(-4, 4));
        break;
      case 3:
        x = a.around(a.uniform(-4, 4));
        break;
      default:
        x = a.around(a.any());
    }
    *what = call(x);
    return encloses(upward([&] { return atan(x); }),
                    increasing_range(mp, mpfr_atan, x.lo(), x.hi()), false, Domain::kFull);
  });
}

TEST(IntervalMpfr, Exp) {
  Mp edges_mp;
  // Where exp overflows, leaves the normal range, reaches the least subnormal, rounds to 0.
  const double edges[] = {edges_mp.f1(mpfr_log, DBL_MAX).lo, edges_mp.f1(mpfr_log, DBL_MIN).lo,
                          edges_mp.f1(mpfr_log, std::numeric_limits<double>::denorm_min()).lo,
                          -745.13321910194122};
  run_rule("exp", [&](Args& a, Mp& mp, std::string* what) {
    Interval x;
    switch (a.pick(6)) {
      case 0:
      case 1:
        x = a.around(Args::ulps(edges[a.pick(4)], a.pick(129) - 64));
        break;
      case 2:
        x = a.around(a.uniform(-750, 750));
        break;
      case 3:
        x = a.around(a.pick(2) ? a.binade(-1074, -1) : -a.binade(-1074, -1));
        break;
      case 4:
        x = a.pick(8) == 0 ? Interval(-kInf, a.uniform(-800, 800)) : a.around(a.any());
        break;
      default:
        x = a.around(a.uniform(-1, 1));
    }
    *what = call(x);
    return encloses(upward([&] { return exp(x); }), increasing_range(mp, mpfr_exp, x.lo(), x.hi()),
                    false, Domain::kFull);
  });
}

TEST(IntervalMpfr, Log) {
  run_rule("log", [](Args& a, Mp& mp, std::string* what) {
    Interval x;
    switch (a.pick(6)) {
      case 0:
        x = a.around(Args::ulps(1.0, a.pick(65) - 32));
        break;
      case 1:
        x = a.around(1.0 + (a.pick(2) ? 1 : -1) * std::ldexp(1.0, -a.pick(54)));
        break;
      case 2:
        x = a.around(a.binade(-1074, -1000));
        break;
      case 3:  // reaching 0 or below: clamped, partial
        x = Interval(a.pick(4) == 0 ? 0.0 : -a.binade(-1074, 3), a.binade(-1074, 10));
        break;
      case 4:
        x = a.around(-a.binade(-20, 20));
        break;
      default:
        x = a.around(std::fabs(a.any()));
    }
    *what = call(x);
    Range want;  // empty where x <= 0
    if (x.hi() > 0) want = increasing_range(mp, mpfr_log, std::max(x.lo(), 0.0), x.hi());
    Domain dom = Domain::kFull;
    const Interval got = upward([&] { return log(x, &dom); });
    return encloses(got, want, x.lo() <= 0, dom);
  });
}

TEST(IntervalMpfr, Sqrt) {
  run_rule("sqrt", [](Args& a, Mp& mp, std::string* what) {
    Interval x;
    switch (a.pick(4)) {
      case 0:
        x = a.around(a.binade(-1074, -1000));
        break;
      case 1:
        x = Interval(-a.binade(-1074, 3), a.binade(-1074, 10));
        break;
      case 2:
        x = a.around(-a.binade(-20, 20));
        break;
      default:
        x = a.around(std::fabs(a.any()));
    }
    *what = call(x);
    Range want;  // empty where x < 0
    if (x.hi() >= 0) want = increasing_range(mp, mpfr_sqrt, std::max(x.lo(), 0.0), x.hi());
    Domain dom = Domain::kFull;
    const Interval got = upward([&] { return sqrt(x, &dom); });
    return encloses(got, want, x.lo() < 0, dom);
  });
}

// --- powers ----------------------------------------------------------------------------------

/// A base of a real power: any positive double, near 1, near 0, reaching below 0, negative.
Interval pow_base(Args& a) {
  switch (a.pick(7)) {
    case 0:
      return a.around(Args::ulps(1.0, a.pick(65) - 32));
    case 1:
      return a.around(1.0 + (a.pick(2) ? 1 : -1) * std::ldexp(1.0, -a.pick(54)));
    case 2:
      return Interval(0.0, a.pick(2) ? a.binade(-1074, 4) : 0.0);
    case 3:
      return Interval(-a.binade(-30, 3), a.binade(-1074, 4));
    case 4:
      return a.pick(8) == 0 ? a.around(-a.binade(-4, 4)) : a.around(a.binade(-4, 4));
    default:
      return a.around(std::fabs(a.any()));
  }
}

/// An exponent: small integers and halves, tiny, huge, anywhere; or, for the base c, one that
/// takes c^y near the overflow or the underflow edge.
Interval pow_exponent(Args& a, double c) {
  switch (a.pick(6)) {
    case 0:
      return a.around(0.5 * static_cast<double>(a.integer(-8, 8)));
    case 1:
      return a.around(a.pick(2) ? a.binade(-1074, -1) : -a.binade(-1074, -1));
    case 2:
      return a.around(a.pick(2) ? a.binade(10, 1023) : -a.binade(10, 1023));
    case 3:
      if (c > 0 && c != 1 && std::isfinite(c)) {
        const double edge = a.pick(2) ? 709.782712893384 : -744.44007192138126;
        return a.around(Args::ulps(edge / std::log(c), a.pick(33) - 16));
      }
      return a.around(a.uniform(-3, 3));
    case 4:
      return a.around(a.uniform(-40, 40));
    default:
      return a.around(a.any());
  }
}

/// The true range of x^y (y real) over x >= 0 (x = 0 only where y > 0): monotone in each
/// argument, so the extremes lie at the corners of the box x clamped to [0, inf); 0^y for
/// y <= 0 stands for the limit (inf, or 1 at y = 0), which x^y takes or exceeds near 0.
Range pow_range(Mp& mp, const Interval& x, const Interval& y) {
  Range r;
  if (x.hi() < 0 || (x.hi() == 0 && y.hi() <= 0)) return r;
  if (x.hi() == 0) return {0, 0};
  for (const double xv : {std::max(x.lo(), 0.0), x.hi()}) {
    for (const double yv : {y.lo(), y.hi()}) r.add(mp.pow(xv, yv));
  }
  return r;
}

TEST(IntervalMpfr, PowReal) {
  run_rule("pow", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = pow_base(a);
    const Interval y = pow_exponent(a, x.hi());
    *what = call(x, &y);
    Domain dom = Domain::kFull;
    const Interval got = upward([&] { return pow_real(x, y, &dom); });
    const bool partial = x.lo() < 0 || (x.lo() <= 0 && y.lo() <= 0);
    return encloses(got, pow_range(mp, x, y), partial, dom);
  });
}

/// The true range of x^n: the values at the ends, and 0 for an even power of an x around 0.
Range pow_int_range(Mp& mp, const Interval& x, int n) {
  Range r = mp.pow_int(x.lo(), static_cast<unsigned long>(n));
  r.add(mp.pow_int(x.hi(), static_cast<unsigned long>(n)));
  if (n > 0 && n % 2 == 0 && x.lo() < 0 && 0 < x.hi()) r.lo = 0;
  return r;
}

/// A base of an integer power: anywhere, moderate, near +-1, around 0, huge or tiny.
Interval int_base(Args& a) {
  const double s = a.pick(2) ? 1.0 : -1.0;
  switch (a.pick(6)) {
    case 0:
      return a.around(s * Args::ulps(1.0, a.pick(65) - 32));
    case 1:
      return Args::span(-a.binade(-40, 4), a.binade(-40, 4));
    case 2:
      return a.around(s * a.binade(100, 1023));
    case 3:
      return a.around(s * a.binade(-1074, -100));
    case 4:
      return a.around(a.uniform(-10, 10));
    default:
      return a.around(a.any());
  }
}

TEST(IntervalMpfr, PowInt) {
  run_rule("pow_int", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = int_base(a);
    const int n = a.pick(3) ? a.pick(9) : (a.pick(8) ? a.pick(257) : a.pick(1 << 20));
    *what = call(x, nullptr, n);
    return encloses(upward([&] { return pow_int(x, n); }), pow_int_range(mp, x, n), false,
                    Domain::kFull);
  });
}

TEST(IntervalMpfr, Square) {
  run_rule("square", [](Args& a, Mp& mp, std::string* what) {
    const Interval x = int_base(a);
    *what = call(x);
    return encloses(upward([&] { return square(x); }), pow_int_range(mp, x, 2), false,
                    Domain::kFull);
  });
}

}  // namespace
}  // namespace iaa
