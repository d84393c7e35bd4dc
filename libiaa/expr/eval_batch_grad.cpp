// Batched interval + gradient evaluation (eval_batch_grad.h). Each operation runs over the K
// lanes of its value and of the partials in its slot's mask, W at a time in one vector, with the
// fast interval rules of batch_lanes.h combined in the order of IntervalGradRules
// (eval_interval_grad.h), so that each lane rounds exactly as the scalar rules do. A lane that
// leaves a fast rule's path (flagged by the rule) sends the operation to the scalar rules for the
// lanes in use. The loop is compiled twice, for the baseline (SSE2, W = 2) and, chosen at run
// time, for AVX2 (W = 4), as eval_batch.cpp's is.
#include "expr/eval_batch_grad.h"

#include "core/error.h"
#include "expr/batch_lanes.h"

namespace iaa {

template <int K>
BatchIntervalGradEvalK<K>::BatchIntervalGradEvalK(const Tape& tape, detail::VarMask partials)
    : tape_(&tape),
      slots_(4 * static_cast<std::size_t>(tape.size())),  // every bound +0, as IGrad's are
      masks_(detail::var_masks(tape)),
      wanted_(partials),
      bare_variable_(partials != detail::kAllVars && tape.root() < tape.first_op()) {
  for (detail::VarMask& m : masks_) m = detail::VarMask(m & partials);
  const auto consts = tape.constants();
  for (int i = 3; i < tape.first_op(); ++i) {
    const Interval c(consts[static_cast<std::size_t>(i)]);
    Slot& s = slot(i, 0);
    for (int j = 0; j < K; ++j) {
      s.lo[j] = c.lo();
      s.hi[j] = c.hi();
    }
  }
  // The variables' seeds: d x / d x = 1, the other partials 0.
  for (int v = 0; v < 3; ++v) {
    Slot& s = slot(v, 1 + v);
    for (int j = 0; j < K; ++j) s.lo[j] = s.hi[j] = 1.0;
  }
}

template <int K>
void BatchIntervalGradEvalK<K>::eval(const IBox* boxes, int n, IGrad* out) {
  IAA_CHECK(n >= 1 && n <= K);
  for (int v = 0; v < 3; ++v) {
    Slot& s = slot(v, 0);
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
  const int root = tape_->root();
  for (int j = 0; j < n; ++j) {
    IGrad& r = out[j];
    r.v = Interval::raw(slot(root, 0).lo[j], slot(root, 0).hi[j]);
    for (int d = 0; d < 3; ++d) {
      const Slot& g = slot(root, 1 + d);
      r.g[static_cast<std::size_t>(d)] = Interval::raw(g.lo[j], g.hi[j]);
    }
    // As IntervalGradEval: a bare variable returns its seed, without the unwanted partials.
    if (bare_variable_) [[unlikely]] {
      for (int d = 0; d < 3; ++d) {
        if (!(wanted_ & (1u << d))) r.g[static_cast<std::size_t>(d)] = Interval(0.0);
      }
    }
  }
}

template <int K>
void BatchIntervalGradEvalK<K>::run(int n) {
#if IAA_BATCH_AVX2
  if (use_avx2_) {
    run_avx2(n);
    return;
  }
#endif
  run_baseline(n);
}

template <int K>
void BatchIntervalGradEvalK<K>::fill_unused(int i, int n) {
  for (int c = 0; c < 4; ++c) {
    Slot& s = slot(i, c);
    for (int j = n; j < K; ++j) {
      s.lo[j] = s.lo[0];
      s.hi[j] = s.hi[0];
    }
  }
}

template <int K>
void BatchIntervalGradEvalK<K>::scalar_op(int i, int j) {
  using R = detail::IntervalGradRules;
  const Instr& in = tape_->instrs()[static_cast<std::size_t>(i)];
  const double* k = tape_->constants().data();
  const detail::VarMask m = masks_[static_cast<std::size_t>(i)];
  const auto lane = [&](int t) {
    IGrad g;
    g.v = Interval::raw(slot(t, 0).lo[j], slot(t, 0).hi[j]);
    for (int d = 0; d < 3; ++d) {
      g.g[static_cast<std::size_t>(d)] = Interval::raw(slot(t, 1 + d).lo[j], slot(t, 1 + d).hi[j]);
    }
    return g;
  };
  // IntervalGradRules::store: the value and the partials of the mask.
  const auto put = [&](int t, const IGrad& r) {
    slot(t, 0).lo[j] = r.v.lo();
    slot(t, 0).hi[j] = r.v.hi();
    for (int d = 0; d < 3; ++d) {
      if (!(m & (1u << d))) continue;
      slot(t, 1 + d).lo[j] = r.g[static_cast<std::size_t>(d)].lo();
      slot(t, 1 + d).hi[j] = r.g[static_cast<std::size_t>(d)].hi();
    }
  };
  const IGrad a = lane(in.a);
  Domain dom = Domain::kFull;
  std::uint8_t choice = 0;
  IGrad r;
  switch (in.op) {
    case Op::kAdd:
      r = R::add(a, lane(in.b), m);
      break;
    case Op::kSub:
      r = R::sub(a, lane(in.b), m);
      break;
    case Op::kMul:
      r = R::mul(a, lane(in.b), m);
      break;
    case Op::kScale:
      r = R::scale(a, k[in.b], m);
      break;
    case Op::kDiv:
      r = R::div(a, lane(in.b), &dom, m);
      break;
    case Op::kDivConst:
      r = R::div_const(a, k[in.b], m);
      break;
    case Op::kNeg:
      r = R::neg(a, m);
      break;
    case Op::kPowInt:
      r = R::pow_int(a, in.power, m);
      break;
    case Op::kPow:
      r = R::pow(a, lane(in.b), &dom, m);
      break;
    case Op::kSquare:
      r = R::square(a, m);
      break;
    case Op::kSqrt:
      r = R::sqrt(a, &dom, m);
      break;
    case Op::kExp:
      r = R::exp(a, m);
      break;
    case Op::kLog:
      r = R::log(a, &dom, m);
      break;
    case Op::kSin:
      r = R::sin(a, m);
      break;
    case Op::kCos:
      r = R::cos(a, m);
      break;
    case Op::kSinCos: {
      const auto [sv, cv] = R::sincos(a, m);
      r = sv;
      put(i + 1, cv);  // the paired cos has this slot's mask
      break;
    }
    case Op::kTan:
      r = R::tan(a, &dom, m);
      break;
    case Op::kAtan:
      r = R::atan(a, m);
      break;
    case Op::kAbs:
      r = R::abs(a, m);
      break;
    case Op::kMin:
      r = R::min(a, lane(in.b), &choice, m);
      break;
    case Op::kMax:
      r = R::max(a, lane(in.b), &choice, m);
      break;
    case Op::kPairedCos:
    case Op::kVarX:
    case Op::kVarY:
    case Op::kVarZ:
    case Op::kConst:
      return;  // written by the sincos before it, or never after first_op
  }
  if (dom == Domain::kPartial) partial_[j] = 1;
  put(i, r);
}

template <int K>
template <int W>
IAA_ALWAYS_INLINE void BatchIntervalGradEvalK<K>::run_impl(int n) {
  using L = detail::batch::Lanes<W>;
  using M = typename L::M;
  using I = typename L::I;
  Slot* s = slots_.data();
  const Instr* ins = tape_->instrs().data();
  const double* k = tape_->constants().data();
  const detail::VarMask* masks = masks_.data();
  const int size = tape_->size();
  for (int i = tape_->first_op(); i < size; ++i) {
    const Instr& in = ins[i];
    const unsigned m = masks[i];
    // The argument's and the result's four slots (value, then the partials); for unary
    // operations b is slot 0 (never read), for scale and divc a constant's slot.
    const Slot* a = s + 4 * in.a;
    const Slot* b = s + 4 * (in.b >= 0 ? in.b : 0);
    Slot* o = s + 4 * i;
    // Lanes a fast rule flags (any lane; the unused ones copy lane 0) send the operation to the
    // scalar rules for the lanes in use, after which the unused lanes take lane 0's result again.
    M bad = L::none();
    const auto ld = [](const Slot& x, int c) __attribute__((always_inline)) {
      return L::load(x.lo, x.hi, c);
    };
    const auto st = [](Slot & x, int c, const I& v) __attribute__((always_inline)) {
      L::store(x.lo, x.hi, c, v);
    };
    // Runs `rule(c, d)` for each group of W lanes starting at lane c and each partial d of the
    // mask (`value(c)` first for the value).
    const auto each = [&](auto value, auto partial) __attribute__((always_inline)) {
      for (int c = 0; c < K; c += W) {
        value(c);
        for (int d = 1; d <= 3; ++d) {
          if (m & (1u << (d - 1))) partial(c, d);
        }
      }
    };
    switch (in.op) {
      case Op::kAdd:
        each(
            [&](int c) __attribute__((always_inline)) {
              st(o[0], c, L::add(ld(a[0], c), ld(b[0], c), bad));
            },
            [&](int c, int d) __attribute__((always_inline)) {
              st(o[d], c, L::add(ld(a[d], c), ld(b[d], c), bad));
            });
        break;
      case Op::kSub:
        each(
            [&](int c) __attribute__((always_inline)) {
              st(o[0], c, L::sub(ld(a[0], c), ld(b[0], c), bad));
            },
            [&](int c, int d) __attribute__((always_inline)) {
              st(o[d], c, L::sub(ld(a[d], c), ld(b[d], c), bad));
            });
        break;
      case Op::kMul:
        // a' * b + b' * a, in this order (IntervalGradRules::mul).
        each(
            [&](int c) __attribute__((always_inline)) {
              st(o[0], c, L::mul(ld(a[0], c), ld(b[0], c), bad));
            },
            [&](int c, int d) __attribute__((always_inline)) {
              const I av = ld(a[0], c), bv = ld(b[0], c);
              st(o[d], c, L::add(L::mul(ld(a[d], c), bv, bad), L::mul(ld(b[d], c), av, bad), bad));
            });
        break;
      case Op::kScale: {
        const double cv = k[in.b];
        each(
            [&](int c) __attribute__((always_inline)) { st(o[0], c, L::scale(ld(a[0], c), cv)); },
            [&](int c, int d)
                __attribute__((always_inline)) { st(o[d], c, L::scale(ld(a[d], c), cv)); });
        break;
      }
      case Op::kDivConst: {
        const double cv = k[in.b];
        each(
            [&](int c)
                __attribute__((always_inline)) { st(o[0], c, L::div_const(ld(a[0], c), cv)); },
            [&](int c, int d)
                __attribute__((always_inline)) { st(o[d], c, L::div_const(ld(a[d], c), cv)); });
        break;
      }
      case Op::kNeg:
        each(
            [&](int c) __attribute__((always_inline)) { st(o[0], c, L::neg(ld(a[0], c))); },
            [&](int c, int d) __attribute__((always_inline)) { st(o[d], c, L::neg(ld(a[d], c))); });
        break;
      case Op::kSquare:
        // a' * (2 a) (IntervalGradRules::square).
        each(
            [&](int c) __attribute__((always_inline)) { st(o[0], c, L::square(ld(a[0], c), bad)); },
            [&](int c, int d) __attribute__((always_inline)) {
              st(o[d], c, L::mul(ld(a[d], c), L::scale(ld(a[0], c), 2.0), bad));
            });
        break;
      case Op::kPowInt: {
        const int p = in.power;
        if (p == 0) {
          // The constant 1 (IntervalGradRules::constant), whatever the argument.
          const I one{L::splat(1.0), L::splat(1.0)}, zero{L::splat(0.0), L::splat(0.0)};
          each(
              [&](int c) __attribute__((always_inline)) { st(o[0], c, one); },
              [&](int c, int d) __attribute__((always_inline)) { st(o[d], c, zero); });
          break;
        }
        // a' * (n a^(n-1)) (IntervalGradRules::pow_int).
        each(
            [&](int c)
                __attribute__((always_inline)) { st(o[0], c, L::pow_int(ld(a[0], c), p, bad)); },
            [&](int c, int d) __attribute__((always_inline)) {
              const I f = L::scale(L::pow_int(ld(a[0], c), p - 1, bad), double(p));
              st(o[d], c, L::mul(ld(a[d], c), f, bad));
            });
        break;
      }
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
        // div, sqrt, exp, log, sin, cos, tan, atan, abs, min, max, the real power: the scalar
        // rules in each lane.
        bad = L::all();
        break;
    }
    if (L::any(bad)) [[unlikely]] {
      for (int j = 0; j < n; ++j) scalar_op(i, j);
      fill_unused(i, n);
    }
  }
}

template <int K>
void BatchIntervalGradEvalK<K>::run_baseline(int n) {
  run_impl<2>(n);
}

template <int K>
IAA_TARGET_AVX2 void BatchIntervalGradEvalK<K>::run_avx2(int n) {
  run_impl<(K < 4 ? K : 4)>(n);
}

template class BatchIntervalGradEvalK<2>;
template class BatchIntervalGradEvalK<4>;
template class BatchIntervalGradEvalK<8>;
template class BatchIntervalGradEvalK<16>;

}  // namespace iaa
