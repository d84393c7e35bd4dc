// Batched interval evaluation (eval_batch.h). Each fast rule below works on the K lanes of a slot,
// W at a time in one vector of GCC's and Clang's vector extension, and computes the bounds with
// the expressions of core/interval.h in the same order, so that each lane rounds exactly as the
// scalar operation does. It also computes, per lane, whether the scalar operation would have left
// its fast path there (an empty or unbounded argument, a NaN bound), and for such an operation,
// rare, the lanes in use are recomputed with the scalar rule. The same loop is compiled twice:
// for the baseline (SSE2, W = 2) and, chosen at run time, for AVX2 (W = 4); neither uses FMA (no
// contraction may change a bound). -frounding-math (iaa_options) keeps the bound expressions as
// written, as it does in interval.h. (Plain loops over the lanes left to the auto-vectorizer
// stayed mostly scalar: docs/eval.md, "The batched interval evaluator".)
#include "expr/eval_batch.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "core/error.h"
#include "expr/eval_interval.h"

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

namespace iaa {

namespace {

bool cpu_has_avx2() {
#if IAA_BATCH_AVX2
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

/// W doubles in one vector (GCC's and Clang's vector extension): 2 is an SSE2 register, 4 an
/// AVX2 one. Each operator works lane by lane with the IEEE operation of its scalar form, in the
/// current rounding mode, so a lane's result is the double the scalar expression gives.
template <int W>
struct VectorTypes;
template <>
struct VectorTypes<2> {
  typedef double V __attribute__((vector_size(16)));
  typedef std::int64_t M __attribute__((vector_size(16)));  ///< comparison results: 0 or -1
};
template <>
struct VectorTypes<4> {
  typedef double V __attribute__((vector_size(32)));
  typedef std::int64_t M __attribute__((vector_size(32)));
};

template <int W>
struct Lanes {
  using V = typename VectorTypes<W>::V;
  using M = typename VectorTypes<W>::M;

  static IAA_ALWAYS_INLINE V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static IAA_ALWAYS_INLINE void store(double* p, const V& v) { std::memcpy(p, &v, sizeof v); }
  static IAA_ALWAYS_INLINE V splat(double x) {
    V v;
    for (int j = 0; j < W; ++j) v[j] = x;
    return v;
  }
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
};

}  // namespace

template <int K>
BatchIntervalEvalK<K>::BatchIntervalEvalK(const Tape& tape)
    : tape_(&tape), slots_(static_cast<std::size_t>(tape.size())) {
  const auto consts = tape.constants();
  for (int i = 3; i < tape.first_op(); ++i) {
    const Interval c(consts[static_cast<std::size_t>(i)]);
    Slot& s = slots_[static_cast<std::size_t>(i)];
    for (int j = 0; j < K; ++j) {
      s.lo[j] = c.lo();
      s.hi[j] = c.hi();
    }
  }
  use_avx2_ = cpu_has_avx2();
}

template <int K>
const char* BatchIntervalEvalK<K>::isa() const {
  return use_avx2_ ? "avx2" : "sse2";
}

template <int K>
void BatchIntervalEvalK<K>::use_baseline(bool baseline) {
  use_avx2_ = !baseline && cpu_has_avx2();
}

template <int K>
void BatchIntervalEvalK<K>::eval(const IBox* boxes, int n, Interval* out) {
  IAA_CHECK(n >= 1 && n <= K);
  for (int v = 0; v < 3; ++v) {
    Slot& s = slots_[static_cast<std::size_t>(v)];
    for (int j = 0; j < K; ++j) {
      const Interval& x = boxes[j < n ? j : 0][v];
      s.lo[j] = x.lo();
      s.hi[j] = x.hi();
    }
  }
  std::fill(partial_, partial_ + K, std::uint8_t{0});
  if (rounding_is_upward()) [[likely]] {
    run(n);
  } else {
    RoundingScope scope;
    run(n);
  }
  const Slot& r = slots_[static_cast<std::size_t>(tape_->root())];
  for (int j = 0; j < n; ++j) out[j] = Interval::raw(r.lo[j], r.hi[j]);
}

template <int K>
void BatchIntervalEvalK<K>::run(int n) {
#if IAA_BATCH_AVX2
  if (use_avx2_) {
    run_avx2(n);
    return;
  }
#endif
  run_baseline(n);
}

template <int K>
void BatchIntervalEvalK<K>::fill_unused(int i, int n) {
  Slot& s = slots_[static_cast<std::size_t>(i)];
  for (int j = n; j < K; ++j) {
    s.lo[j] = s.lo[0];
    s.hi[j] = s.hi[0];
  }
}

template <int K>
void BatchIntervalEvalK<K>::scalar_op(int i, int j) {
  using R = detail::IntervalRules;
  const Instr& in = tape_->instrs()[static_cast<std::size_t>(i)];
  const double* k = tape_->constants().data();
  const auto lane = [&](int slot) {
    const Slot& s = slots_[static_cast<std::size_t>(slot)];
    return Interval::raw(s.lo[j], s.hi[j]);
  };
  const Interval a = lane(in.a);
  Domain dom = Domain::kFull;
  std::uint8_t choice = 0;
  Interval r;
  switch (in.op) {
    case Op::kAdd:
      r = R::add(a, lane(in.b));
      break;
    case Op::kSub:
      r = R::sub(a, lane(in.b));
      break;
    case Op::kMul:
      r = R::mul(a, lane(in.b));
      break;
    case Op::kScale:
      r = R::scale(a, k[in.b]);
      break;
    case Op::kDiv:
      r = R::div(a, lane(in.b), &dom);
      break;
    case Op::kDivConst:
      r = R::div_const(a, k[in.b]);
      break;
    case Op::kNeg:
      r = R::neg(a);
      break;
    case Op::kPowInt:
      r = R::pow_int(a, in.power);
      break;
    case Op::kPow:
      r = R::pow(a, lane(in.b), &dom);
      break;
    case Op::kSquare:
      r = R::square(a);
      break;
    case Op::kSqrt:
      r = R::sqrt(a, &dom);
      break;
    case Op::kExp:
      r = R::exp(a);
      break;
    case Op::kLog:
      r = R::log(a, &dom);
      break;
    case Op::kSin:
      r = R::sin(a);
      break;
    case Op::kCos:
      r = R::cos(a);
      break;
    case Op::kSinCos: {
      const auto [sv, cv] = R::sincos(a);
      r = sv;
      Slot& c = slots_[static_cast<std::size_t>(i) + 1];
      c.lo[j] = cv.lo();
      c.hi[j] = cv.hi();
      break;
    }
    case Op::kTan:
      r = R::tan(a, &dom);
      break;
    case Op::kAtan:
      r = R::atan(a);
      break;
    case Op::kAbs:
      r = R::abs(a);
      break;
    case Op::kMin:
      r = R::min(a, lane(in.b), &choice);
      break;
    case Op::kMax:
      r = R::max(a, lane(in.b), &choice);
      break;
    case Op::kPairedCos:
    case Op::kVarX:
    case Op::kVarY:
    case Op::kVarZ:
    case Op::kConst:
      return;  // written by the sincos before it, or never after first_op
  }
  if (dom == Domain::kPartial) partial_[j] = 1;
  Slot& o = slots_[static_cast<std::size_t>(i)];
  o.lo[j] = r.lo();
  o.hi[j] = r.hi();
}

template <int K>
template <int W>
IAA_ALWAYS_INLINE void BatchIntervalEvalK<K>::run_impl(int n) {
  using L = Lanes<W>;
  using V = typename L::V;
  using M = typename L::M;
  Slot* s = slots_.data();
  const Instr* ins = tape_->instrs().data();
  const double* k = tape_->constants().data();
  const int size = tape_->size();
  const V zero = L::splat(0.0);
  for (int i = tape_->first_op(); i < size; ++i) {
    const Instr& in = ins[i];
    const double* al = s[in.a].lo;
    const double* ah = s[in.a].hi;
    // For unary operations b is slot 0 (never read); for scale and divc a constant's slot.
    const Slot& sb = s[in.b >= 0 ? in.b : 0];
    const double* bl = sb.lo;
    const double* bh = sb.hi;
    double* ol = s[i].lo;
    double* oh = s[i].hi;
    // Lanes a fast rule flags (any lane; the unused ones copy lane 0) send the operation to the
    // scalar rule for the lanes in use, after which the unused lanes take lane 0's result again.
    M bad = M{} != M{};  // all clear
    // Runs `rule(c)` for each group of W lanes starting at lane c.
    const auto each = [&](auto rule) __attribute__((always_inline)) {
      for (int c = 0; c < K; c += W) rule(c);
    };
    switch (in.op) {
      case Op::kAdd:
        each([&](int c) __attribute__((always_inline)) {
          const V lo = -((-L::load(al + c)) - L::load(bl + c));
          const V hi = L::load(ah + c) + L::load(bh + c);
          L::store(ol + c, lo);
          L::store(oh + c, hi);
          bad |= ~(lo <= hi);  // operator+: an empty argument or a NaN bound
        });
        break;
      case Op::kSub:
        each([&](int c) __attribute__((always_inline)) {
          const V lo = -(L::load(bh + c) - L::load(al + c));
          const V hi = L::load(ah + c) - L::load(bl + c);
          L::store(ol + c, lo);
          L::store(oh + c, hi);
          bad |= ~(lo <= hi);
        });
        break;
      case Op::kMul:
        each([&](int c) __attribute__((always_inline)) {
          const V a0 = L::load(al + c), a1 = L::load(ah + c);
          const V b0 = L::load(bl + c), b1 = L::load(bh + c);
          // operator*: finite bounds, else detail::mul_general.
          bad |= L::not_finite(a0) | L::not_finite(a1) | L::not_finite(b0) | L::not_finite(b1);
          L::store(oh + c, L::max(L::max(a0 * b0, a0 * b1), L::max(a1 * b0, a1 * b1)));
          const V n0 = -a0, n1 = -a1;
          L::store(ol + c, -L::max(L::max(n0 * b0, n0 * b1), L::max(n1 * b0, n1 * b1)));
        });
        break;
      case Op::kScale: {
        // iaa::scale: no tests; empty and unbounded arguments come out as they do there.
        const double cv = k[in.b];
        const V cc = L::splat(cv);
        const double* l = cv > 0.0 ? al : ah;
        const double* h = cv > 0.0 ? ah : al;
        each([&](int c) __attribute__((always_inline)) {
          L::store(ol + c, -((-L::load(l + c)) * cc));
          L::store(oh + c, L::load(h + c) * cc);
        });
        break;
      }
      case Op::kDivConst: {
        const double cv = k[in.b];
        const V cc = L::splat(cv);
        const double* l = cv > 0.0 ? al : ah;
        const double* h = cv > 0.0 ? ah : al;
        each([&](int c) __attribute__((always_inline)) {
          L::store(ol + c, -((-L::load(l + c)) / cc));
          L::store(oh + c, L::load(h + c) / cc);
        });
        break;
      }
      case Op::kDiv:
        // iaa::divide's inline path: non-empty arguments, a divisor that excludes 0, and no NaN
        // quotient (inf / inf), which Interval(lo, hi) would make infinite.
        each([&](int c) __attribute__((always_inline)) {
          const V a0 = L::load(al + c), a1 = L::load(ah + c);
          const V b0 = L::load(bl + c), b1 = L::load(bh + c);
          const M neg = b1 < zero;
          const V nl = neg ? -a1 : a0, nh = neg ? -a0 : a1;
          const V dl = neg ? -b1 : b0, dh = neg ? -b0 : b1;
          const V lo = -((-nl) / ((nl >= zero) ? dh : dl));
          const V hi = nh / ((nh >= zero) ? dl : dh);
          L::store(ol + c, lo);
          L::store(oh + c, hi);
          bad |= ~(a0 <= a1) | ~(b0 <= b1) | ((b0 <= zero) & (zero <= b1)) | ~(lo <= hi);
        });
        break;
      case Op::kNeg:
        // -a, empty included: (-(-inf), -(+inf)) is the empty interval again.
        each([&](int c) __attribute__((always_inline)) {
          L::store(ol + c, -L::load(ah + c));
          L::store(oh + c, -L::load(al + c));
        });
        break;
      case Op::kSquare:
        each([&](int c) __attribute__((always_inline)) {
          // detail::abs_range, then iaa::square's two products; an empty argument is returned
          // as it is (the scalar rule).
          const V l = L::load(al + c), h = L::load(ah + c);
          const V big = L::max(-l, h), small = L::max(zero, L::max(l, -h));
          L::store(ol + c, -((-small) * small));
          L::store(oh + c, big * big);
          bad |= l > h;
        });
        break;
      case Op::kPowInt: {
        // iaa::pow_int: n is the same in every lane, so its cases are chosen once.
        const int p = in.power;
        each([&](int c) __attribute__((always_inline)) {
          const V l = L::load(al + c), h = L::load(ah + c);
          bad |= l > h;  // empty: returned as it is
          V lo, hi;
          if (p == 0) {
            lo = hi = L::splat(1.0);
          } else if (p == 1) {
            lo = l;
            hi = h;
          } else if (p == 2) {
            const V big = L::max(-l, h), small = L::max(zero, L::max(l, -h));
            lo = -((-small) * small);
            hi = big * big;
          } else if (p & 1) {
            // Increasing: each end's power rounded its way, through |end| where the end is < 0.
            const V lp = L::pow_down(l, p), ln = -L::pow_up(-l, p);
            const V hp = L::pow_up(h, p), hn = -L::pow_down(-h, p);
            lo = (l >= zero) ? lp : ln;
            hi = (h >= zero) ? hp : hn;
          } else {
            const V big = L::max(-l, h), small = L::max(zero, L::max(l, -h));
            lo = L::pow_down(small, p);
            hi = L::pow_up(big, p);
          }
          L::store(ol + c, lo);
          L::store(oh + c, hi);
        });
        break;
      }
      case Op::kAbs:
        // iaa::abs: x where lo >= 0, -x where hi <= 0, else [0, max(-lo, hi)].
        each([&](int c) __attribute__((always_inline)) {
          const V l = L::load(al + c), h = L::load(ah + c);
          const M pos = l >= zero, nonpos = h <= zero;
          L::store(ol + c, pos ? l : (nonpos ? -h : zero));
          L::store(oh + c, pos ? h : (nonpos ? -l : L::max(-l, h)));
          bad |= l > h;
        });
        break;
      case Op::kMin:
        each([&](int c) __attribute__((always_inline)) {
          const V a0 = L::load(al + c), a1 = L::load(ah + c);
          const V b0 = L::load(bl + c), b1 = L::load(bh + c);
          L::store(ol + c, L::min(a0, b0));
          L::store(oh + c, L::min(a1, b1));
          bad |= (a0 > a1) | (b0 > b1);  // an empty argument gives empty
        });
        break;
      case Op::kMax:
        each([&](int c) __attribute__((always_inline)) {
          const V a0 = L::load(al + c), a1 = L::load(ah + c);
          const V b0 = L::load(bl + c), b1 = L::load(bh + c);
          L::store(ol + c, L::max(a0, b0));
          L::store(oh + c, L::max(a1, b1));
          bad |= (a0 > a1) | (b0 > b1);
        });
        break;
      case Op::kSinCos:
        for (int j = 0; j < n; ++j) scalar_op(i, j);
        fill_unused(i, n);
        fill_unused(i + 1, n);
        break;
      case Op::kPairedCos:
      case Op::kVarX:
      case Op::kVarY:
      case Op::kVarZ:
      case Op::kConst:
        break;  // written by the sincos before it, or never after first_op
      default:
        // sqrt, exp, log, sin, cos, tan, atan, the real power: the scalar rule in each lane.
        bad = M{} == M{};
        break;
    }
    if (L::any(bad)) [[unlikely]] {
      for (int j = 0; j < n; ++j) scalar_op(i, j);
      fill_unused(i, n);
    }
  }
}

template <int K>
void BatchIntervalEvalK<K>::run_baseline(int n) {
  run_impl<2>(n);
}

template <int K>
IAA_TARGET_AVX2 void BatchIntervalEvalK<K>::run_avx2(int n) {
  run_impl<(K < 4 ? K : 4)>(n);
}

template class BatchIntervalEvalK<2>;
template class BatchIntervalEvalK<4>;
template class BatchIntervalEvalK<8>;
template class BatchIntervalEvalK<16>;

}  // namespace iaa
