// Point evaluation with the gradient, by forward-mode differentiation. At kinks (abs at 0, min/max
// ties) the gradient of one side is returned; the interval gradient contains both sides.
#pragma once

#include <utility>

#include "core/vec.h"
#include "expr/eval_loop.h"

namespace iaa {

/// A value and its gradient.
struct PGrad {
  double v = 0.0;
  Vec3 g;
};

namespace detail {
struct PointGradRules {
  using Num = PGrad;
  static constexpr bool kTracksChoices = false;
  static PGrad constant(double v) { return {v, {}}; }
  static PGrad add(const PGrad& a, const PGrad& b) { return {a.v + b.v, a.g + b.g}; }
  static PGrad sub(const PGrad& a, const PGrad& b) { return {a.v - b.v, a.g - b.g}; }
  static PGrad mul(const PGrad& a, const PGrad& b) { return {a.v * b.v, a.g * b.v + b.g * a.v}; }
  static PGrad scale(const PGrad& a, double c) { return {a.v * c, a.g * c}; }
  static PGrad div_const(const PGrad& a, double c) { return {a.v / c, a.g / c}; }
  static PGrad div(const PGrad& a, const PGrad& b, Domain*);
  static PGrad neg(const PGrad& a) { return {-a.v, -a.g}; }
  static PGrad pow_int(const PGrad& a, int n);
  static PGrad pow(const PGrad& a, const PGrad& b, Domain*);
  static PGrad square(const PGrad& a) { return {a.v * a.v, a.g * (2.0 * a.v)}; }
  static PGrad sqrt(const PGrad& a, Domain*);
  static PGrad exp(const PGrad& a);
  static PGrad log(const PGrad& a, Domain*);
  static PGrad sin(const PGrad& a);
  static PGrad cos(const PGrad& a);
  static std::pair<PGrad, PGrad> sincos(const PGrad& a);
  static PGrad tan(const PGrad& a, Domain*);
  static PGrad atan(const PGrad& a);
  static PGrad abs(const PGrad& a);
  static PGrad min(const PGrad& a, const PGrad& b, std::uint8_t*) {
    return (b.v < a.v || b.v != b.v) ? b : a;
  }
  static PGrad max(const PGrad& a, const PGrad& b, std::uint8_t*) {
    return (b.v > a.v || b.v != b.v) ? b : a;
  }
};
}  // namespace detail

/// Evaluates a tape and its gradient at points. One per thread; no allocation per call.
class PointGradEval {
 public:
  explicit PointGradEval(const Tape& tape) : loop_(tape) {}
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit PointGradEval(Tape&&) = delete;
  PGrad eval(const Vec3& p) {
    return loop_.run({p.x, {1, 0, 0}}, {p.y, {0, 1, 0}}, {p.z, {0, 0, 1}});
  }
  const Tape& tape() const { return loop_.tape(); }

 private:
  detail::TapeLoop<detail::PointGradRules> loop_;
};

}  // namespace iaa
