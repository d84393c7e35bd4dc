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
    : wanted_(partials),
      bare_variable_(partials != detail::kAllVars && tape.root() < tape.first_op()),
      tape_(&tape),
      masks_(detail::var_masks(tape)),
      slots_(4 * static_cast<std::size_t>(tape.size())) {  // every bound +0, as IGrad's are
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
    // scalar rules for the lanes in use (Runner::scalar_lanes).
    M bad = L::none();
    const auto ld = [](const Slot& x, int c) __attribute__((always_inline)) {
      return L::load(x.lo, x.hi, c);
    };
    const auto st = [](Slot & x, int c, const I& v) __attribute__((always_inline)) {
      L::store(x.lo, x.hi, c, v);
    };
    // For each group of W lanes starting at lane c, the value (d = 0) and each partial of the
    // mask (d = 1, 2, 3 along x, y, z): component d of the result is `rule(x, y, d, c)`, x and y
    // the arguments' components d.
    const auto each = [&](auto rule) __attribute__((always_inline)) {
      for (int c = 0; c < K; c += W) {
        for (int d = 0; d <= 3; ++d) {
          if (d == 0 || (m & (1u << (d - 1)))) st(o[d], c, rule(ld(a[d], c), ld(b[d], c), d, c));
        }
      }
    };
    if (in.op == Op::kPairedCos) continue;  // written by the sincos before it
    switch (in.op) {
      default:
        // div, sqrt, log, tan, atan, abs, the real power: the scalar rules in each lane.
        bad = L::all();
        break;
      case Op::kMin:
      case Op::kMax:
        // IntervalGradRules::min and max: the argument certainly taken whole (ties to the first,
        // min_choice and max_choice), else iaa::min or max of the values and the hulls of the
        // partials. An empty value or partial (hulls makes that whole) is bad.
        for (int c = 0; c < K; c += W) {
          const I x = ld(a[0], c), y = ld(b[0], c);
          bad |= ~(x.lo <= x.hi) | ~(y.lo <= y.hi);
          const bool is_min = in.op == Op::kMin;
          const M first = is_min ? (x.hi <= y.lo) : (x.lo >= y.hi);
          const M second = ~first & (is_min ? (y.hi < x.lo) : (y.lo > x.hi));
          const auto pick = [&](const I& u, const I& v, const I& both)
              __attribute__((always_inline)) {
            return I{first ? u.lo : (second ? v.lo : both.lo),
                     first ? u.hi : (second ? v.hi : both.hi)};
          };
          st(o[0], c,
             pick(x, y,
                  is_min ? I{L::min(x.lo, y.lo), L::min(x.hi, y.hi)}
                         : I{L::max(x.lo, y.lo), L::max(x.hi, y.hi)}));
          for (int d = 1; d <= 3; ++d) {
            if (!(m & (1u << (d - 1)))) continue;
            const I u = ld(a[d], c), v = ld(b[d], c);
            bad |= ~(u.lo <= u.hi) | ~(v.lo <= v.hi);
            st(o[d], c, pick(u, v, I{L::min(u.lo, v.lo), L::max(u.hi, v.hi)}));
          }
        }
        break;
      case Op::kExp:
        // (e, a' * e), e = exp a (IntervalGradRules::exp).
        for (int c = 0; c < K; c += W) {
          const I e = L::exp(ld(a[0], c), bad);
          st(o[0], c, e);
          for (int d = 1; d <= 3; ++d) {
            if (m & (1u << (d - 1))) st(o[d], c, L::mul(ld(a[d], c), e, bad));
          }
        }
        break;
      case Op::kSin:
      case Op::kCos:
      case Op::kSinCos:
        // sin a: (s, a' * c); cos a: (c, a' * (-s)) (IntervalGradRules::sincos); sincos puts
        // the cos into the paired slot after this one, with this slot's mask.
        for (int c = 0; c < K; c += W) {
          I sv, cv;
          L::sincos(ld(a[0], c), &sv, &cv, bad);
          const I nsv = L::neg(sv);
          const auto put = [&](Slot * out, const I& v, const I& dv) __attribute__((always_inline)) {
            st(out[0], c, v);
            for (int d = 1; d <= 3; ++d) {
              if (m & (1u << (d - 1))) st(out[d], c, L::mul(ld(a[d], c), dv, bad));
            }
          };
          if (in.op == Op::kCos) {
            put(o, cv, nsv);
          } else {
            put(o, sv, cv);
            if (in.op == Op::kSinCos) put(o + 4, cv, nsv);
          }
        }
        break;
      // The linear operations: the same rule for the value and the partials.
      case Op::kAdd:
        each([&](const I& x, const I& y, int, int)
                 __attribute__((always_inline)) { return L::add(x, y, bad); });
        break;
      case Op::kSub:
        each([&](const I& x, const I& y, int, int)
                 __attribute__((always_inline)) { return L::sub(x, y, bad); });
        break;
      case Op::kScale:
        each([&, cv = k[in.b] ](const I& x, const I&, int, int)
                 __attribute__((always_inline)) { return L::scale(x, cv); });
        break;
      case Op::kDivConst:
        each([&, cv = k[in.b] ](const I& x, const I&, int, int)
                 __attribute__((always_inline)) { return L::div_const(x, cv); });
        break;
      case Op::kNeg:
        each([&](const I& x, const I&, int, int)
                 __attribute__((always_inline)) { return L::neg(x); });
        break;
      case Op::kMul:
        // a' * b + b' * a, in this order (IntervalGradRules::mul).
        each([&](const I& x, const I& y, int d, int c) __attribute__((always_inline)) {
          if (d == 0) return L::mul(x, y, bad);
          return L::add(L::mul(x, ld(b[0], c), bad), L::mul(y, ld(a[0], c), bad), bad);
        });
        break;
      case Op::kSquare:
        // a' * (2 a) (IntervalGradRules::square).
        each([&](const I& x, const I&, int d, int c) __attribute__((always_inline)) {
          if (d == 0) return L::square(x, bad);
          return L::mul(x, L::scale(ld(a[0], c), 2.0), bad);
        });
        break;
      case Op::kPowInt:
        // a' * (n a^(n-1)) (IntervalGradRules::pow_int); for n = 0 the constant 1 (its value
        // and partials whatever the argument).
        each([&, p = in.power ](const I& x, const I&, int d, int c) __attribute__((always_inline)) {
          if (p == 0)
            return d == 0 ? I{L::splat(1.0), L::splat(1.0)} : I{L::splat(0.0), L::splat(0.0)};
          if (d == 0) return L::pow_int(x, p, bad);
          return L::mul(x, L::scale(L::pow_int(ld(a[0], c), p - 1, bad), double(p)), bad);
        });
        break;
    }
    if (L::any(bad)) [[unlikely]]
      detail::batch::Runner::scalar_lanes(*this, in, i, n);
  }
}

template <int K>
void BatchIntervalGradEvalK<K>::eval(const IBox* boxes, int n, IGrad* out) {
  detail::batch::Runner::load_and_run(*this, boxes, n, [&](int v) -> Slot& { return slot(v, 0); });
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
  const detail::VarMask m = masks_[static_cast<std::size_t>(i)];
  const auto arg = [&](int t) {
    IGrad g;
    g.v = Interval::raw(slot(t, 0).lo[j], slot(t, 0).hi[j]);
    for (int d = 0; d < 3; ++d) {
      g.g[static_cast<std::size_t>(d)] = Interval::raw(slot(t, 1 + d).lo[j], slot(t, 1 + d).hi[j]);
    }
    return g;
  };
  // IntervalGradRules::store: the value and the partials of the mask.
  const auto put = [&](int next, const IGrad& r) {
    slot(i + next, 0).lo[j] = r.v.lo();
    slot(i + next, 0).hi[j] = r.v.hi();
    for (int d = 0; d < 3; ++d) {
      if (!(m & (1u << d))) continue;
      slot(i + next, 1 + d).lo[j] = r.g[static_cast<std::size_t>(d)].lo();
      slot(i + next, 1 + d).hi[j] = r.g[static_cast<std::size_t>(d)].hi();
    }
  };
  Domain dom = Domain::kFull;
  detail::batch::scalar_rule<detail::IntervalGradRules>(
      tape_->instrs()[static_cast<std::size_t>(i)], tape_->constants().data(), arg, put, &dom, m);
  if (dom == Domain::kPartial) partial_[j] = 1;
}

template class BatchIntervalGradEvalK<2>;
template class BatchIntervalGradEvalK<4>;
template class BatchIntervalGradEvalK<8>;
template class BatchIntervalGradEvalK<16>;

}  // namespace iaa
