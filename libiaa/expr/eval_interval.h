// Interval evaluation: an enclosure of f over a box, outward rounded. 0 outside the result proves
// that the box holds no point of the surface.
#pragma once

#include <utility>

#include "core/vec.h"
#include "expr/eval_loop.h"

namespace iaa {

namespace detail {
struct IntervalRules {
  using Num = Interval;
  static constexpr bool kTracksChoices = true;
  static Interval constant(double v) { return Interval(v); }
  static void store(Interval& o, const Interval& v) { o.store(v); }
  static Interval add(const Interval& a, const Interval& b) { return a + b; }
  static Interval sub(const Interval& a, const Interval& b) { return a - b; }
  static Interval mul(const Interval& a, const Interval& b) { return a * b; }
  static Interval scale(const Interval& a, double c) { return iaa::scale(a, c); }
  static Interval div_const(const Interval& a, double c) { return iaa::div_const(a, c); }
  static Interval div(const Interval& a, const Interval& b, Domain* d) { return divide(a, b, d); }
  static Interval neg(const Interval& a) { return -a; }
  static Interval pow_int(const Interval& a, int n) { return iaa::pow_int(a, n); }
  static Interval pow(const Interval& a, const Interval& b, Domain* d) { return pow_real(a, b, d); }
  static Interval square(const Interval& a) { return iaa::square(a); }
  static Interval sqrt(const Interval& a, Domain* d) { return iaa::sqrt(a, d); }
  static Interval exp(const Interval& a) { return iaa::exp(a); }
  static Interval log(const Interval& a, Domain* d) { return iaa::log(a, d); }
  static Interval sin(const Interval& a) { return iaa::sin(a); }
  static Interval cos(const Interval& a) { return iaa::cos(a); }
  static std::pair<Interval, Interval> sincos(const Interval& a) {
    std::pair<Interval, Interval> r;
    iaa::sincos(a, &r.first, &r.second);
    return r;
  }
  static Interval tan(const Interval& a, Domain* d) { return iaa::tan(a, d); }
  static Interval atan(const Interval& a) { return iaa::atan(a); }
  static Interval abs(const Interval& a) { return iaa::abs(a); }
  // min/max also record which argument is certainly taken (1 or 2), for Tape::simplify.
  static Interval min(const Interval& a, const Interval& b, std::uint8_t* c) {
    *c = min_choice(a, b);
    return iaa::min(a, b);
  }
  static Interval max(const Interval& a, const Interval& b, std::uint8_t* c) {
    *c = max_choice(a, b);
    return iaa::max(a, b);
  }
};
}  // namespace detail

/// Evaluates a tape over boxes. One per thread; no allocation per call. Opens a RoundingScope
/// itself when the caller has none (callers in hot loops open one per tile instead).
class IntervalEval {
 public:
  explicit IntervalEval(const Tape& tape) : loop_(tape) {}
  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit IntervalEval(Tape&&) = delete;

  /// Checked: evaluates under a RoundingScope, opening one when the caller has none. The check is
  /// an inline read of the rounding mode (interval.h), a few cycles per call; evaluation never
  /// runs in another mode.
  Interval eval(const IBox& b) {
    if (rounding_is_upward()) [[likely]]
      return loop_.run(b.x, b.y, b.z);
    RoundingScope scope;
    return loop_.run(b.x, b.y, b.z);
  }
  Interval eval(const Box3& b) { return eval(IBox(b)); }

  /// True when the last evaluation met a partial domain or a pole: f may be undefined or
  /// discontinuous somewhere in the box, so a sign change does not prove a root there.
  bool partial_domain() const { return loop_.partial_domain(); }
  /// Per instruction of the tape, the min/max argument the last box certainly took (0: both).
  const std::vector<std::uint8_t>& choices() const { return loop_.choices(); }
  const Tape& tape() const { return loop_.tape(); }

 private:
  detail::TapeLoop<detail::IntervalRules> loop_;
};

}  // namespace iaa
