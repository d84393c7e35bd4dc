// Point evaluation in double: f(x, y, z). Undefined points (sqrt of a negative, log of 0, a pole)
// give NaN or an infinity, never a finite wrong value; callers treat a non-finite value as "no
// surface here".
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "core/vec.h"
#include "expr/eval_loop.h"

namespace iaa {

namespace detail {
struct PointRules {
  using Num = double;
  static constexpr bool kTracksChoices = false;
  static double constant(double v) { return v; }
  static double add(double a, double b) { return a + b; }
  static double sub(double a, double b) { return a - b; }
  static double mul(double a, double b) { return a * b; }
  static double scale(double a, double c) { return a * c; }
  static double div_const(double a, double c) { return a / c; }
  // A pole (division by exactly 0, log of 0) is undefined, NaN, as in the interval rules; IEEE's
  // infinities would turn finite again downstream (atan(1/0) = pi/2) where intervals say empty.
  static double div(double a, double b, Domain*) {
    return b == 0.0 ? std::numeric_limits<double>::quiet_NaN() : a / b;
  }
  static double neg(double a) { return -a; }
  // Binary powering in the same order of multiplications as the interval rule (interval.h's
  // detail::pow_up/pow_down), so that the point value is bracketed by the interval bounds step by
  // step. Inline: it is the hot operation of polynomial surfaces.
  static double pow_int(double a, int n) {
    if (n == 0) return a == a ? 1.0 : a;  // x^0 = 1 wherever x is defined
    double x = std::fabs(a);
    double y = (n & 1) ? x : 1.0;
    for (int p = n >> 1; p > 0; p >>= 1) {
      x = x * x;
      if (p & 1) y = x * y;
    }
    return (a < 0.0 && (n & 1)) ? -y : y;
  }
  static double pow(double a, double b, Domain*);
  static double square(double a) { return a * a; }
  static double sqrt(double a, Domain*);
  static double exp(double a);
  static double log(double a, Domain*);
  static double sin(double a);
  static double cos(double a);
  static std::pair<double, double> sincos(double a);
  static double tan(double a, Domain*);
  static double atan(double a);
  static double abs(double a);
  // An undefined argument makes the result undefined (NaN), as in the interval rules: f is
  // defined only where every subexpression is.
  static double min(double a, double b, std::uint8_t*) { return (b < a || b != b) ? b : a; }
  static double max(double a, double b, std::uint8_t*) { return (b > a || b != b) ? b : a; }
};
}  // namespace detail

/// Evaluates a tape at points. One per thread; no allocation per call.
class PointEval {
 public:
  explicit PointEval(const Tape& tape) : loop_(tape) {}
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit PointEval(Tape&&) = delete;
  double eval(double x, double y, double z) { return loop_.run(x, y, z); }
  double eval(const Vec3& p) { return loop_.run(p.x, p.y, p.z); }
  const Tape& tape() const { return loop_.tape(); }

 private:
  detail::TapeLoop<detail::PointRules> loop_;
};

}  // namespace iaa
