// Rules of the interval + gradient mode. Each derivative rule is the interval extension of the
// calculus rule evaluated with enclosures of its arguments, hence an enclosure of the derivative.
#include "expr/eval_interval_grad.h"

namespace iaa::detail {

namespace {

using G = std::array<Interval, 3>;

G scale(const G& g, const Interval& s) {
  return {g[0] * s, g[1] * s, g[2] * s};
}
G plus(const G& a, const G& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
G minus(const G& a, const G& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
G negate(const G& a) {
  return {-a[0], -a[1], -a[2]};
}
G hulls(const G& a, const G& b) {
  return {hull(a[0], b[0]), hull(a[1], b[1]), hull(a[2], b[2])};
}

// Quotient for derivatives: where the divisor may vanish the derivative is unbounded (or, for a
// numerator that is exactly 0, 0), never `empty`.
Interval dquot(const Interval& num, const Interval& den) {
  if (num.lo() == 0.0 && num.hi() == 0.0) return Interval(0.0);
  if (den.contains_zero()) return Interval::whole();
  return num / den;
}
G dquot(const G& g, const Interval& den) {
  return {dquot(g[0], den), dquot(g[1], den), dquot(g[2], den)};
}

}  // namespace

IGrad IntervalGradRules::add(const IGrad& a, const IGrad& b) {
  return {a.v + b.v, plus(a.g, b.g)};
}
IGrad IntervalGradRules::sub(const IGrad& a, const IGrad& b) {
  return {a.v - b.v, minus(a.g, b.g)};
}
IGrad IntervalGradRules::mul(const IGrad& a, const IGrad& b) {
  return {a.v * b.v, plus(scale(a.g, b.v), scale(b.g, a.v))};
}
IGrad IntervalGradRules::div(const IGrad& a, const IGrad& b, Domain* d) {
  const Interval v = divide(a.v, b.v, d);
  // (a/b)' = (a' - (a/b) b') / b
  return {v, dquot(minus(a.g, scale(b.g, v)), b.v)};
}
IGrad IntervalGradRules::neg(const IGrad& a) {
  return {-a.v, negate(a.g)};
}
IGrad IntervalGradRules::pow_int(const IGrad& a, int n) {
  if (n == 0) return constant(1.0);
  return {iaa::pow_int(a.v, n), scale(a.g, Interval(n) * iaa::pow_int(a.v, n - 1))};
}
IGrad IntervalGradRules::pow(const IGrad& a, const IGrad& b, Domain* d) {
  const Interval v = pow_real(a.v, b.v, d);
  Domain ignored = Domain::kFull;
  // (a^b)' = b a^(b-1) a' + a^b log(a) b'
  G g = scale(a.g, b.v * pow_real(a.v, b.v - Interval(1.0), &ignored));
  // The log term only where the exponent varies: log(a) may be empty (a = 0) while a^b is not.
  // At a = 0 (where a^b = 0 for b > 0) log(a) is empty or unbounded while a^b log(a) -> 0: no
  // finite bound is derived there, the term is left unbounded (still exactly 0 where v = 0).
  Interval l = iaa::log(a.v, &ignored);
  if (l.is_empty()) l = Interval::whole();
  for (std::size_t i = 0; i < 3; ++i) {
    if (b.g[i].lo() != 0.0 || b.g[i].hi() != 0.0) g[i] = g[i] + b.g[i] * (v * l);
  }
  return {v, g};
}
IGrad IntervalGradRules::square(const IGrad& a) {
  return {iaa::square(a.v), scale(a.g, Interval(2.0) * a.v)};
}
IGrad IntervalGradRules::sqrt(const IGrad& a, Domain* d) {
  const Interval v = iaa::sqrt(a.v, d);
  return {v, dquot(a.g, Interval(2.0) * v)};
}
IGrad IntervalGradRules::exp(const IGrad& a) {
  const Interval v = iaa::exp(a.v);
  return {v, scale(a.g, v)};
}
IGrad IntervalGradRules::log(const IGrad& a, Domain* d) {
  return {iaa::log(a.v, d), dquot(a.g, a.v)};
}
IGrad IntervalGradRules::sin(const IGrad& a) {
  return {iaa::sin(a.v), scale(a.g, iaa::cos(a.v))};
}
IGrad IntervalGradRules::cos(const IGrad& a) {
  return {iaa::cos(a.v), scale(a.g, -iaa::sin(a.v))};
}
IGrad IntervalGradRules::tan(const IGrad& a, Domain* d) {
  const Interval v = iaa::tan(a.v, d);
  return {v, scale(a.g, Interval(1.0) + iaa::square(v))};
}
IGrad IntervalGradRules::atan(const IGrad& a) {
  return {iaa::atan(a.v), dquot(a.g, Interval(1.0) + iaa::square(a.v))};
}
// The point rule takes the slope +1 at 0, so only a strictly negative box is the mirrored side.
IGrad IntervalGradRules::abs(const IGrad& a) {
  if (a.v.lo() >= 0.0) return a;
  if (a.v.hi() < 0.0) return neg(a);
  return {iaa::abs(a.v), hulls(a.g, negate(a.g))};
}
// Ties follow the point rule (the first argument wins), so a decided box uses one side only.
IGrad IntervalGradRules::min(const IGrad& a, const IGrad& b, std::uint8_t*) {
  if (a.v.hi() <= b.v.lo()) return a;
  if (b.v.hi() < a.v.lo()) return b;
  return {iaa::min(a.v, b.v), hulls(a.g, b.g)};
}
IGrad IntervalGradRules::max(const IGrad& a, const IGrad& b, std::uint8_t*) {
  if (a.v.lo() >= b.v.hi()) return a;
  if (b.v.lo() > a.v.hi()) return b;
  return {iaa::max(a.v, b.v), hulls(a.g, b.g)};
}

}  // namespace iaa::detail
