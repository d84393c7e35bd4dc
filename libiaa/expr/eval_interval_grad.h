// Interval evaluation with the interval gradient, by forward-mode differentiation over intervals:
// encloses f and every partial derivative over a box. At kinks (abs at 0, min/max that the box
// does not decide) the gradient enclosure is the hull of both sides, so it contains every one-sided
// and generalized gradient.
#pragma once

#include <array>
#include <utility>

#include "core/vec.h"
#include "expr/eval_loop.h"

namespace iaa {

/// An interval value and its interval gradient.
struct IGrad {
  Interval v;
  std::array<Interval, 3> g;
};

namespace detail {

// Gradient helpers: the partial derivatives named by the output slot's VarMask `m` (the others
// are structurally 0: the slot keeps them at [0,0] and the result leaves them unset).
namespace igrad {
using G = std::array<Interval, 3>;
/// out[i] = f(i) for each component i in m.
template <class F>
inline G each(VarMask m, F f) {
  G out;
  for (std::size_t i = 0; i < 3; ++i) {
    if (m & (1u << i)) out[i] = f(i);
  }
  return out;
}
inline G scale(const G& g, const Interval& s, VarMask m) {
  return each(m, [&](std::size_t i) { return g[i] * s; });
}
inline G scale(const G& g, double c, VarMask m) {
  return each(m, [&](std::size_t i) { return iaa::scale(g[i], c); });
}
inline G plus(const G& a, const G& b, VarMask m) {
  return each(m, [&](std::size_t i) { return a[i] + b[i]; });
}
inline G minus(const G& a, const G& b, VarMask m) {
  return each(m, [&](std::size_t i) { return a[i] - b[i]; });
}
inline G negate(const G& a, VarMask m) {
  return each(m, [&](std::size_t i) { return -a[i]; });
}
// Hull of the two sides' partials at a kink. An empty partial of one side is no knowledge of it
// (a derivative is never empty where the value exists): the hull is then unbounded, not the
// other side alone, so the branch is never dropped.
inline G hulls(const G& a, const G& b, VarMask m) {
  return each(m, [&](std::size_t i) {
    return a[i].is_empty() || b[i].is_empty() ? Interval::whole() : hull(a[i], b[i]);
  });
}
// Quotient for derivatives: where the divisor may vanish the derivative is unbounded (or, for a
// numerator that is exactly 0, 0), never `empty`.
inline Interval dquot(const Interval& num, const Interval& den) {
  if (num.lo() == 0.0 && num.hi() == 0.0) return Interval(0.0);
  if (den.contains_zero()) return Interval::whole();
  return num / den;
}
inline G dquot(const G& g, const Interval& den, VarMask m) {
  return each(m, [&](std::size_t i) { return dquot(g[i], den); });
}
}  // namespace igrad

// Rules of the interval + gradient mode. Each derivative rule is the interval extension of the
// calculus rule evaluated with enclosures of its arguments, hence an enclosure of the derivative.
// They are inline, as the interval rules are, so that the tape loop compiles them in place.
//
// Sparse: each rule gets the output slot's VarMask `m` and computes only the partials along the
// variables the slot depends on; the others are exactly 0 by structure, stay [0,0] in the slot
// (the loop initializes slots to 0 and `store` never writes them) and are not computed. An
// argument's component outside the argument's own mask reads as that exact 0.
struct IntervalGradRules {
  using Num = IGrad;
  static constexpr bool kTracksChoices = true;
  static constexpr bool kUsesVarMasks = true;
  static IGrad constant(double v) {
    return {Interval(v), {Interval(0.0), Interval(0.0), Interval(0.0)}};
  }
  // Each interval with one 16-byte store (Interval::store); only the components in the mask.
  static void store(IGrad& o, const IGrad& v, VarMask m) {
    o.v.store(v.v);
    for (std::size_t i = 0; i < 3; ++i) {
      if (m & (1u << i)) o.g[i].store(v.g[i]);
    }
  }
  static IGrad add(const IGrad& a, const IGrad& b, VarMask m) {
    return {a.v + b.v, igrad::plus(a.g, b.g, m)};
  }
  static IGrad sub(const IGrad& a, const IGrad& b, VarMask m) {
    return {a.v - b.v, igrad::minus(a.g, b.g, m)};
  }
  static IGrad mul(const IGrad& a, const IGrad& b, VarMask m) {
    return {a.v * b.v, igrad::each(m, [&](std::size_t i) { return a.g[i] * b.v + b.g[i] * a.v; })};
  }
  static IGrad scale(const IGrad& a, double c, VarMask m) {
    return {iaa::scale(a.v, c), igrad::scale(a.g, c, m)};
  }
  // (a/c)' = a' / c for a finite non-zero constant c.
  static IGrad div_const(const IGrad& a, double c, VarMask m) {
    return {iaa::div_const(a.v, c),
            igrad::each(m, [&](std::size_t i) { return iaa::div_const(a.g[i], c); })};
  }
  static IGrad div(const IGrad& a, const IGrad& b, Domain* d, VarMask m) {
    const Interval v = divide(a.v, b.v, d);
    // (a/b)' = (a' - (a/b) b') / b
    return {v,
            igrad::each(m, [&](std::size_t i) { return igrad::dquot(a.g[i] - b.g[i] * v, b.v); })};
  }
  static IGrad neg(const IGrad& a, VarMask m) { return {-a.v, igrad::negate(a.g, m)}; }
  static IGrad pow_int(const IGrad& a, int n, VarMask m) {
    // The small powers of polynomial surfaces with n a constant, so that iaa::pow_int unrolls
    // into the rule (the same operations in the same order: the same bounds).
    switch (n) {
      case 0:
        return constant(1.0);
      case 3:
        return pow_int_n<3>(a, m);
      case 4:
        return pow_int_n<4>(a, m);
      default:
        return pow_int_n(a, n, m);
    }
  }
  // (a^n)' = n a^(n-1) a'
  template <int N>
  static IGrad pow_int_n(const IGrad& a, VarMask m) {
    return pow_int_n(a, N, m);
  }
  [[gnu::always_inline]] static IGrad pow_int_n(const IGrad& a, int n, VarMask m) {
    return {iaa::pow_int(a.v, n), igrad::scale(a.g, iaa::scale(iaa::pow_int(a.v, n - 1), n), m)};
  }
  /// Real power; out of line (eval_interval_grad.cpp): long, and rare in surfaces.
  static IGrad pow(const IGrad& a, const IGrad& b, Domain*, VarMask m);
  static IGrad square(const IGrad& a, VarMask m) {
    return {iaa::square(a.v), igrad::scale(a.g, iaa::scale(a.v, 2.0), m)};
  }
  static IGrad sqrt(const IGrad& a, Domain* d, VarMask m) {
    const Interval v = iaa::sqrt(a.v, d);
    return {v, igrad::dquot(a.g, iaa::scale(v, 2.0), m)};
  }
  static IGrad exp(const IGrad& a, VarMask m) {
    const Interval v = iaa::exp(a.v);
    return {v, igrad::scale(a.g, v, m)};
  }
  static IGrad log(const IGrad& a, Domain* d, VarMask m) {
    return {iaa::log(a.v, d), igrad::dquot(a.g, a.v, m)};
  }
  // sin and cos need both functions of the same argument: one sincos.
  static IGrad sin(const IGrad& a, VarMask m) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {s, igrad::scale(a.g, c, m)};
  }
  static IGrad cos(const IGrad& a, VarMask m) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {c, igrad::scale(a.g, -s, m)};
  }
  static std::pair<IGrad, IGrad> sincos(const IGrad& a, VarMask m) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {IGrad{s, igrad::scale(a.g, c, m)}, IGrad{c, igrad::scale(a.g, -s, m)}};
  }
  static IGrad tan(const IGrad& a, Domain* d, VarMask m) {
    const Interval v = iaa::tan(a.v, d);
    return {v, igrad::scale(a.g, Interval(1.0) + iaa::square(v), m)};
  }
  static IGrad atan(const IGrad& a, VarMask m) {
    return {iaa::atan(a.v), igrad::dquot(a.g, Interval(1.0) + iaa::square(a.v), m)};
  }
  // The point rule takes the slope +1 at 0, so only a strictly negative box is the mirrored side.
  // (abs, min and max have their argument's mask or the union of both, so returning an argument
  // whole is right: store keeps only the components of the output mask.)
  static IGrad abs(const IGrad& a, VarMask m) {
    if (a.v.lo() >= 0.0) return a;
    if (a.v.hi() < 0.0) return neg(a, m);
    return {iaa::abs(a.v), igrad::each(m, [&](std::size_t i) { return hull(a.g[i], -a.g[i]); })};
  }
  // Ties follow the point rule (the first argument wins), so a decided box uses one side only.
  // They record the choice as the interval rules do (min_choice, max_choice).
  static IGrad min(const IGrad& a, const IGrad& b, std::uint8_t* c, VarMask m) {
    *c = min_choice(a.v, b.v);
    if (*c == 1) return a;
    if (*c == 2) return b;
    return {iaa::min(a.v, b.v), igrad::hulls(a.g, b.g, m)};
  }
  static IGrad max(const IGrad& a, const IGrad& b, std::uint8_t* c, VarMask m) {
    *c = max_choice(a.v, b.v);
    if (*c == 1) return a;
    if (*c == 2) return b;
    return {iaa::max(a.v, b.v), igrad::hulls(a.g, b.g, m)};
  }
};

/// The interval + gradient evaluator over a tape; `dense` computes every partial of every slot
/// (the same rules with all masks kAllVars), a reference for tests.
class BasicIntervalGradEval {
 public:
  BasicIntervalGradEval(const Tape& tape, bool dense, VarMask wanted = kAllVars)
      : loop_(tape, dense, wanted),
        wanted_(wanted),
        bare_variable_(wanted != kAllVars && tape.root() < tape.first_op()) {}
  /// Checked: evaluates under a RoundingScope, opening one when the caller has none (the check
  /// is an inline read of the rounding mode; callers in hot loops open one per tile).
  IGrad eval(const IBox& b) {
    if (rounding_is_upward()) [[likely]]
      return run(b);
    RoundingScope scope;
    return run(b);
  }
  bool partial_domain() const { return loop_.partial_domain(); }
  /// Per instruction of the tape, the min/max argument the last box certainly took (0: both).
  const std::vector<std::uint8_t>& choices() const { return loop_.choices(); }
  const Tape& tape() const { return loop_.tape(); }

 private:
  IGrad run(const IBox& b) {
    const Interval o(0.0), l(1.0);
    IGrad r = loop_.run({b.x, {l, o, o}}, {b.y, {o, l, o}}, {b.z, {o, o, l}});
    // An instruction's unwanted partials are never computed, but a tape that is a bare variable
    // (or a constant) returns that slot's seed: its unwanted partials are set to 0 here.
    if (bare_variable_) [[unlikely]] {
      for (std::size_t i = 0; i < 3; ++i) {
        if (!(wanted_ & (1u << i))) r.g[i] = o;
      }
    }
    return r;
  }
  TapeLoop<IntervalGradRules> loop_;
  VarMask wanted_;
  bool bare_variable_;
};
}  // namespace detail

/// Evaluates a tape and its gradient over boxes. One per thread; no allocation per call.
/// Structurally zero partials (along a variable the expression does not use) are exactly [0,0]
/// and cost nothing.
class IntervalGradEval : public detail::BasicIntervalGradEval {
 public:
  explicit IntervalGradEval(const Tape& tape) : BasicIntervalGradEval(tape, /*dense=*/false) {}
  /// Computes only the partials along the variables in `partials` (x = 1, y = 2, z = 4), each
  /// exactly as the full evaluation does; the others are [0,0]. For callers that read only some
  /// (a derivative along an edge, the tangential gradient on a face): the rest costs nothing.
  IntervalGradEval(const Tape& tape, detail::VarMask partials)
      : BasicIntervalGradEval(tape, /*dense=*/false, partials) {}
  IntervalGradEval(Tape&&, detail::VarMask) = delete;
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit IntervalGradEval(Tape&&) = delete;
};

}  // namespace iaa
