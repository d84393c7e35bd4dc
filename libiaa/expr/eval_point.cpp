// Rules of the two point modes (double, and double with gradient).
#include <cmath>
#include <limits>

#include "core/elementary.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"

namespace iaa::detail {

// Real power exp(b log a), defined for a > 0, and at a = 0 for b > 0 (as the interval rule):
// x^2.5 at x = -1 and 0^0 are undefined (NaN).
double PointRules::pow(double a, double b, Domain*) {
  if (a != a || a < 0.0 || (a == 0.0 && !(b > 0.0)) || b != b)
    return std::numeric_limits<double>::quiet_NaN();
  return std::pow(a, b);
}
double PointRules::sqrt(double a, Domain*) {
  return std::sqrt(a);
}
double PointRules::exp(double a) {
  return elementary::exp(a);
}
double PointRules::log(double a, Domain*) {
  return a > 0.0 ? elementary::log(a) : std::numeric_limits<double>::quiet_NaN();
}
double PointRules::sin(double a) {
  return elementary::sin(a);
}
double PointRules::cos(double a) {
  return elementary::cos(a);
}
std::pair<double, double> PointRules::sincos(double a) {
  std::pair<double, double> r;
  iaa::sincos(a, &r.first, &r.second);
  return r;
}
double PointRules::tan(double a, Domain*) {
  return std::tan(a);
}
double PointRules::atan(double a) {
  return std::atan(a);
}
double PointRules::abs(double a) {
  return std::fabs(a);
}

PGrad PointGradRules::div(const PGrad& a, const PGrad& b, Domain* d) {
  const double v = PointRules::div(a.v, b.v, d);
  return {v, (a.g - b.g * v) / b.v};
}
PGrad PointGradRules::pow_int(const PGrad& a, int n) {
  if (n == 0) return {PointRules::pow_int(a.v, 0), {}};
  return {PointRules::pow_int(a.v, n), a.g * (n * PointRules::pow_int(a.v, n - 1))};
}
PGrad PointGradRules::pow(const PGrad& a, const PGrad& b, Domain* d) {
  const double v = PointRules::pow(a.v, b.v, d);
  // d(a^b) = b a^(b-1) da + a^b log(a) db; the second term only where b varies.
  Vec3 g = a.g * (b.v * PointRules::pow(a.v, b.v - 1.0, d));
  const double l = PointRules::log(a.v, d);
  for (int i = 0; i < 3; ++i) {
    if (b.g[i] != 0.0) g[i] += v * l * b.g[i];
  }
  return {v, g};
}
PGrad PointGradRules::sqrt(const PGrad& a, Domain*) {
  const double v = std::sqrt(a.v);
  return {v, a.g / (2.0 * v)};
}
PGrad PointGradRules::exp(const PGrad& a) {
  const double v = elementary::exp(a.v);
  return {v, a.g * v};
}
PGrad PointGradRules::log(const PGrad& a, Domain* d) {
  return {PointRules::log(a.v, d), a.g / a.v};
}
PGrad PointGradRules::sin(const PGrad& a) {
  const auto [s, c] = PointRules::sincos(a.v);
  return {s, a.g * c};
}
PGrad PointGradRules::cos(const PGrad& a) {
  const auto [s, c] = PointRules::sincos(a.v);
  return {c, a.g * -s};
}
std::pair<PGrad, PGrad> PointGradRules::sincos(const PGrad& a) {
  const auto [s, c] = PointRules::sincos(a.v);
  return {PGrad{s, a.g * c}, PGrad{c, a.g * -s}};
}
PGrad PointGradRules::tan(const PGrad& a, Domain*) {
  const double v = std::tan(a.v);
  return {v, a.g * (1.0 + v * v)};
}
PGrad PointGradRules::atan(const PGrad& a) {
  return {std::atan(a.v), a.g / (1.0 + a.v * a.v)};
}
PGrad PointGradRules::abs(const PGrad& a) {
  return a.v < 0.0 ? neg(a) : a;
}

}  // namespace iaa::detail
