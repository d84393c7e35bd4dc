// Batched interval evaluation (eval_batch.h). Each operation runs over the K lanes of a slot, W
// at a time in one vector, with the fast interval rules of batch_lanes.h (the expressions of
// core/interval.h in the same order, so that each lane rounds exactly as the scalar operation
// does). A rule also flags the lanes where the scalar operation would have left its fast path
// (an empty or unbounded argument, a NaN bound), and for such an operation, rare, the lanes in use
// are recomputed with the scalar rule. The same loop is compiled twice: for the baseline (SSE2,
// W = 2) and, chosen at run time, for AVX2 (W = 4). (Plain loops over the lanes left to the
// auto-vectorizer stayed mostly scalar: docs/eval.md, "The batched interval evaluator".)
#include "expr/eval_batch.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "core/error.h"
#include "expr/batch_lanes.h"
#include "expr/eval_interval.h"

namespace iaa {

namespace detail {

BatchIsa::BatchIsa() : use_avx2_(batch::cpu_has_avx2()) {}

void BatchIsa::use_baseline(bool baseline) {
  use_avx2_ = !baseline && batch::cpu_has_avx2();
}

}  // namespace detail

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
}

template <int K>
void BatchIntervalEvalK<K>::eval(const IBox* boxes, int n, Interval* out) {
  detail::batch::Runner::load_and_run(
      *this, boxes, n, [&](int v) -> Slot& { return slots_[static_cast<std::size_t>(v)]; });
  const Slot& r = slots_[static_cast<std::size_t>(tape_->root())];
  for (int j = 0; j < n; ++j) out[j] = Interval::raw(r.lo[j], r.hi[j]);
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
  const auto arg = [&](int t) {
    const Slot& s = slots_[static_cast<std::size_t>(t)];
    return Interval::raw(s.lo[j], s.hi[j]);
  };
  const auto put = [&](int next, const Interval& r) {
    Slot& o = slots_[static_cast<std::size_t>(i + next)];
    o.lo[j] = r.lo();
    o.hi[j] = r.hi();
  };
  Domain dom = Domain::kFull;
  detail::batch::scalar_rule<detail::IntervalRules>(tape_->instrs()[static_cast<std::size_t>(i)],
                                                    tape_->constants().data(), arg, put, &dom);
  if (dom == Domain::kPartial) partial_[j] = 1;
}

template <int K>
template <int W>
IAA_ALWAYS_INLINE void BatchIntervalEvalK<K>::run_impl(int n) {
  using L = detail::batch::Lanes<W>;
  using M = typename L::M;
  Slot* s = slots_.data();
  const Instr* ins = tape_->instrs().data();
  const double* k = tape_->constants().data();
  const int size = tape_->size();
  for (int i = tape_->first_op(); i < size; ++i) {
    const Instr& in = ins[i];
    const Slot& sa = s[in.a];
    // For unary operations b is slot 0 (never read); for scale and divc a constant's slot.
    const Slot& sb = s[in.b >= 0 ? in.b : 0];
    Slot& so = s[i];
    // Lanes a fast rule flags (any lane; the unused ones copy lane 0) send the operation to the
    // scalar rule for the lanes in use (Runner::scalar_lanes).
    M bad = L::none();
    // Runs `rule(a, b)` for each group of W lanes and stores its result.
    const auto each = [&](auto rule) __attribute__((always_inline)) {
      for (int c = 0; c < K; c += W) {
        L::store(so.lo, so.hi, c, rule(L::load(sa.lo, sa.hi, c), L::load(sb.lo, sb.hi, c)));
      }
    };
    using I = typename L::I;
    if (in.op == Op::kPairedCos) continue;  // written by the sincos before it
    switch (in.op) {
      case Op::kAdd:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::add(a, b, bad); });
        break;
      case Op::kSub:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::sub(a, b, bad); });
        break;
      case Op::kMul:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::mul(a, b, bad); });
        break;
      case Op::kScale:
        each([&](const I& a, const I&)
                 __attribute__((always_inline)) { return L::scale(a, k[in.b]); });
        break;
      case Op::kDivConst:
        each([&](const I& a, const I&)
                 __attribute__((always_inline)) { return L::div_const(a, k[in.b]); });
        break;
      case Op::kDiv:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::div(a, b, bad); });
        break;
      case Op::kNeg:
        each([&](const I& a, const I&) __attribute__((always_inline)) { return L::neg(a); });
        break;
      case Op::kSquare:
        each([&](const I& a, const I&)
                 __attribute__((always_inline)) { return L::square(a, bad); });
        break;
      case Op::kPowInt:
        each([&](const I& a, const I&)
                 __attribute__((always_inline)) { return L::pow_int(a, in.power, bad); });
        break;
      case Op::kAbs:
        each([&](const I& a, const I&) __attribute__((always_inline)) { return L::abs(a, bad); });
        break;
      case Op::kMin:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::min(a, b, bad); });
        break;
      case Op::kMax:
        each([&](const I& a, const I& b)
                 __attribute__((always_inline)) { return L::max(a, b, bad); });
        break;
      case Op::kExp:
        each([&](const I& a, const I&) __attribute__((always_inline)) { return L::exp(a, bad); });
        break;
      case Op::kSin:
      case Op::kCos:
      case Op::kSinCos:
        // sin, cos, or both into this slot and the paired cos after it.
        for (int c = 0; c < K; c += W) {
          I sv, cv;
          L::sincos(L::load(sa.lo, sa.hi, c), &sv, &cv, bad);
          if (in.op == Op::kCos) {
            L::store(so.lo, so.hi, c, cv);
          } else {
            L::store(so.lo, so.hi, c, sv);
            if (in.op == Op::kSinCos) L::store(s[i + 1].lo, s[i + 1].hi, c, cv);
          }
        }
        break;
      default:
        // sqrt, log, tan, atan, the real power: the scalar rule in each lane.
        bad = L::all();
        break;
    }
    if (L::any(bad)) [[unlikely]]
      detail::batch::Runner::scalar_lanes(*this, in, i, n);
  }
}

double lane_by_lane_share(const Tape& tape) {
  int ops = 0, slow = 0;
  const auto ins = tape.instrs();
  for (int i = tape.first_op(); i < tape.size(); ++i) {
    const Op op = ins[static_cast<std::size_t>(i)].op;
    if (op == Op::kPairedCos) continue;
    ++ops;
    switch (op) {  // the operations with a vector rule in both batched evaluators
      case Op::kAdd:
      case Op::kSub:
      case Op::kMul:
      case Op::kScale:
      case Op::kDivConst:
      case Op::kNeg:
      case Op::kSquare:
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

template class BatchIntervalEvalK<2>;
template class BatchIntervalEvalK<4>;
template class BatchIntervalEvalK<8>;
template class BatchIntervalEvalK<16>;

}  // namespace iaa
