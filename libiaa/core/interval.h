// Guaranteed interval arithmetic over doubles.
//
// `Interval` wraps boost::numeric::interval<double> with one fixed set of policies and documents
// every edge case it handles. All operations are *outward rounded*: the interval result contains
// the exact real result for every choice of real arguments inside the argument intervals.
//
// Rounding mode. Boost's "opposite" rounding policy computes every bound with the FPU rounding
// upward (a lower bound is -((-a) - b)). Switching the mode costs ~25 ns, so it is set once per
// scope, not per operation: every Interval operation must run while a `RoundingScope` is alive on
// the current thread. Evaluators and renderers open one scope per call or per tile. Builds that
// define IAA_CHECK_ROUNDING (none does by default) assert it in division, powers and sqrt; the
// evaluators' eval() checks it once per call; tests/core/rounding_test.cpp proves the bounds under
// the flags the build really uses (Release: CMake's -O3 -DNDEBUG plus -frounding-math
// -fno-fast-math from iaa_options; clang also gets -ffp-model=strict).
//
// Edge cases, all sound:
// - Division by an interval containing 0: the hull of both sides, i.e. usually the whole line;
//   division by exactly [0, 0] is undefined everywhere and gives `empty`.
// - sqrt/log of an interval reaching below 0 (resp. 0): clamped to the domain; the caller is told
//   through the Domain result so that it can mark the value as *partial domain* (no sign-change
//   argument may then be made on the box). Entirely outside the domain: `empty`.
// - sin, cos and exp (|x| <= 1e6, resp. 708) and log (finite x > 0) use the kernels of
//   core/elementary.h: one argument reduction and a polynomial per endpoint with a proved error
//   bound, widened by that bound (needs upward rounding, like the arithmetic); no libm call, no
//   mode switch. Beyond those ranges, and for tan atan and the real power, <cmath>, which
//   guarantees nothing about its error: results are widened outward by kTranscUlps ulps and
//   clamped to the true range.
// - Integer powers are tight: [-2,1]^2 = [0,4].
// - NaN never escapes: a NaN lower bound becomes -inf and a NaN upper bound +inf (this happens for
//   inf - inf or 0 * inf), which is the sound answer "anything".
// - Empty intervals are represented by lo = +inf, hi = -inf; `is_empty()` tests it. Operations on
// an
//   empty interval give empty.
#pragma once

#include <boost/numeric/interval.hpp>

#include <algorithm>
#include <cassert>
#include <cfenv>
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace iaa {

namespace detail {
namespace bil = boost::numeric::interval_lib;
// Upward-rounding policy without per-operation mode switches; RoundingScope sets the mode.
using FastPolicies = bil::policies<bil::save_state_nothing<bil::rounded_arith_opp<double>>,
                                   bil::checking_base<double>>;
using BoostInterval = boost::numeric::interval<double, FastPolicies>;
}  // namespace detail

/// RAII guard that switches the current thread's FPU to round upward and restores the previous
/// mode when it goes out of scope. Scopes nest. Point evaluation done inside a scope rounds upward
/// too, which is still contained in the interval results (see interval.h's header comment).
class RoundingScope {
 public:
  RoundingScope() : saved_(std::fegetround()) { std::fesetround(FE_UPWARD); }
  ~RoundingScope() { std::fesetround(saved_); }
  RoundingScope(const RoundingScope&) = delete;
  RoundingScope& operator=(const RoundingScope&) = delete;

 private:
  int saved_;
};

/// RAII guard that switches the current thread's FPU to round to nearest and restores the previous
/// mode when it goes out of scope: for point geometry (mesh vertices, areas, ray casts) that must
/// give the same doubles whatever mode the caller's thread is in. No Interval operation may run
/// inside it (interval.h's bounds rely on upward rounding).
class NearestScope {
 public:
  NearestScope() : saved_(std::fegetround()) { std::fesetround(FE_TONEAREST); }
  ~NearestScope() { std::fesetround(saved_); }
  NearestScope(const NearestScope&) = delete;
  NearestScope& operator=(const NearestScope&) = delete;

 private:
  int saved_;
};

/// True when the current thread rounds upward, i.e. a RoundingScope is alive. Cheap enough to
/// call once per evaluation: on x86 it reads the SSE control register inline (the mode that double
/// arithmetic really uses; fegetround() is a libm call that reads the x87 control word).
inline bool rounding_is_upward() {
#if defined(__SSE2_MATH__) && (defined(__x86_64__) || defined(__i386__))
  // MXCSR bits 13-14 are the rounding control: 00 nearest, 01 down, 10 up, 11 toward zero.
  return (_mm_getcsr() & 0x6000u) == 0x4000u;
#else
  return std::fegetround() == FE_UPWARD;
#endif
}

// Checks, in builds that define IAA_CHECK_ROUNDING, that an Interval operation runs upward.
#ifdef IAA_CHECK_ROUNDING
#define IAA_ASSERT_UPWARD() \
  assert(::iaa::rounding_is_upward() && "Interval op outside a RoundingScope")
#else
#define IAA_ASSERT_UPWARD() ((void)0)
#endif

/// Number of ulps by which the results of <cmath> transcendental functions are widened.
/// glibc documents at most 1-4 ulps of error for exp, log, sin, cos, tan, atan, pow on x86-64 in
/// every rounding mode; 8 leaves a margin for other libms.
inline constexpr int kTranscUlps = 8;

/// A closed interval [lo, hi] of reals, possibly unbounded, possibly empty.
class Interval {
 public:
  using Boost = detail::BoostInterval;

  /// The degenerate interval [0, 0].
  Interval() : lo_(0.0), hi_(0.0) {}
  /// The degenerate interval [v, v]. A NaN gives the whole line.
  Interval(double v) : lo_(v), hi_(v) {  // NOLINT: implicit by design, like a number
    if (v != v) *this = whole();
  }
  /// [lo, hi]. NaN bounds become infinite (outward); lo > hi is the caller's bug and gives empty.
  Interval(double lo, double hi) : lo_(lo != lo ? -kInf : lo), hi_(hi != hi ? kInf : hi) {
    if (lo_ > hi_) *this = empty();
  }
  explicit Interval(const Boost& b) : Interval(b.lower(), b.upper()) {}

  static Interval whole() { return raw(-kInf, kInf); }
  static Interval empty() { return raw(kInf, -kInf); }

  double lo() const { return lo_; }
  double hi() const { return hi_; }
  bool is_empty() const { return lo_ > hi_; }
  bool is_point() const { return lo_ == hi_; }
  bool is_finite() const { return std::isfinite(lo_) && std::isfinite(hi_); }
  bool contains(double v) const { return lo_ <= v && v <= hi_; }
  bool contains(const Interval& o) const { return o.is_empty() || (lo_ <= o.lo_ && o.hi_ <= hi_); }
  /// True if 0 lies in the interval: the only test a root exclusion may use.
  bool contains_zero() const { return lo_ <= 0.0 && 0.0 <= hi_; }
  /// Width hi - lo, rounded upward (needs a RoundingScope to be an upper bound).
  double width() const { return is_empty() ? 0.0 : hi_ - lo_; }
  /// A point inside the interval (the midpoint when finite), for splitting and shading.
  double mid() const;
  /// Greatest absolute value. (std::max, not std::fmax: the bounds are never NaN, and fmax is a
  /// libm call under -frounding-math.)
  double mag() const { return std::max(std::fabs(lo_), std::fabs(hi_)); }
  bool certainly_positive() const { return lo_ > 0.0; }
  bool certainly_negative() const { return hi_ < 0.0; }

  Boost boost() const { return Boost(lo_, hi_); }

  /// Assigns v with one 16-byte store where SSE2 is available. The tape loop writes each result
  /// slot once and later operations read it, often with one 16-byte load; a plain assignment may
  /// compile to two 8-byte stores, and a 16-byte load of two pending 8-byte stores cannot be
  /// forwarded from them: it stalls until they reach the cache (docs/eval.md, "How fast the
  /// evaluators are").
  void store(const Interval& v) {
#if defined(__SSE2__)
    _mm_storeu_pd(&lo_, _mm_set_pd(v.hi_, v.lo_));
#else
    *this = v;
#endif
  }

#if defined(__SSE2__)
  /// The bounds as one vector (lo in lane 0, hi in lane 1), and back: for operations that work
  /// on both bounds at once (operator*).
  __m128d pd() const {
    return _mm_loadu_pd(&lo_);
  }
  static Interval from_pd(__m128d v) {
    Interval r;
    _mm_storeu_pd(&r.lo_, v);
    return r;
  }
#endif

  friend bool operator==(const Interval& a, const Interval& b) {
    return (a.is_empty() && b.is_empty()) || (a.lo_ == b.lo_ && a.hi_ == b.hi_);
  }

  /// Builds [lo, hi] with no checks; for operation code that already guarantees lo <= hi or
  /// intends the empty representation.
  static Interval raw(double lo, double hi) {
    Interval r;
    r.lo_ = lo;
    r.hi_ = hi;
    return r;
  }

  static constexpr double kInf = std::numeric_limits<double>::infinity();

 private:
  double lo_, hi_;
};

static_assert(sizeof(Interval) == 2 * sizeof(double), "Interval::store writes lo and hi at once");

/// Hull of two intervals (empty is the neutral element).
inline Interval hull(const Interval& a, const Interval& b) {
  if (a.is_empty()) return b;
  if (b.is_empty()) return a;
  return Interval::raw(std::min(a.lo(), b.lo()), std::max(a.hi(), b.hi()));
}
/// Intersection (may be empty).
inline Interval intersect(const Interval& a, const Interval& b) {
  const double lo = std::max(a.lo(), b.lo());
  const double hi = std::min(a.hi(), b.hi());
  return lo <= hi ? Interval::raw(lo, hi) : Interval::empty();
}

// Inline (the renderer's searches call it on every piece): the midpoint of a finite interval,
// clamped into it (lo + (hi - lo) / 2 may round past hi), and a point of an unbounded one.
inline double Interval::mid() const {
  if (is_empty()) return std::numeric_limits<double>::quiet_NaN();
  if (lo_ == -kInf && hi_ == kInf) return 0.0;
  if (lo_ == -kInf) return hi_ > 0.0 ? 0.0 : hi_;
  if (hi_ == kInf) return lo_ < 0.0 ? 0.0 : lo_;
  const double m = lo_ + 0.5 * (hi_ - lo_);
  return std::clamp(m, lo_, hi_);
}

// Arithmetic. All need a RoundingScope. The hot ones are inline so that the tape loop can
// inline them (they are most of its time).

namespace detail {
using Rounding = Interval::Boost::traits_type::rounding;
/// max that ignores a NaN argument (IEEE maxNum); compiles to maxsd plus a compare.
inline double max_num(double x, double y) {
  return (x >= y || y != y) ? x : y;
}
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace detail

// Each operation computes its bounds first and checks them once: the rare cases (an empty
// argument, a NaN bound from inf - inf or 0 * inf) leave the fast path on one predictable branch.

inline Interval operator+(const Interval& a, const Interval& b) {
  // Rounding upward: x + y rounds up, -((-x) - y) rounds down (Boost's "opposite" trick, without
  // its volatile round trip, which only x87 code needs). -frounding-math keeps the compiler from
  // folding the two into one; tests/core/rounding_test.cpp checks it.
  const double lo = -((-a.lo()) - b.lo()), hi = a.hi() + b.hi();
  // Non-empty arguments give lo <= hi unless a bound is NaN (inf - inf); an empty argument
  // (lo = +inf, hi = -inf) gives lo = +inf or NaN and hi = -inf or NaN, never lo <= hi.
  if (lo <= hi) [[likely]]
    return Interval::raw(lo, hi);
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  return Interval(lo, hi);  // a NaN bound becomes infinite: "anything", outward
}

inline Interval operator-(const Interval& a, const Interval& b) {
  const double lo = -(b.hi() - a.lo()), hi = a.hi() - b.lo();
  if (lo <= hi) [[likely]]  // as in operator+
    return Interval::raw(lo, hi);
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  return Interval(lo, hi);
}

inline Interval operator-(const Interval& a) {
  return a.is_empty() ? a : Interval::raw(-a.hi(), -a.lo());
}

namespace detail {
/// True when the four bounds are finite, which also excludes the empty interval (infinite
/// bounds). Bounds are never NaN.
inline bool all_finite(double a, double b, double c, double d) {
  const double m =
      std::max(std::max(std::fabs(a), std::fabs(b)), std::max(std::fabs(c), std::fabs(d)));
  return m <= std::numeric_limits<double>::max();
}
/// Product with an empty, unbounded or infinite argument (interval.cpp).
Interval mul_general(const Interval& a, const Interval& b);
}  // namespace detail

inline Interval operator*(const Interval& a, const Interval& b) {
#if defined(__SSE2__)
  // Both bounds in one pass: lane 1 computes hi as below, lane 0 computes -lo from the negated
  // factors, the same products in the same order, so the bounds are bit for bit the scalar
  // code's (std::max(x, y) is _mm_max_pd(y, x): both give x when neither is greater, so even
  // the signs of zero bounds agree). Half the instructions of the scalar code.
  const __m128d va = a.pd(), vb = b.pd();
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
  const __m128d m = _mm_max_pd(_mm_and_pd(va, magnitude), _mm_and_pd(vb, magnitude));
  if (_mm_cvtsd_f64(_mm_max_sd(m, _mm_unpackhi_pd(m, m))) <= std::numeric_limits<double>::max())
      [[likely]] {
    const __m128d sign_lo = _mm_set_pd(0.0, -0.0);                   // flips lane 0 only
    const __m128d u = _mm_xor_pd(_mm_unpacklo_pd(va, va), sign_lo);  // (-al, al)
    const __m128d v = _mm_xor_pd(_mm_unpackhi_pd(va, va), sign_lo);  // (-ah, ah)
    const __m128d bl = _mm_unpacklo_pd(vb, vb), bh = _mm_unpackhi_pd(vb, vb);
    const auto max = [](__m128d x, __m128d y) { return _mm_max_pd(y, x); };  // std::max(x, y)
    const __m128d p =
        max(max(_mm_mul_pd(u, bl), _mm_mul_pd(u, bh)), max(_mm_mul_pd(v, bl), _mm_mul_pd(v, bh)));
    return Interval::from_pd(_mm_xor_pd(p, sign_lo));
  }
  return detail::mul_general(a, b);
#else
  const double al = a.lo(), ah = a.hi(), bl = b.lo(), bh = b.hi();
  if (detail::all_finite(al, ah, bl, bh)) [[likely]] {
    // Branch-free: the bounds are the extreme endpoint products. With the FPU rounding upward,
    // p rounds up and -((-x) * y) rounds down. Finite factors give no NaN product (an overflow
    // is an infinity, still a bound), so a plain max is exact; lo <= hi as lo is the least and
    // hi the greatest of the same products, rounded down and up.
    const double hi = std::max(std::max(al * bl, al * bh), std::max(ah * bl, ah * bh));
    const double lo = -std::max(std::max((-al) * bl, (-al) * bh), std::max((-ah) * bl, (-ah) * bh));
    return Interval::raw(lo, hi);
  }
  return detail::mul_general(a, b);
#endif
}
inline Interval& operator+=(Interval& a, const Interval& b) {
  return a = a + b;
}
inline Interval& operator-=(Interval& a, const Interval& b) {
  return a = a - b;
}
inline Interval& operator*=(Interval& a, const Interval& b) {
  return a = a * b;
}

/// Whether an operation saw its whole argument inside its domain.
enum class Domain : unsigned char {
  kFull = 0,     ///< defined (and continuous) on the whole argument
  kPartial = 1,  ///< defined on part of the argument only, or has a pole inside it
};

namespace detail {
/// Division with a divisor that may contain 0 or be empty (interval.cpp); see divide().
Interval divide_general(const Interval& a, const Interval& b, Domain* dom);

/// x^n for x >= 0 and n >= 1, rounded up. Binary powering, in the same order of multiplications
/// as PointRules::pow_int, so that a point value (rounded in any mode) is bracketed step by step.
/// Every factor is >= 0 and every product rounds up (upward mode), so each partial result is an
/// upper bound of its exact value: the result is an upper bound of x^n (inf on overflow).
inline double pow_up(double x, int n) {
  double y = (n & 1) ? x : 1.0;
  for (int p = n >> 1; p > 0; p >>= 1) {
    x = x * x;
    if (p & 1) y = x * y;
  }
  return y;
}
/// x^n for x >= 0 and n >= 1, rounded down: each product is -((-u) * v), which rounds u*v down
/// under the upward mode, so each partial result is a lower bound (0 on underflow, DBL_MAX on
/// overflow, both below the exact value).
inline double pow_down(double x, int n) {
  double y = (n & 1) ? x : 1.0;
  for (int p = n >> 1; p > 0; p >>= 1) {
    x = -((-x) * x);
    if (p & 1) y = -((-x) * y);
  }
  return y;
}
/// Least and greatest |v| over a non-empty x, branch-free: the even powers are functions of
/// them. The least is lo when x >= 0, -hi when x <= 0, and 0 when x straddles 0.
inline void abs_range(const Interval& x, double* small, double* big) {
  *big = std::max(-x.lo(), x.hi());
  *small = std::max(0.0, std::max(x.lo(), -x.hi()));
}
}  // namespace detail

/// a * c for a finite non-zero number c (a constant of the expression): two products, no tests.
/// An empty a stays empty (its infinite bounds swap and keep lo > hi); an unbounded a stays
/// unbounded (inf * c is an infinity, never NaN, as c != 0).
inline Interval scale(const Interval& a, double c) {
  IAA_ASSERT_UPWARD();
  assert(std::isfinite(c) && c != 0.0);
  const double l = c > 0.0 ? a.lo() : a.hi(), h = c > 0.0 ? a.hi() : a.lo();
  return Interval::raw(-((-l) * c), h * c);
}

/// a / c for a finite non-zero number c (a constant of the expression): two divisions, no tests;
/// the same bounds as divide(a, Interval(c)). Empty and unbounded a behave as in scale().
inline Interval div_const(const Interval& a, double c) {
  IAA_ASSERT_UPWARD();
  assert(std::isfinite(c) && c != 0.0);
  const double l = c > 0.0 ? a.lo() : a.hi(), h = c > 0.0 ? a.hi() : a.lo();
  return Interval::raw(-((-l) / c), h / c);
}

/// Division reporting kPartial when the divisor contains 0 (a pole or an undefined point).
/// A divisor that excludes 0 (e.g. a constant) takes the inline path: two divisions.
inline Interval divide(const Interval& a, const Interval& b, Domain* dom) {
  IAA_ASSERT_UPWARD();
  if (a.is_empty() || b.is_empty() || b.contains_zero()) return detail::divide_general(a, b, dom);
  // a / b = (-a) / (-b): reduce to a divisor 0 < dl <= dh.
  const bool neg = b.hi() < 0.0;
  const double nl = neg ? -a.hi() : a.lo(), nh = neg ? -a.lo() : a.hi();
  const double dl = neg ? -b.hi() : b.lo(), dh = neg ? -b.lo() : b.hi();
  // The quotient is least at nl / dh when nl >= 0, else at nl / dl; greatest at nh / dl when
  // nh >= 0, else at nh / dh. -((-u) / v) rounds u / v down. inf / inf is NaN, which the
  // constructor turns into the infinite (outward) bound.
  const double lo = -((-nl) / (nl >= 0.0 ? dh : dl));
  const double hi = nh / (nh >= 0.0 ? dl : dh);
  return Interval(lo, hi);
}
/// Division; see the header comment for divisors containing 0.
inline Interval operator/(const Interval& a, const Interval& b) {
  Domain dom = Domain::kFull;
  return divide(a, b, &dom);
}

/// x*x, tight: [-2,1] -> [0,4].
inline Interval square(const Interval& x) {
  IAA_ASSERT_UPWARD();
  if (x.is_empty()) return x;
  double small, big;
  detail::abs_range(x, &small, &big);
  // No NaN: small and big are >= 0 and each is squared on its own.
  return Interval::raw(-((-small) * small), big * big);
}
/// x^n for an integer n >= 0, tight: even powers of an interval containing 0 start at 0, odd
/// powers are increasing. pow(x, 0) = [1,1] (also at x = 0, as for polynomials).
inline Interval pow_int(const Interval& x, int n) {
  IAA_ASSERT_UPWARD();
  assert(n >= 0);
  if (x.is_empty()) return x;
  if (n == 0) return Interval(1.0);
  if (n == 1) return x;
  if (n == 2) return square(x);
  if (n & 1) {
    const double lo = x.lo() >= 0.0 ? detail::pow_down(x.lo(), n) : -detail::pow_up(-x.lo(), n);
    const double hi = x.hi() >= 0.0 ? detail::pow_up(x.hi(), n) : -detail::pow_down(-x.hi(), n);
    return Interval::raw(lo, hi);
  }
  double small, big;
  detail::abs_range(x, &small, &big);
  return Interval::raw(detail::pow_down(small, n), detail::pow_up(big, n));
}
/// sqrt on x >= 0; clamps and reports kPartial when x reaches below 0.
Interval sqrt(const Interval& x, Domain* dom);
Interval exp(const Interval& x);
/// log on x > 0; clamps and reports kPartial when x reaches 0 or below (log 0 = -inf).
Interval log(const Interval& x, Domain* dom);
Interval sin(const Interval& x);
Interval cos(const Interval& x);
/// sin(x) and cos(x) at once, as the two functions give them; shares the work on x (one sincos
/// per endpoint), for the gradient rules, which need both.
void sincos(const Interval& x, Interval* s, Interval* c);
/// sin(v) and cos(v) of a double, the values std::sin and std::cos give, for about the cost of
/// one (glibc's sincos; elsewhere the two calls). No rounding guarantee: a point value.
void sincos(double v, double* s, double* c);
/// tan; an interval that contains a pole gives the whole line and kPartial.
Interval tan(const Interval& x, Domain* dom);
Interval atan(const Interval& x);
Interval abs(const Interval& x);
Interval min(const Interval& a, const Interval& b);
Interval max(const Interval& a, const Interval& b);
/// Real power x^y = exp(y log x) on x > 0 (x = 0 is allowed where y > 0). Clamps x to the domain
/// and reports kPartial when it reaches below.
Interval pow_real(const Interval& x, const Interval& y, Domain* dom);

/// Widens v outward by n ulps (toward -inf when down, +inf otherwise); infinities stay.
double widen_down(double v, int n = kTranscUlps);
double widen_up(double v, int n = kTranscUlps);

}  // namespace iaa
