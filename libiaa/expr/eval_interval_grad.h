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
struct IntervalGradRules {
  using Num = IGrad;
  static constexpr bool kTracksChoices = false;
  static IGrad constant(double v) {
    return {Interval(v), {Interval(0.0), Interval(0.0), Interval(0.0)}};
  }
  static IGrad add(const IGrad& a, const IGrad& b);
  static IGrad sub(const IGrad& a, const IGrad& b);
  static IGrad mul(const IGrad& a, const IGrad& b);
  static IGrad div(const IGrad& a, const IGrad& b, Domain*);
  static IGrad neg(const IGrad& a);
  static IGrad pow_int(const IGrad& a, int n);
  static IGrad pow(const IGrad& a, const IGrad& b, Domain*);
  static IGrad square(const IGrad& a);
  static IGrad sqrt(const IGrad& a, Domain*);
  static IGrad exp(const IGrad& a);
  static IGrad log(const IGrad& a, Domain*);
  static IGrad sin(const IGrad& a);
  static IGrad cos(const IGrad& a);
  static IGrad tan(const IGrad& a, Domain*);
  static IGrad atan(const IGrad& a);
  static IGrad abs(const IGrad& a);
  static IGrad min(const IGrad& a, const IGrad& b, std::uint8_t*);
  static IGrad max(const IGrad& a, const IGrad& b, std::uint8_t*);
};
}  // namespace detail

/// Evaluates a tape and its gradient over boxes. One per thread; no allocation per call.
class IntervalGradEval {
 public:
  explicit IntervalGradEval(const Tape& tape) : loop_(tape) {}
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit IntervalGradEval(Tape&&) = delete;
  IGrad eval(const IBox& b) {
    if (!rounding_is_upward()) {
      RoundingScope scope;
      return run(b);
    }
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
