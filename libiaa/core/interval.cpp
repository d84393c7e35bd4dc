#include "core/interval.h"

#include "core/elementary.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cfloat>
#include <cstdint>
#include <numbers>
#include <utility>

namespace iaa {

namespace {

using detail::Rounding;

constexpr double kInf = Interval::kInf;
constexpr double kPi = std::numbers::pi;
// constexpr so that it is folded at compile time: under -frounding-math GCC otherwise converts
// the long double literal behind denorm_min() to double at run time, on every use.
constexpr double kDenormMin = std::numeric_limits<double>::denorm_min();

// Decides conservatively whether some point c_k = offset + k * period lies in [lo, hi]. Returns
// the smallest such k through *k_first and whether the range may hold more than one. The slack
// (1e-9 periods) absorbs the rounding error of (x - offset) / period, computed as a product with
// the rounded 1/period, for |x| <= 1e6: a critical point that is truly inside is never missed; one
// just outside may be reported (a looser, still sound bound).
struct CriticalPoints {
  bool any;        // at least one c_k may lie in [lo, hi]
  double k_first;  // smallest candidate k (integer-valued)
  double k_last;   // largest candidate k
};
// `inv_period` is 1/period rounded: its relative error (1 ulp) adds at most 1e6/pi * 2^-52 ~ 1e-10
// periods for |x| <= kTrigArgLimit, well inside the slack, and spares a division.
CriticalPoints critical_points(double lo, double hi, double offset, double inv_period) {
  const double slack = 1e-9;
  const double a = std::ceil((lo - offset) * inv_period - slack);
  const double b = std::floor((hi - offset) * inv_period + slack);
  return {a <= b, a, b};
}
// Beyond this magnitude the critical-point slack above is not proved; sin/cos/tan give their
// whole range.
constexpr double kTrigArgLimit = 1e6;
constexpr double kInvPi = std::numbers::inv_pi;

// The next double below (above) a finite v, without the library call of std::nextafter: the
// bit pattern of a double is monotone in its magnitude. -DBL_MAX steps to -inf (and DBL_MAX to
// +inf) as nextafter does; zeros of either sign step to the smallest subnormal.
double next_down(double v) {
  if (v == 0.0) return -kDenormMin;
  const auto bits = std::bit_cast<std::uint64_t>(v);
  return std::bit_cast<double>(v > 0.0 ? bits - 1 : bits + 1);
}
double next_up(double v) {
  if (v == 0.0) return kDenormMin;
  const auto bits = std::bit_cast<std::uint64_t>(v);
  return std::bit_cast<double>(v > 0.0 ? bits + 1 : bits - 1);
}

// glibc's sin, cos, exp and log run in round-to-nearest: called while the thread rounds upward,
// each one writes the SSE control register twice (to nearest and back), which about doubles its
// cost. Around a batch of such calls this switches once. Their results are widened by
// kTranscUlps ulps afterwards, which holds in every rounding mode, so the mode during the call
// does not matter for soundness. Elsewhere (other targets) it does nothing.
class LibmNearest {
 public:
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  // LDMXCSR reads memory and cannot take a value from the store buffer: loading a control word
  // stored just before (as _mm_setcsr does) waits for that store to be written, which in some
  // memory layouts is slow (docs/eval.md). So both words loaded here were written long before:
  // the nearest-mode word is kept per thread (rewritten only when the caller's control bits
  // change), the caller's word at construction.
  LibmNearest() {
    asm volatile("stmxcsr %0" : "=m"(saved_) : : "memory");
    thread_local unsigned nearest = 0, control_of_nearest = ~0u;
    const unsigned control = saved_ & ~kFlagBits;
    if (control != control_of_nearest) {
      control_of_nearest = control;
      nearest = control & ~kRoundingBits;
    }
    asm volatile("ldmxcsr %0" : : "m"(nearest) : "memory");
  }
  ~LibmNearest() {
    asm volatile("ldmxcsr %0" : : "m"(saved_) : "memory");
  }

 private:
  static constexpr unsigned kRoundingBits = 0x6000u;  // MXCSR.RC
  static constexpr unsigned kFlagBits = 0x3Fu;        // sticky exception flags, not control
  unsigned saved_;

 public:
#else
  LibmNearest() = default;
#endif
  LibmNearest(const LibmNearest&) = delete;
  LibmNearest& operator=(const LibmNearest&) = delete;
};

// v - (elementary::kRelErr |v| + abs) rounded down, and v + (...) rounded up: the ends of an
// enclosure of f(x) from a kernel value v of elementary.h with the absolute error term `abs`.
// Needs upward rounding: the error term and the upper end round up, and -((-v) + err) rounds the
// lower end down. kRelErr is a power of 2, so the product is exact unless it underflows (then it
// rounds up too).
double below(double v, double abs) {
  return -((-v) + (elementary::kRelErr * std::fabs(v) + abs));
}
double above(double v, double abs) {
  return v + (elementary::kRelErr * std::fabs(v) + abs);
}

}  // namespace

double widen_down(double v, int n) {
  if (!std::isfinite(v)) return v;
  // n * 2^-52 * |v| is between n and 2n ulps of v; 2^-1074 per ulp covers subnormals.
  const double d = std::fabs(v) * (n * DBL_EPSILON) + n * kDenormMin;
  const double r = v - d;
  return std::isfinite(r) ? next_down(r) : r;
}

double widen_up(double v, int n) {
  if (!std::isfinite(v)) return v;
  const double d = std::fabs(v) * (n * DBL_EPSILON) + n * kDenormMin;
  const double r = v + d;
  return std::isfinite(r) ? next_up(r) : r;
}

Interval detail::mul_general(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  // A factor that is exactly 0 makes the product 0 even when the other factor is unbounded
  // (0 times any real is 0; IEEE's 0 * inf = NaN would otherwise widen the result to everything).
  if ((a.lo() == 0.0 && a.hi() == 0.0) || (b.lo() == 0.0 && b.hi() == 0.0)) return Interval(0.0);
  // The extreme endpoint products, as in operator*. An endpoint product 0 * inf is NaN; it
  // stands for 0 times reals and is dropped (max_num ignores it), the other products bound the
  // result. All four are NaN only when a or b is [0, 0], handled above.
  const double al = a.lo(), ah = a.hi(), bl = b.lo(), bh = b.hi();
  const double hi =
      detail::max_num(detail::max_num(al * bl, al * bh), detail::max_num(ah * bl, ah * bh));
  const double lo = -detail::max_num(detail::max_num((-al) * bl, (-al) * bh),
                                     detail::max_num((-ah) * bl, (-ah) * bh));
  return Interval(lo, hi);
}

// The divisor contains 0 or an argument is empty; divide() handles the rest inline.
Interval detail::divide_general(const Interval& a, const Interval& b, Domain* dom) {
  IAA_ASSERT_UPWARD();
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  if (!b.contains_zero()) return divide(a, b, dom);
  *dom = Domain::kPartial;
  if (b.lo() == 0.0 && b.hi() == 0.0) return Interval::empty();  // undefined everywhere
  if (a.lo() == 0.0 && a.hi() == 0.0) return Interval(0.0);      // 0 / y = 0 wherever defined
  Rounding rnd;
  if (b.lo() == 0.0) {  // divisor in (0, hi]
    if (a.lo() >= 0.0) return Interval(rnd.div_down(a.lo(), b.hi()), kInf);
    if (a.hi() <= 0.0) return Interval(-kInf, rnd.div_up(a.hi(), b.hi()));
    return Interval::whole();
  }
  if (b.hi() == 0.0) {  // divisor in [lo, 0)
    if (a.lo() >= 0.0) return Interval(-kInf, rnd.div_up(a.lo(), b.lo()));
    if (a.hi() <= 0.0) return Interval(rnd.div_down(a.hi(), b.lo()), kInf);
    return Interval::whole();
  }
  // 0 strictly inside the divisor: the two branches together cover the whole line.
  return Interval::whole();
}

Interval sqrt(const Interval& x, Domain* dom) {
  IAA_ASSERT_UPWARD();
  if (x.is_empty()) return x;
  if (x.hi() < 0.0) {
    *dom = Domain::kPartial;
    return Interval::empty();
  }
  double lo = x.lo();
  if (lo < 0.0) {
    *dom = Domain::kPartial;
    lo = 0.0;
  }
  // IEEE sqrt is correctly rounded in the current (upward) mode: std::sqrt(hi) >= the true root.
  // One step down from the upward-rounded root is below the true root of lo.
  double r_lo = std::sqrt(lo);
  if (r_lo > 0.0) r_lo = next_down(r_lo);
  return Interval(r_lo, std::sqrt(x.hi()));
}

namespace {
// The lower (upper) bound of exp over an interval with the end v: by the kernel (elementary.h)
// widened by its bound where |v| <= kExpMax, else glibc's exp widened by kTranscUlps (in
// round-to-nearest). Each bound depends on its own end only, by one rule for every interval,
// so that the bounds over a box enclose those over every box inside it.
double exp_below(double v) {
  if (std::fabs(v) <= elementary::kExpMax) return below(elementary::exp_kernel(v), 0.0);
  double e;
  {
    const LibmNearest nearest;
    e = std::exp(v);
  }
  // exp > 0 and finite for every real argument: the lower bound lies in [0, DBL_MAX].
  return std::clamp(widen_down(e), 0.0, DBL_MAX);
}
double exp_above(double v) {
  if (std::fabs(v) <= elementary::kExpMax) return above(elementary::exp_kernel(v), 0.0);
  const LibmNearest nearest;
  return widen_up(std::exp(v));
}
}  // namespace

Interval exp(const Interval& x) {
  if (x.is_empty()) return x;
  IAA_ASSERT_UPWARD();
#ifdef IAA_ELEMENTARY_LANES
  // Both ends in the kernel's range (the common case): one pass over two lanes, the same
  // doubles as exp_below's and exp_above's kernel calls.
  if (std::fabs(x.lo()) <= elementary::kExpMax && std::fabs(x.hi()) <= elementary::kExpMax) {
    const elementary::V2d v = elementary::exp_kernel2(elementary::V2d{x.lo(), x.hi()});
    return Interval(below(v[0], 0.0), above(v[1], 0.0));
  }
#endif
  return Interval(exp_below(x.lo()), exp_above(x.hi()));
}

namespace {
// The lower (upper) bound of log over an interval with the end v > 0: the kernel (elementary.h)
// widened by its bound where v is finite, log(inf) = inf otherwise. Each bound depends on its
// own end only, as for exp.
double log_below(double v) {
  if (v <= DBL_MAX) return below(elementary::log_kernel(v), elementary::log_abs_err(v));
  return kInf;  // [inf, inf]: beyond every finite double, as its log
}
double log_above(double v) {
  if (v <= DBL_MAX) return above(elementary::log_kernel(v), elementary::log_abs_err(v));
  return kInf;
}
}  // namespace

Interval log(const Interval& x, Domain* dom) {
  if (x.is_empty()) return x;
  if (x.hi() <= 0.0) {
    *dom = Domain::kPartial;
    return Interval::empty();
  }
  IAA_ASSERT_UPWARD();
  // -inf where the box reaches 0 or below (partial); log of a finite double is at most ~709.8.
  if (x.lo() <= 0.0) *dom = Domain::kPartial;
  return Interval(x.lo() > 0.0 ? log_below(x.lo()) : -kInf, log_above(x.hi()));
}

namespace {
// sin and cos of an argument this wide, unbounded or large take their whole range [-1, 1].
bool trig_takes_whole_range(const Interval& x) {
  return !x.is_finite() || x.mag() > kTrigArgLimit || x.hi() - x.lo() >= 2.0 * kPi;
}

// One end of an argument of sin and cos: its reduction x = k pi/2 + r (elementary.h), sin r,
// cos r and the absolute error term of the values.
struct TrigEnd {
  elementary::Quadrant q;
  double s, c, abs;
};
// Both ends of [a, b] at once (elementary::reduce_sin_cos2: the same doubles as one end at a
// time, in half the instructions).
void trig_ends(double a, double b, TrigEnd* ea, TrigEnd* eb) {
  elementary::ReducedTrig ra, rb;
  elementary::reduce_sin_cos2(a, b, &ra, &rb);
  *ea = {ra.q, ra.s, ra.c, elementary::trig_abs_err(ra.q)};
  *eb = {rb.q, rb.s, rb.c, elementary::trig_abs_err(rb.q)};
}

// The range of sin (shift 0) or cos (shift 1) over [a, b], x = [a, b] not
// trig_takes_whole_range. Both take their extrema at the multiples n pi/2, sin(n pi/2) being
// 0, 1, 0, -1 for n = 0, 1, 2, 3 mod 4 (cos: n + 1). The multiples that may lie in [a, b] are
// n = a.k .. b.k, without a.k when r_a is certainly > 0 (a > a.k pi/2) and without b.k when r_b
// is certainly < 0: the reduced arguments are within 2^-51 |r| + 2^-99 of the exact ones
// (elementary.h), so a computed r beyond 2^-90 has the sign of the exact one; |r| < pi/4 puts
// every other multiple outside. Four or more of them give [-1, 1].
Interval trig_range(const TrigEnd& a, const TrigEnd& b, int shift) {
  const double va = elementary::sin_of(a.q.k + shift, a.s, a.c);
  const double vb = elementary::sin_of(b.q.k + shift, b.s, b.c);
  double lo = std::min(below(va, a.abs), below(vb, b.abs));
  double hi = std::max(above(va, a.abs), above(vb, b.abs));
  constexpr double kSure = 0x1p-90;
  const std::int64_t first = a.q.r > kSure ? a.q.k + 1 : a.q.k;
  const std::int64_t last = b.q.r < -kSure ? b.q.k - 1 : b.q.k;
  // Branch-free: the multiples first .. last (count of them) hold the maximum (n + shift = 1 mod
  // 4) when the first such n is within count of `first`, likewise the minimum (3 mod 4).
  const std::int64_t count = last - first + 1, phase = first + shift;
  if (((1 - phase) & 3) < count) hi = 1.0;
  if (((3 - phase) & 3) < count) lo = -1.0;
  return Interval::raw(std::max(lo, -1.0), std::min(hi, 1.0));
}

#ifdef IAA_ELEMENTARY_LANES
// sin and cos over [a, b] (not trig_takes_whole_range) with the two ends in the lanes of one
// vector (elementary::reduce_sin_cos_lanes): trig_ends and trig_range's operations on each
// lane, so the same bounds to the bit, in about half the instructions.
void sincos_lanes(double a, double b, Interval* s, Interval* c) {
  using elementary::V2d;
  using elementary::V2l;
  using elementary::V2u;
  const elementary::TrigLanes t = elementary::reduce_sin_cos_lanes(V2d{a, b});
  // elementary::trig_abs_err of each end.
  const V2u k_zero = std::bit_cast<V2u>(t.k == 0);
  const V2d abs =
      std::bit_cast<V2d>((k_zero & std::bit_cast<std::uint64_t>(0x1p-1070)) |
                         (~k_zero & std::bit_cast<std::uint64_t>(elementary::kReducedAbsErr)));
  const auto ends = [&](V2d v, double* lo, double* hi) {
    // below() and above() of each lane, then the lower of the two lows and the higher high.
    const V2d fabs_v = std::bit_cast<V2d>(std::bit_cast<V2u>(v) & 0x7fffffffffffffffULL);
    const V2d err = elementary::kRelErr * fabs_v + abs;
    const V2d down = -((-v) + err), up = v + err;
    *lo = std::min(down[0], down[1]);
    *hi = std::max(up[0], up[1]);
  };
  double s_lo, s_hi, c_lo, c_hi;
  ends(elementary::sin_of_lanes(t.k, t.s, t.c), &s_lo, &s_hi);
  ends(elementary::sin_of_lanes(t.k + 1, t.s, t.c), &c_lo, &c_hi);
  // The multiples of pi/2 in [a, b], as in trig_range.
  constexpr double kSure = 0x1p-90;
  const std::int64_t first = t.r[0] > kSure ? t.k[0] + 1 : t.k[0];
  const std::int64_t last = t.r[1] < -kSure ? t.k[1] - 1 : t.k[1];
  const std::int64_t count = last - first + 1;
  if (((1 - first) & 3) < count) s_hi = 1.0;
  if (((3 - first) & 3) < count) s_lo = -1.0;
  if (((1 - (first + 1)) & 3) < count) c_hi = 1.0;
  if (((3 - (first + 1)) & 3) < count) c_lo = -1.0;
  *s = Interval::raw(std::max(s_lo, -1.0), std::min(s_hi, 1.0));
  *c = Interval::raw(std::max(c_lo, -1.0), std::min(c_hi, 1.0));
}
#endif
}  // namespace

void sincos(double v, double* s, double* c) {
  elementary::sincos(v, s, c);
}

Interval sin(const Interval& x) {
  if (x.is_empty()) return x;
  if (trig_takes_whole_range(x)) return Interval(-1.0, 1.0);
  IAA_ASSERT_UPWARD();
  TrigEnd a, b;
  trig_ends(x.lo(), x.hi(), &a, &b);
  return trig_range(a, b, 0);
}
Interval cos(const Interval& x) {
  if (x.is_empty()) return x;
  if (trig_takes_whole_range(x)) return Interval(-1.0, 1.0);
  IAA_ASSERT_UPWARD();
  TrigEnd a, b;
  trig_ends(x.lo(), x.hi(), &a, &b);
  return trig_range(a, b, 1);
}
void sincos(const Interval& x, Interval* s, Interval* c) {
  if (x.is_empty()) {
    *s = *c = x;
    return;
  }
  if (trig_takes_whole_range(x)) {
    *s = *c = Interval(-1.0, 1.0);
    return;
  }
  IAA_ASSERT_UPWARD();
#ifdef IAA_ELEMENTARY_LANES
  sincos_lanes(x.lo(), x.hi(), s, c);
#else
  TrigEnd a, b;
  trig_ends(x.lo(), x.hi(), &a, &b);
  *s = trig_range(a, b, 0);
  *c = trig_range(a, b, 1);
#endif
}

Interval tan(const Interval& x, Domain* dom) {
  if (x.is_empty()) return x;
  if (!x.is_finite() || x.mag() > kTrigArgLimit || x.hi() - x.lo() >= kPi) {
    *dom = Domain::kPartial;
    return Interval::whole();
  }
  // Poles at pi/2 + k pi; between two poles tan increases.
  if (critical_points(x.lo(), x.hi(), kPi / 2.0, kInvPi).any) {
    *dom = Domain::kPartial;
    return Interval::whole();
  }
  return Interval(widen_down(std::tan(x.lo())), widen_up(std::tan(x.hi())));
}

Interval atan(const Interval& x) {
  if (x.is_empty()) return x;
  const double lim = widen_up(kPi / 2.0);
  const double lo = x.lo() == -kInf ? -lim : widen_down(std::atan(x.lo()));
  const double hi = x.hi() == kInf ? lim : widen_up(std::atan(x.hi()));
  return Interval(std::max(lo, -lim), std::min(hi, lim));
}

Interval abs(const Interval& x) {
  if (x.is_empty()) return x;
  if (x.lo() >= 0.0) return x;
  if (x.hi() <= 0.0) return -x;
  return Interval::raw(0.0, std::max(-x.lo(), x.hi()));
}

Interval min(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  return Interval::raw(std::min(a.lo(), b.lo()), std::min(a.hi(), b.hi()));
}

Interval max(const Interval& a, const Interval& b) {
  if (a.is_empty() || b.is_empty()) return Interval::empty();
  return Interval::raw(std::max(a.lo(), b.lo()), std::max(a.hi(), b.hi()));
}

Interval pow_real(const Interval& x, const Interval& y, Domain* dom) {
  if (x.is_empty() || y.is_empty()) return Interval::empty();
  if (x.hi() < 0.0 || (x.hi() == 0.0 && y.hi() <= 0.0)) {
    *dom = Domain::kPartial;
    return Interval::empty();
  }
  double x0 = x.lo();
  if (x0 < 0.0) {
    *dom = Domain::kPartial;
    x0 = 0.0;
  }
  if (x0 == 0.0 && y.lo() <= 0.0) *dom = Domain::kPartial;  // pole or 0^0 at the boundary
  // x^y is monotone in x for fixed y and in y for fixed x, so its extremes over the box lie at
  // the four corners (0^y is 0 for y > 0, 1 at y = 0, +inf for y < 0: also monotone in y).
  // Signed zeros matter to std::pow (pow(-0, -1) = -inf): use +0.
  if (x0 == 0.0) x0 = 0.0;
  const double xs[2] = {x0, x.hi() == 0.0 ? 0.0 : x.hi()};
  const double ys[2] = {y.lo(), y.hi()};
  double lo = kInf, hi = -kInf;
  {
    const LibmNearest nearest;
    for (double xv : xs) {
      for (double yv : ys) {
        if (!std::isfinite(yv)) {  // unbounded exponent: anything from 0 to inf
          lo = std::min(lo, 0.0);
          hi = kInf;
          continue;
        }
        const double v = std::pow(xv, yv);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  // An overflow (std::pow = inf) is a finite real above DBL_MAX: the lower bound stays finite.
  return Interval(std::clamp(widen_down(lo), 0.0, DBL_MAX), widen_up(hi));
}

}  // namespace iaa
