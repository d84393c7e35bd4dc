// The vector half of the batched evaluators (eval_batch.cpp, eval_batch_grad.cpp): W doubles in
// one vector of GCC's and Clang's vector extension, and the fast interval rules over W lanes at a
// time. Each rule computes the bounds with the expressions of core/interval.h in the same order,
// so that each lane rounds exactly as the scalar operation does, and sets, per lane, `bad` where
// the scalar operation would have left its fast path (an empty or unbounded argument, a NaN
// bound): the evaluator then recomputes the operation with the scalar rule. Never FMA (no
// contraction may change a bound); -frounding-math (iaa_options) keeps the expressions as written.
//
// Internal to libiaa/expr: everything here is forced inline, so that the loops that use it are
// compiled once per instruction set (the baseline, and an AVX2 copy chosen at run time) and no
// 32-byte vector crosses a call (see -Wno-psabi in CMakeLists.txt).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

#include "core/elementary.h"
#include "core/error.h"
#include "core/interval.h"
#include "core/vec.h"
#include "expr/tape.h"

#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define IAA_BATCH_AVX2 1
#define IAA_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define IAA_BATCH_AVX2 0
#define IAA_TARGET_AVX2
#endif

#if defined(__GNUC__) || defined(__clang__)
#define IAA_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define IAA_ALWAYS_INLINE inline
#endif

namespace iaa::detail::batch {

/// True where the processor runs AVX2 code.
inline bool cpu_has_avx2() {
#if IAA_BATCH_AVX2
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

/// W doubles in one vector: 2 is an SSE2 register, 4 an AVX2 one. Each operator works lane by
/// lane with the IEEE operation of its scalar form, in the current rounding mode, so a lane's
/// result is the double the scalar expression gives.
template <int W>
struct VectorTypes;
template <>
struct VectorTypes<2> {
  typedef double V __attribute__((vector_size(16)));
  typedef std::int64_t M __attribute__((vector_size(16)));   ///< comparison results: 0 or -1
  typedef std::int32_t K32 __attribute__((vector_size(8)));  ///< quadrants of the trig rules
};
template <>
struct VectorTypes<4> {
  typedef double V __attribute__((vector_size(32)));
  typedef std::int64_t M __attribute__((vector_size(32)));
  typedef std::int32_t K32 __attribute__((vector_size(16)));  ///< quadrants of the trig rules
};

template <int W>
struct Lanes {
  using V = typename VectorTypes<W>::V;
  using M = typename VectorTypes<W>::M;
  /// W intervals: their lower and their upper bounds.
  struct I {
    V lo, hi;
  };

  static IAA_ALWAYS_INLINE V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static IAA_ALWAYS_INLINE void store(double* p, const V& v) { std::memcpy(p, &v, sizeof v); }
  /// The intervals of lanes c..c+W-1 of bound arrays lo and hi, and back.
  static IAA_ALWAYS_INLINE I load(const double* lo, const double* hi, int c) {
    return {load(lo + c), load(hi + c)};
  }
  static IAA_ALWAYS_INLINE void store(double* lo, double* hi, int c, const I& x) {
    store(lo + c, x.lo);
    store(hi + c, x.hi);
  }
  static IAA_ALWAYS_INLINE V splat(double x) {
    V v;
    for (int j = 0; j < W; ++j) v[j] = x;
    return v;
  }
  static IAA_ALWAYS_INLINE M none() { return M{} != M{}; }
  static IAA_ALWAYS_INLINE M all() { return M{} == M{}; }
  /// std::max(a, b) and std::min(a, b) lane by lane: (a < b) ? b : a and (b < a) ? b : a.
  static IAA_ALWAYS_INLINE V max(V a, V b) { return (a < b) ? b : a; }
  static IAA_ALWAYS_INLINE V min(V a, V b) { return (b < a) ? b : a; }
  /// True when a lane of m is set.
  static IAA_ALWAYS_INLINE bool any(M m) {
    std::int64_t r = 0;
    for (int j = 0; j < W; ++j) r |= m[j];
    return r != 0;
  }
  /// Set where a bound is infinite or NaN: detail::all_finite's test, lane by lane.
  static IAA_ALWAYS_INLINE M not_finite(V x) {
    const V big = splat(std::numeric_limits<double>::max());
    return ~((x <= big) & (-big <= x));
  }
  /// detail::pow_up lane by lane: x^n rounded up, its products in its order (n >= 1).
  static IAA_ALWAYS_INLINE V pow_up(V x, int n) {
    V y = (n & 1) ? x : splat(1.0);
    for (int p = n >> 1; p > 0; p >>= 1) {
      x = x * x;
      if (p & 1) y = x * y;
    }
    return y;
  }
  /// detail::pow_down lane by lane: x^n rounded down (n >= 1).
  static IAA_ALWAYS_INLINE V pow_down(V x, int n) {
    V y = (n & 1) ? x : splat(1.0);
    for (int p = n >> 1; p > 0; p >>= 1) {
      x = -((-x) * x);
      if (p & 1) y = -((-x) * y);
    }
    return y;
  }

  // The fast interval rules. `bad` gains the lanes where the scalar operation leaves the
  // expressions below (its fast path); the rules without `bad` have no such lanes.

  /// operator+: an empty argument or a NaN bound fails lo <= hi.
  static IAA_ALWAYS_INLINE I add(const I& a, const I& b, M& bad) {
    const I r{-((-a.lo) - b.lo), a.hi + b.hi};
    bad |= ~(r.lo <= r.hi);
    return r;
  }
  /// operator-(a, b).
  static IAA_ALWAYS_INLINE I sub(const I& a, const I& b, M& bad) {
    const I r{-(b.hi - a.lo), a.hi - b.lo};
    bad |= ~(r.lo <= r.hi);
    return r;
  }
  /// operator*: finite bounds, else detail::mul_general.
  static IAA_ALWAYS_INLINE I mul(const I& a, const I& b, M& bad) {
    bad |= not_finite(a.lo) | not_finite(a.hi) | not_finite(b.lo) | not_finite(b.hi);
    const V hi = max(max(a.lo * b.lo, a.lo * b.hi), max(a.hi * b.lo, a.hi * b.hi));
    const V n0 = -a.lo, n1 = -a.hi;
    const V lo = -max(max(n0 * b.lo, n0 * b.hi), max(n1 * b.lo, n1 * b.hi));
    return {lo, hi};
  }
  /// iaa::scale(a, c), c finite and non-zero: no tests; empty and unbounded arguments come out
  /// as they do there.
  static IAA_ALWAYS_INLINE I scale(const I& a, double c) {
    const V cc = splat(c);
    const V l = c > 0.0 ? a.lo : a.hi, h = c > 0.0 ? a.hi : a.lo;
    return {-((-l) * cc), h * cc};
  }
  /// iaa::div_const(a, c).
  static IAA_ALWAYS_INLINE I div_const(const I& a, double c) {
    const V cc = splat(c);
    const V l = c > 0.0 ? a.lo : a.hi, h = c > 0.0 ? a.hi : a.lo;
    return {-((-l) / cc), h / cc};
  }
  /// iaa::divide's inline path: non-empty arguments, a divisor that excludes 0, and no NaN
  /// quotient (inf / inf), which Interval(lo, hi) would make infinite.
  static IAA_ALWAYS_INLINE I div(const I& a, const I& b, M& bad) {
    const V zero = splat(0.0);
    const M neg = b.hi < zero;
    const V nl = neg ? -a.hi : a.lo, nh = neg ? -a.lo : a.hi;
    const V dl = neg ? -b.hi : b.lo, dh = neg ? -b.lo : b.hi;
    const I r{-((-nl) / ((nl >= zero) ? dh : dl)), nh / ((nh >= zero) ? dl : dh)};
    bad |= ~(a.lo <= a.hi) | ~(b.lo <= b.hi) | ((b.lo <= zero) & (zero <= b.hi)) | ~(r.lo <= r.hi);
    return r;
  }
  /// -a, empty included: (-(-inf), -(+inf)) is the empty interval again.
  static IAA_ALWAYS_INLINE I neg(const I& a) { return {-a.hi, -a.lo}; }
  /// detail::abs_range: the least and the greatest |x| over x.
  static IAA_ALWAYS_INLINE void abs_range(const I& x, V* small, V* big) {
    *big = max(-x.lo, x.hi);
    *small = max(splat(0.0), max(x.lo, -x.hi));
  }
  /// iaa::square; an empty argument (returned as it is there) is bad.
  static IAA_ALWAYS_INLINE I square(const I& x, M& bad) {
    V small, big;
    abs_range(x, &small, &big);
    bad |= x.lo > x.hi;
    return {-((-small) * small), big * big};
  }
  /// iaa::pow_int(x, p), p >= 0 the same in every lane, so its cases are chosen once; an empty
  /// argument (returned as it is there) is bad.
  static IAA_ALWAYS_INLINE I pow_int(const I& x, int p, M& bad) {
    bad |= x.lo > x.hi;
    if (p == 0) return {splat(1.0), splat(1.0)};
    if (p == 1) return x;
    V small, big;
    if (p == 2) {
      abs_range(x, &small, &big);
      return {-((-small) * small), big * big};
    }
    if (p & 1) {
      // Increasing: each end's power rounded its way, through |end| where the end is < 0.
      const V zero = splat(0.0);
      const V lp = pow_down(x.lo, p), ln = -pow_up(-x.lo, p);
      const V hp = pow_up(x.hi, p), hn = -pow_down(-x.hi, p);
      return {(x.lo >= zero) ? lp : ln, (x.hi >= zero) ? hp : hn};
    }
    abs_range(x, &small, &big);
    return {pow_down(small, p), pow_up(big, p)};
  }
  /// iaa::abs: x where lo >= 0, -x where hi <= 0, else [0, max(-lo, hi)]; empty is bad.
  static IAA_ALWAYS_INLINE I abs(const I& x, M& bad) {
    const V zero = splat(0.0);
    const M pos = x.lo >= zero, nonpos = x.hi <= zero;
    bad |= x.lo > x.hi;
    return {pos ? x.lo : (nonpos ? -x.hi : zero), pos ? x.hi : (nonpos ? -x.lo : max(-x.lo, x.hi))};
  }
  /// iaa::min and iaa::max: an empty argument (which gives empty) is bad.
  static IAA_ALWAYS_INLINE I min(const I& a, const I& b, M& bad) {
    bad |= (a.lo > a.hi) | (b.lo > b.hi);
    return {min(a.lo, b.lo), min(a.hi, b.hi)};
  }
  static IAA_ALWAYS_INLINE I max(const I& a, const I& b, M& bad) {
    bad |= (a.lo > a.hi) | (b.lo > b.hi);
    return {max(a.lo, b.lo), max(a.hi, b.hi)};
  }

  /// The reduction of W arguments by pi/2 and sin and cos of the reduced ones
  /// (elementary::reduce_sin_cos_lanes over W lanes): the same doubles as the scalar kernels.
  struct Trig {
    V r, s, c;
    M k;
  };
  static IAA_ALWAYS_INLINE Trig reduce_sin_cos(V x) {
    namespace el = elementary;
    const V y = x * el::kTwoOverPi;
    // copysign(0.5, y) by the sign bit; the truncation to int32 (|k| < 2^20) is the kernels'.
    const V half = bits_to_v((v_to_bits(y) & splat_m(std::int64_t(0x8000000000000000ULL))) |
                             splat_m(std::bit_cast<std::int64_t>(0.5)));
    const typename VectorTypes<W>::K32 k =
        __builtin_convertvector(y + half, typename VectorTypes<W>::K32);
    const V kd = __builtin_convertvector(k, V);
    const V r = ((x - kd * el::kHalfPi1) - kd * el::kHalfPi2) - kd * el::kHalfPi3;
    return {r, el::sin_poly(r), el::cos_poly(r), __builtin_convertvector(k, M)};
  }
  /// elementary::sin_of lane by lane: c for odd k, s for even, the sign flipped for k = 2, 3
  /// mod 4.
  static IAA_ALWAYS_INLINE V sin_of(M k, V s, V c) {
    const M odd = M{} - (k & 1);
    return bits_to_v(((v_to_bits(c) & odd) | (v_to_bits(s) & ~odd)) ^ ((k & 2) << 62));
  }
  static IAA_ALWAYS_INLINE M v_to_bits(V v) {
    M m;
    std::memcpy(&m, &v, sizeof v);
    return m;
  }
  static IAA_ALWAYS_INLINE V bits_to_v(M m) {
    V v;
    std::memcpy(&v, &m, sizeof v);
    return v;
  }
  static IAA_ALWAYS_INLINE M splat_m(std::int64_t x) {
    M m;
    for (int j = 0; j < W; ++j) m[j] = x;
    return m;
  }
  /// std::fabs lane by lane: the sign bit cleared (a compare-and-negate would keep -0).
  static IAA_ALWAYS_INLINE V fabs(V v) {
    return bits_to_v(v_to_bits(v) & splat_m(std::numeric_limits<std::int64_t>::max()));
  }

  /// True in the lanes where |x| <= kExpMax (false for NaN): where exp is the kernel's.
  static IAA_ALWAYS_INLINE M exp_in_range(V x) { return fabs(x) <= splat(elementary::kExpMax); }
  /// elementary::exp_kernel lane by lane (the same doubles) where exp_in_range; the other lanes
  /// compute exp 0, so that no conversion to an integer overflows.
  static IAA_ALWAYS_INLINE V exp_kernel(V x) {
    using K32 = typename VectorTypes<W>::K32;
    return elementary::exp_kernel_lanes<V, K32, M>(exp_in_range(x) ? x : splat(0.0));
  }
  /// iaa::exp (interval.cpp) over W intervals with both ends in the kernel's range: each end's
  /// kernel value widened by its bound (interval.cpp's below and above, the same operations). An
  /// empty argument, an end beyond the range (glibc's exp there) or bounds that cross (which
  /// Interval(lo, hi) would make empty; never seen) are bad.
  static IAA_ALWAYS_INLINE I exp(const I& x, M& bad) {
    const V rel = splat(elementary::kRelErr), zero = splat(0.0);
    const V lo = exp_kernel(x.lo), hi = exp_kernel(x.hi);
    const I r{-((-lo) + (rel * fabs(lo) + zero)), hi + (rel * fabs(hi) + zero)};
    bad |= ~exp_in_range(x.lo) | ~exp_in_range(x.hi) | ~(x.lo <= x.hi) | ~(r.lo <= r.hi);
    return r;
  }

  /// iaa::sincos (interval.cpp's sincos_lanes) over W intervals: each end reduced, its sin and
  /// cos widened by the kernels' error bound, the lower of the two ends' lows and the higher
  /// high, then +-1 where a multiple of pi/2 with that value lies inside; the same operations in
  /// the same order, so the same bounds. An empty argument, or one that takes the whole range
  /// (unbounded, beyond the kernels' range or 2 pi wide), is bad.
  static IAA_ALWAYS_INLINE void sincos(const I& x, I* sin_x, I* cos_x, M& bad) {
    namespace el = elementary;
    const V big = splat(el::kTrigMax);
    bad |= (x.lo > x.hi) | ~((-big <= x.lo) & (x.hi <= big)) |
           (x.hi - x.lo >= splat(2.0 * std::numbers::pi));
    const Trig a = reduce_sin_cos(x.lo), b = reduce_sin_cos(x.hi);
    const auto abs_err = [&](const M& k) __attribute__((always_inline)) {
      const M k0 = k == M{};
      return bits_to_v((k0 & splat_m(std::bit_cast<std::int64_t>(0x1p-1070))) |
                       (~k0 & splat_m(std::bit_cast<std::int64_t>(el::kReducedAbsErr))));
    };
    const V abs_a = abs_err(a.k), abs_b = abs_err(b.k);
    const V rel = splat(el::kRelErr);
    const auto down_up = [&](V v, V abs, V * down, V * up) __attribute__((always_inline)) {
      const V err = rel * fabs(v) + abs;
      *down = -((-v) + err);
      *up = v + err;
    };
    // The multiples of pi/2 in [lo, hi]: first .. last.
    const V sure = splat(0x1p-90);
    const M first = (a.r > sure) ? a.k + 1 : a.k;
    const M last = (b.r < -sure) ? b.k - 1 : b.k;
    const M count = last - first + 1;
    const auto range = [&](int shift) __attribute__((always_inline)) {
      V da, ua, db, ub;
      down_up(sin_of(a.k + shift, a.s, a.c), abs_a, &da, &ua);
      down_up(sin_of(b.k + shift, b.s, b.c), abs_b, &db, &ub);
      V lo = min(da, db), hi = max(ua, ub);
      const M phase = first + shift;
      hi = (((1 - phase) & 3) < count) ? splat(1.0) : hi;
      lo = (((3 - phase) & 3) < count) ? splat(-1.0) : lo;
      return I{max(lo, splat(-1.0)), min(hi, splat(1.0))};
    };
    *sin_x = range(0);
    *cos_x = range(1);
  }
};

/// The scalar rule of instruction `in` (Rules: IntervalRules, IntervalGradRules) for one lane,
/// for what the fast rules do not cover: `arg(slot)` reads an argument's lane, `put(0, r)` writes
/// the result's (and `put(1, r)` the paired cos of a sincos); `m` is the output slot's mask for
/// the modes that use masks, as in TapeLoop.
template <class Rules, class Arg, class Put, class... Mask>
inline void scalar_rule(const Instr& in, const double* k, Arg arg, Put put, Domain* dom,
                        Mask... m) {
  const typename Rules::Num a = arg(in.a);
  std::uint8_t choice = 0;  // min/max choices are not recorded (eval_batch_grad.h)
  switch (in.op) {
    case Op::kAdd:
      return put(0, Rules::add(a, arg(in.b), m...));
    case Op::kSub:
      return put(0, Rules::sub(a, arg(in.b), m...));
    case Op::kMul:
      return put(0, Rules::mul(a, arg(in.b), m...));
    case Op::kScale:
      return put(0, Rules::scale(a, k[in.b], m...));
    case Op::kDiv:
      return put(0, Rules::div(a, arg(in.b), dom, m...));
    case Op::kDivConst:
      return put(0, Rules::div_const(a, k[in.b], m...));
    case Op::kNeg:
      return put(0, Rules::neg(a, m...));
    case Op::kPowInt:
      return put(0, Rules::pow_int(a, in.power, m...));
    case Op::kPow:
      return put(0, Rules::pow(a, arg(in.b), dom, m...));
    case Op::kSquare:
      return put(0, Rules::square(a, m...));
    case Op::kSqrt:
      return put(0, Rules::sqrt(a, dom, m...));
    case Op::kExp:
      return put(0, Rules::exp(a, m...));
    case Op::kLog:
      return put(0, Rules::log(a, dom, m...));
    case Op::kSin:
      return put(0, Rules::sin(a, m...));
    case Op::kCos:
      return put(0, Rules::cos(a, m...));
    case Op::kSinCos: {
      const auto [sv, cv] = Rules::sincos(a, m...);
      put(0, sv);
      return put(1, cv);  // the paired cos, with this slot's mask
    }
    case Op::kTan:
      return put(0, Rules::tan(a, dom, m...));
    case Op::kAtan:
      return put(0, Rules::atan(a, m...));
    case Op::kAbs:
      return put(0, Rules::abs(a, m...));
    case Op::kMin:
      return put(0, Rules::min(a, arg(in.b), &choice, m...));
    case Op::kMax:
      return put(0, Rules::max(a, arg(in.b), &choice, m...));
    case Op::kPairedCos:
    case Op::kVarX:
    case Op::kVarY:
    case Op::kVarZ:
    case Op::kConst:
      return;  // written by the sincos before it, or never after first_op
  }
}

/// Runs an evaluator's loop (its run_impl<W>, forced inline) with the baseline code or the AVX2
/// copy of it. The evaluators befriend it.
struct Runner {
  /// The start of an evaluation: loads the boxes (the unused lanes n..K-1 copy box 0) into the
  /// variables' value slots (`var(v)`, v = 0, 1, 2), clears the partial-domain flags and runs
  /// the loop, under upward rounding (opening a RoundingScope when the caller has none).
  template <class Eval, class Var>
  static void load_and_run(Eval& e, const IBox* boxes, int n, Var var) {
    constexpr int K = Eval::kLanes;
    IAA_CHECK(n >= 1 && n <= K);
    for (int v = 0; v < 3; ++v) {
      auto& s = var(v);
      for (int j = 0; j < K; ++j) {
        const Interval& x = boxes[j < n ? j : 0][v];
        s.lo[j] = x.lo();
        s.hi[j] = x.hi();
      }
    }
    for (int j = 0; j < K; ++j) e.partial_[j] = 0;
    if (rounding_is_upward()) [[likely]] {
      run(e, e.use_avx2_, n);
    } else {
      RoundingScope scope;
      run(e, e.use_avx2_, n);
    }
  }
  template <class Eval>
  static void run(Eval& e, bool avx2, int n) {
#if IAA_BATCH_AVX2
    if (avx2) return run_avx2(e, n);
#else
    (void)avx2;
#endif
    e.template run_impl<2>(n);
  }
  /// Runs instruction i's scalar rule in the lanes in use (an operation without a fast rule, or
  /// with flagged lanes), then copies lane 0 to the unused lanes (for a sincos, of its paired
  /// cos too), so that they compute what lane 0 does and never leave the fast rules.
  template <class Eval>
  static void scalar_lanes(Eval& e, const Instr& in, int i, int n) {
    for (int j = 0; j < n; ++j) e.scalar_op(i, j);
    e.fill_unused(i, n);
    if (in.op == Op::kSinCos) e.fill_unused(i + 1, n);
  }
  template <class Eval>
  IAA_TARGET_AVX2 static void run_avx2(Eval& e, int n) {
    e.template run_impl<(Eval::kLanes < 4 ? Eval::kLanes : 4)>(n);
  }
};

}  // namespace iaa::detail::batch
