// Guaranteed interval arithmetic over doubles.
//
// `Interval` wraps boost::numeric::interval<double> with one fixed set of policies and documents
// every edge case it handles. All operations are *outward rounded*: the interval result contains
// the exact real result for every choice of real arguments inside the argument intervals.
//
// Rounding mode. Boost's "opposite" rounding policy computes every bound with the FPU rounding
// upward (a lower bound is -((-a) - b)). Switching the mode costs ~25 ns, so it is set once per
// scope, not per operation: every Interval operation must run while a `RoundingScope` is alive on
// the current thread. Evaluators and renderers open one scope per call or per tile. Debug builds
// check it (IAA_CHECK_ROUNDING); tests/core/rounding_test.cpp proves the bounds under the flags of
// the release build (-O2 -frounding-math).
//
// Edge cases, all sound:
// - Division by an interval containing 0: the hull of both sides, i.e. usually the whole line;
//   division by exactly [0, 0] is undefined everywhere and gives `empty`.
// - sqrt/log of an interval reaching below 0 (resp. 0): clamped to the domain; the caller is told
//   through the Domain result so that it can mark the value as *partial domain* (no sign-change
//   argument may then be made on the box). Entirely outside the domain: `empty`.
// - Transcendentals (exp log sin cos tan atan, real pow) call <cmath>, which guarantees nothing
//   about its error; results are widened outward by kTranscUlps ulps and clamped to the true range.
// - Integer powers are tight: [-2,1]^2 = [0,4].
// - NaN never escapes: a NaN lower bound becomes -inf and a NaN upper bound +inf (this happens for
//   inf - inf or 0 * inf), which is the sound answer "anything".
// - Empty intervals are represented by lo = +inf, hi = -inf; `is_empty()` tests it. Operations on
// an
//   empty interval give empty.
#pragma once

#include <boost/numeric/interval.hpp>

#include <cfenv>
#include <cmath>
#include <limits>

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

/// True when the current thread rounds upward, i.e. a RoundingScope is alive.
inline bool rounding_is_upward() {
  return std::fegetround() == FE_UPWARD;
}

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
  /// Smallest interval containing a and b (in either order).
  static Interval hull_of(double a, double b) { return a <= b ? Interval(a, b) : Interval(b, a); }

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
  /// Greatest absolute value.
  double mag() const { return std::fmax(std::fabs(lo_), std::fabs(hi_)); }
  /// Least absolute value.
  double mig() const { return contains_zero() ? 0.0 : std::fmin(std::fabs(lo_), std::fabs(hi_)); }
  bool certainly_positive() const { return lo_ > 0.0; }
  bool certainly_negative() const { return hi_ < 0.0; }

  Boost boost() const { return Boost(lo_, hi_); }

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

/// Hull of two intervals (empty is the neutral element).
Interval hull(const Interval& a, const Interval& b);
/// Intersection (may be empty).
Interval intersect(const Interval& a, const Interval& b);

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

inline Interval operator+(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  // Rounding upward: x + y rounds up, -((-x) - y) rounds down (Boost's "opposite" trick, without
  // its volatile round trip, which only x87 code needs). -frounding-math keeps the compiler from
  // folding the two into one; tests/core/rounding_test.cpp checks it.
  return Interval(-((-a.lo()) - b.lo()), a.hi() + b.hi());
}

inline Interval operator-(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  return Interval(-(b.hi() - a.lo()), a.hi() - b.lo());
}

inline Interval operator-(const Interval& a) {
  return a.is_empty() ? a : Interval::raw(-a.hi(), -a.lo());
}

inline Interval operator*(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  // A factor that is exactly 0 makes the product 0 even when the other factor is unbounded
  // (0 times any real is 0; IEEE's 0 * inf = NaN would otherwise widen the result to everything).
  if ((a.lo() == 0.0 && a.hi() == 0.0) || (b.lo() == 0.0 && b.hi() == 0.0)) return Interval(0.0);
  // Branch-free: the bounds are the extreme endpoint products. With the FPU rounding upward,
  // p rounds up and -((-x) * y) rounds down. An endpoint product 0 * inf is NaN; it stands for
  // 0 times reals and is dropped (max_num ignores it), the other products bound the result.
  const double al = a.lo(), ah = a.hi(), bl = b.lo(), bh = b.hi();
  // Scaling by a finite point (a constant of the expression) needs two products.
  if (bl == bh && bl > 0.0 && bl < detail::kInfinity) return Interval(-((-al) * bl), ah * bl);
  if (bl == bh && bl < 0.0 && bl > -detail::kInfinity) return Interval(-((-ah) * bl), al * bl);
  if (al == ah && al > 0.0 && al < detail::kInfinity) return Interval(-((-bl) * al), bh * al);
  if (al == ah && al < 0.0 && al > -detail::kInfinity) return Interval(-((-bh) * al), bl * al);
  const double hi =
      detail::max_num(detail::max_num(al * bl, al * bh), detail::max_num(ah * bl, ah * bh));
  const double lo = -detail::max_num(detail::max_num((-al) * bl, (-al) * bh),
                                     detail::max_num((-ah) * bl, (-ah) * bh));
  return Interval(lo, hi);
}
/// Division; see the header comment for divisors containing 0.
Interval operator/(const Interval& a, const Interval& b);
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

/// x*x, tight: [-2,1] -> [0,4].
inline Interval square(const Interval& x) {
  if (x.is_empty()) return x;
  return Interval(boost::numeric::square(x.boost()));
}
/// x^n for an integer n >= 0, tight. pow(x, 0) = [1,1] (also at x = 0, as for polynomials).
Interval pow_int(const Interval& x, int n);
/// sqrt on x >= 0; clamps and reports kPartial when x reaches below 0.
Interval sqrt(const Interval& x, Domain* dom);
Interval exp(const Interval& x);
/// log on x > 0; clamps and reports kPartial when x reaches 0 or below (log 0 = -inf).
Interval log(const Interval& x, Domain* dom);
Interval sin(const Interval& x);
Interval cos(const Interval& x);
/// tan; an interval that contains a pole gives the whole line and kPartial.
Interval tan(const Interval& x, Domain* dom);
Interval atan(const Interval& x);
Interval abs(const Interval& x);
Interval min(const Interval& a, const Interval& b);
Interval max(const Interval& a, const Interval& b);
/// Real power x^y = exp(y log x) on x > 0 (x = 0 is allowed where y > 0). Clamps x to the domain
/// and reports kPartial when it reaches below.
Interval pow_real(const Interval& x, const Interval& y, Domain* dom);
/// Division reporting kPartial when the divisor contains 0 (a pole or an undefined point).
Interval divide(const Interval& a, const Interval& b, Domain* dom);

/// Widens v outward by n ulps (toward -inf when down, +inf otherwise); infinities stay.
double widen_down(double v, int n = kTranscUlps);
double widen_up(double v, int n = kTranscUlps);

}  // namespace iaa
