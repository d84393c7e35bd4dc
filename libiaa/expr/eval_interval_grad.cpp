// The real-power rule of the interval + gradient mode (the other rules are inline in the header).
#include "expr/eval_interval_grad.h"

namespace iaa::detail {

IGrad IntervalGradRules::pow(const IGrad& a, const IGrad& b, Domain* d, VarMask m) {
  const Interval v = pow_real(a.v, b.v, d);
  Domain ignored = Domain::kFull;
  // (a^b)' = b a^(b-1) a' + a^b log(a) b'
  // a^(b-1) has a pole where a reaches 0 and b < 1 (empty there): the factor is then unbounded.
  Interval power = pow_real(a.v, b.v - Interval(1.0), &ignored);
  if (power.is_empty()) power = Interval::whole();
  igrad::G g = igrad::scale(a.g, b.v * power, m);
  // The log term only where the exponent varies: log(a) may be empty (a = 0) while a^b is not.
  // At a = 0 (where a^b = 0 for b > 0) log(a) is empty or unbounded while a^b log(a) -> 0: no
  // finite bound is derived there, the term is left unbounded (still exactly 0 where v = 0).
  Interval l = iaa::log(a.v, &ignored);
  if (l.is_empty()) l = Interval::whole();
  for (std::size_t i = 0; i < 3; ++i) {
    if (!(m & (1u << i))) continue;
    if (b.g[i].lo() != 0.0 || b.g[i].hi() != 0.0) g[i] = g[i] + b.g[i] * (v * l);
  }
  return {v, g};
}

}  // namespace iaa::detail
