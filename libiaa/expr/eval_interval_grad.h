// Interval evaluation with the interval gradient, by forward-mode differentiation over intervals:
// encloses f and every partial derivative over a box. At kinks (abs at 0, min/max that the box
// does not decide) the gradient enclosure is the hull of both sides, so it contains every one-sided
// and generalized gradient.
#pragma once

#include <array>

#include "core/vec.h"
#include "expr/eval_loop.h"

namespace iaa {

/// An interval value and its interval gradient.
struct IGrad {
  Interval v;
  std::array<Interval, 3> g;
};

namespace detail {

// Gradient helpers: the three partial derivatives at once.
namespace igrad {
using G = std::array<Interval, 3>;
inline G scale(const G& g, const Interval& s) {
  return {g[0] * s, g[1] * s, g[2] * s};
}
inline G scale(const G& g, double c) {
  return {iaa::scale(g[0], c), iaa::scale(g[1], c), iaa::scale(g[2], c)};
}
inline G plus(const G& a, const G& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline G minus(const G& a, const G& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline G negate(const G& a) {
  return {-a[0], -a[1], -a[2]};
}
inline G hulls(const G& a, const G& b) {
  return {hull(a[0], b[0]), hull(a[1], b[1]), hull(a[2], b[2])};
}
// Quotient for derivatives: where the divisor may vanish the derivative is unbounded (or, for a
// numerator that is exactly 0, 0), never `empty`.
inline Interval dquot(const Interval& num, const Interval& den) {
  if (num.lo() == 0.0 && num.hi() == 0.0) return Interval(0.0);
  if (den.contains_zero()) return Interval::whole();
  return num / den;
}
inline G dquot(const G& g, const Interval& den) {
  return {dquot(g[0], den), dquot(g[1], den), dquot(g[2], den)};
}
}  // namespace igrad

// Rules of the interval + gradient mode. Each derivative rule is the interval extension of the
// calculus rule evaluated with enclosures of its arguments, hence an enclosure of the derivative.
// They are inline, as the interval rules are, so that the tape loop compiles them in place.
struct IntervalGradRules {
  using Num = IGrad;
  static constexpr bool kTracksChoices = false;
  static IGrad constant(double v) {
    return {Interval(v), {Interval(0.0), Interval(0.0), Interval(0.0)}};
  }
  // Each interval with one 16-byte store (Interval::store).
  static void store(IGrad& o, const IGrad& v) {
    o.v.store(v.v);
    for (std::size_t i = 0; i < 3; ++i) o.g[i].store(v.g[i]);
  }
  static IGrad add(const IGrad& a, const IGrad& b) { return {a.v + b.v, igrad::plus(a.g, b.g)}; }
  static IGrad sub(const IGrad& a, const IGrad& b) { return {a.v - b.v, igrad::minus(a.g, b.g)}; }
  static IGrad mul(const IGrad& a, const IGrad& b) {
    return {a.v * b.v, igrad::plus(igrad::scale(a.g, b.v), igrad::scale(b.g, a.v))};
  }
  static IGrad scale(const IGrad& a, double c) {
    return {iaa::scale(a.v, c), igrad::scale(a.g, c)};
  }
  static IGrad div(const IGrad& a, const IGrad& b, Domain* d) {
    const Interval v = divide(a.v, b.v, d);
    // (a/b)' = (a' - (a/b) b') / b
    return {v, igrad::dquot(igrad::minus(a.g, igrad::scale(b.g, v)), b.v)};
  }
  static IGrad neg(const IGrad& a) { return {-a.v, igrad::negate(a.g)}; }
  static IGrad pow_int(const IGrad& a, int n) {
    if (n == 0) return constant(1.0);
    // (a^n)' = n a^(n-1) a'
    return {iaa::pow_int(a.v, n), igrad::scale(a.g, iaa::scale(iaa::pow_int(a.v, n - 1), n))};
  }
  /// Real power; out of line (eval_interval_grad.cpp): long, and rare in surfaces.
  static IGrad pow(const IGrad& a, const IGrad& b, Domain*);
  static IGrad square(const IGrad& a) {
    return {iaa::square(a.v), igrad::scale(a.g, iaa::scale(a.v, 2.0))};
  }
  static IGrad sqrt(const IGrad& a, Domain* d) {
    const Interval v = iaa::sqrt(a.v, d);
    return {v, igrad::dquot(a.g, iaa::scale(v, 2.0))};
  }
  static IGrad exp(const IGrad& a) {
    const Interval v = iaa::exp(a.v);
    return {v, igrad::scale(a.g, v)};
  }
  static IGrad log(const IGrad& a, Domain* d) { return {iaa::log(a.v, d), igrad::dquot(a.g, a.v)}; }
  // sin and cos need both functions of the same argument: one sincos.
  static IGrad sin(const IGrad& a) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {s, igrad::scale(a.g, c)};
  }
  static IGrad cos(const IGrad& a) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {c, igrad::scale(a.g, -s)};
  }
  static IGrad tan(const IGrad& a, Domain* d) {
    const Interval v = iaa::tan(a.v, d);
    return {v, igrad::scale(a.g, Interval(1.0) + iaa::square(v))};
  }
  static IGrad atan(const IGrad& a) {
    return {iaa::atan(a.v), igrad::dquot(a.g, Interval(1.0) + iaa::square(a.v))};
  }
  // The point rule takes the slope +1 at 0, so only a strictly negative box is the mirrored side.
  static IGrad abs(const IGrad& a) {
    if (a.v.lo() >= 0.0) return a;
    if (a.v.hi() < 0.0) return neg(a);
    return {iaa::abs(a.v), igrad::hulls(a.g, igrad::negate(a.g))};
  }
  // Ties follow the point rule (the first argument wins), so a decided box uses one side only.
  static IGrad min(const IGrad& a, const IGrad& b, std::uint8_t*) {
    if (a.v.hi() <= b.v.lo()) return a;
    if (b.v.hi() < a.v.lo()) return b;
    return {iaa::min(a.v, b.v), igrad::hulls(a.g, b.g)};
  }
  static IGrad max(const IGrad& a, const IGrad& b, std::uint8_t*) {
    if (a.v.lo() >= b.v.hi()) return a;
    if (b.v.lo() > a.v.hi()) return b;
    return {iaa::max(a.v, b.v), igrad::hulls(a.g, b.g)};
  }
};
}  // namespace detail

/// Evaluates a tape and its gradient over boxes. One per thread; no allocation per call.
class IntervalGradEval {
 public:
  explicit IntervalGradEval(const Tape& tape) : loop_(tape) {}
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit IntervalGradEval(Tape&&) = delete;
  /// Checked: evaluates under a RoundingScope, opening one when the caller has none (the check
  /// is an inline read of the rounding mode; callers in hot loops open one per tile).
  IGrad eval(const IBox& b) {
    if (rounding_is_upward()) [[likely]]
      return run(b);
    RoundingScope scope;
    return run(b);
  }
  bool partial_domain() const { return loop_.partial_domain(); }
  const Tape& tape() const { return loop_.tape(); }

 private:
  IGrad run(const IBox& b) {
    const Interval o(0.0), l(1.0);
    return loop_.run({b.x, {l, o, o}}, {b.y, {o, l, o}}, {b.z, {o, o, l}});
  }
  detail::TapeLoop<detail::IntervalGradRules> loop_;
};

}  // namespace iaa
