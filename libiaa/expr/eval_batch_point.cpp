// Batched point evaluation (eval_batch_point.h). Each operation runs over the K lanes of a slot,
// W at a time in one vector, with PointRules' expressions written for vectors; the operations
// without a vector form run PointRules lane by lane. The same loop is compiled for the baseline
// (SSE2, W = 2) and, chosen at run time, for AVX2 (W = 4), as in eval_batch.cpp.
#include "expr/eval_batch_point.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "core/elementary.h"
#include "core/error.h"
#include "expr/batch_lanes.h"
#include "expr/eval_point.h"

namespace iaa {

namespace {

/// elementary::sincos over W lanes, for |x| <= kTrigMax in every lane (the caller checks): the
/// reduction and both polynomials of batch_lanes.h (the kernels' operations in the same order on
/// each lane, so the same doubles), then sin_of's selection by the bits of k.
template <int W>
IAA_ALWAYS_INLINE void sin_cos_lanes(typename detail::batch::Lanes<W>::V x,
                                     typename detail::batch::Lanes<W>::V* sin_x,
                                     typename detail::batch::Lanes<W>::V* cos_x) {
  using L = detail::batch::Lanes<W>;
  const typename L::Trig t = L::reduce_sin_cos(x);
  *sin_x = L::sin_of(t.k, t.s, t.c);
  *cos_x = L::sin_of(t.k + 1, t.s, t.c);
}

}  // namespace

double point_lane_by_lane_share(const Tape& tape) {
  int ops = 0, slow = 0;
  const auto ins = tape.instrs();
  for (int i = tape.first_op(); i < tape.size(); ++i) {
    const Op op = ins[static_cast<std::size_t>(i)].op;
    if (op == Op::kPairedCos) continue;
    ++ops;
    switch (op) {  // the operations BatchPointEvalK runs in vectors
      case Op::kAdd:
      case Op::kSub:
      case Op::kMul:
      case Op::kScale:
      case Op::kDivConst:
      case Op::kDiv:
      case Op::kNeg:
      case Op::kSquare:
      case Op::kAbs:
      case Op::kPowInt:
      case Op::kMin:
      case Op::kMax:
      case Op::kExp:
      case Op::kSin:
      case Op::kCos:
      case Op::kSinCos:
        break;
      default:
        ++slow;
        break;
    }
  }
  return ops > 0 ? double(slow) / ops : 0.0;
}

template <int K>
BatchPointEvalK<K>::BatchPointEvalK(const Tape& tape)
    : tape_(&tape), slots_(static_cast<std::size_t>(tape.size())) {
  const auto consts = tape.constants();
  for (int i = 3; i < tape.first_op(); ++i) {
    Slot& s = slots_[static_cast<std::size_t>(i)];
    for (int j = 0; j < K; ++j) s.v[j] = consts[static_cast<std::size_t>(i)];
  }
}

template <int K>
void BatchPointEvalK<K>::eval(const Vec3* points, int n, double* out) {
  IAA_CHECK(n >= 1 && n <= K);
  for (int v = 0; v < 3; ++v) {
    Slot& s = slots_[static_cast<std::size_t>(v)];
    for (int j = 0; j < K; ++j) s.v[j] = points[j < n ? j : 0][v];
  }
  detail::batch::Runner::run(*this, use_avx2_, n);
  const Slot& r = slots_[static_cast<std::size_t>(tape_->root())];
  for (int j = 0; j < n; ++j) out[j] = r.v[j];
}

template <int K>
void BatchPointEvalK<K>::fill_unused(int i, int n) {
  Slot& s = slots_[static_cast<std::size_t>(i)];
  for (int j = n; j < K; ++j) s.v[j] = s.v[0];
}

template <int K>
void BatchPointEvalK<K>::scalar_op(int i, int j) {
  const auto arg = [&](int t) { return slots_[static_cast<std::size_t>(t)].v[j]; };
  const auto put = [&](int next, double r) { slots_[static_cast<std::size_t>(i + next)].v[j] = r; };
  Domain dom = Domain::kFull;  // PointRules mark nothing: an undefined value is NaN
  detail::batch::scalar_rule<detail::PointRules>(tape_->instrs()[static_cast<std::size_t>(i)],
                                                 tape_->constants().data(), arg, put, &dom);
}

template <int K>
template <int W>
IAA_ALWAYS_INLINE void BatchPointEvalK<K>::run_impl(int n) {
  using L = detail::batch::Lanes<W>;
  using V = typename L::V;
  using M = typename L::M;
  Slot* s = slots_.data();
  const Instr* ins = tape_->instrs().data();
  const double* k = tape_->constants().data();
  const int size = tape_->size();
  for (int i = tape_->first_op(); i < size; ++i) {
    const Instr& in = ins[i];
    const Slot& sa = s[in.a];
    const Slot& sb = s[in.b >= 0 ? in.b : 0];  // slot 0 for unary operations (never read)
    Slot& so = s[i];
    // Runs `rule(a, b)` for each group of W lanes and stores its result.
    const auto each = [&](auto rule) __attribute__((always_inline)) {
      for (int c = 0; c < K; c += W) L::store(so.v + c, rule(L::load(sa.v + c), L::load(sb.v + c)));
    };
    switch (in.op) {
      case Op::kAdd:
        each([](V a, V b) __attribute__((always_inline)) { return a + b; });
        break;
      case Op::kSub:
        each([](V a, V b) __attribute__((always_inline)) { return a - b; });
        break;
      case Op::kMul:
        each([](V a, V b) __attribute__((always_inline)) { return a * b; });
        break;
      case Op::kScale: {
        const V c = L::splat(k[in.b]);
        each([c](V a, V) __attribute__((always_inline)) { return a * c; });
        break;
      }
      case Op::kDivConst: {
        const V c = L::splat(k[in.b]);
        each([c](V a, V) __attribute__((always_inline)) { return a / c; });
        break;
      }
      case Op::kDiv: {
        // PointRules::div: a pole (b == 0) is NaN, not IEEE's infinity.
        const V nan = L::splat(std::numeric_limits<double>::quiet_NaN()), zero = L::splat(0.0);
        each([&](V a, V b) __attribute__((always_inline)) {
          const M pole = b == zero;
          return pole ? nan : a / b;
        });
        break;
      }
      case Op::kNeg:
        each([](V a, V) __attribute__((always_inline)) { return -a; });
        break;
      case Op::kSquare:
        each([](V a, V) __attribute__((always_inline)) { return a * a; });
        break;
      case Op::kAbs:
        each([](V a, V) __attribute__((always_inline)) { return L::fabs(a); });
        break;
      case Op::kPowInt: {
        // PointRules::pow_int: binary powering of |a| in the interval rule's order, the sign
        // put back for odd powers of negative a; a^0 = 1 where a is not NaN.
        const int p = in.power;
        const V one = L::splat(1.0), zero = L::splat(0.0);
        if (p == 0) {
          each([&](V a, V) __attribute__((always_inline)) {
            const M defined = a == a;
            return defined ? one : a;
          });
          break;
        }
        each([&](V a, V) __attribute__((always_inline)) {
          V x = L::fabs(a);
          V y = (p & 1) ? x : one;
          for (int q = p >> 1; q > 0; q >>= 1) {
            x = x * x;
            if (q & 1) y = x * y;
          }
          if (!(p & 1)) return y;
          const M negative = a < zero;
          return negative ? -y : y;
        });
        break;
      }
      case Op::kMin:
        // (b < a || b != b) ? b : a: a NaN argument gives NaN.
        each([](V a, V b) __attribute__((always_inline)) {
          const M take_b = (b < a) | (b != b);
          return take_b ? b : a;
        });
        break;
      case Op::kMax:
        each([](V a, V b) __attribute__((always_inline)) {
          const M take_b = (b > a) | (b != b);
          return take_b ? b : a;
        });
        break;
      case Op::kSin:
      case Op::kCos:
      case Op::kSinCos: {
        // The kernels of elementary.h where every lane is in their range (libm beyond it, as
        // PointRules): sin, cos, or both into this slot and the paired cos after it.
        const V big = L::splat(elementary::kTrigMax);
        M out = L::none();
        for (int c = 0; c < K; c += W) out |= ~(L::fabs(L::load(sa.v + c)) <= big);
        if (L::any(out)) {
          detail::batch::Runner::scalar_lanes(*this, in, i, n);
          break;
        }
        for (int c = 0; c < K; c += W) {
          V sv, cv;
          sin_cos_lanes<W>(L::load(sa.v + c), &sv, &cv);
          if (in.op == Op::kCos) {
            L::store(so.v + c, cv);
          } else {
            L::store(so.v + c, sv);
            if (in.op == Op::kSinCos) L::store(s[i + 1].v + c, cv);
          }
        }
        break;
      }
      case Op::kExp: {
        // The kernel where every lane is in its range (libm beyond it, as PointRules).
        M ok = L::all();
        for (int c = 0; c < K; c += W) ok &= L::exp_in_range(L::load(sa.v + c));
        if (L::any(~ok)) {
          detail::batch::Runner::scalar_lanes(*this, in, i, n);
          break;
        }
        each([](V a, V) __attribute__((always_inline)) { return L::exp_kernel(a); });
        break;
      }
      case Op::kPairedCos:
        break;  // written by the sincos before it
      default:
        // sqrt, log, tan, atan, the real power: PointRules in each lane.
        detail::batch::Runner::scalar_lanes(*this, in, i, n);
        break;
    }
  }
}

template class BatchPointEvalK<4>;
template class BatchPointEvalK<8>;
template class BatchPointEvalK<16>;

}  // namespace iaa
