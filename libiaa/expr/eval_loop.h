// The one tape loop shared by every evaluator. Each evaluation mode supplies a `Rules` struct
// with its number type and one static function per operation (eval_point.h, eval_interval.h,
// eval_interval_grad.h, eval_point_grad.h); this template runs them over the tape. Keeping the
// loop in one place means every mode sees every opcode: a missing rule does not compile.
#pragma once

#include <cstdint>
#include <vector>

#include "core/interval.h"
#include "expr/tape.h"

namespace iaa::detail {

/// Writes an operation's result to its slot, with the mode's own store when it has one
/// (Rules::store: the interval modes write each interval with one 16-byte store, see
/// Interval::store).
template <class Rules, class Num>
inline void put(Num& o, const Num& v) {
  if constexpr (requires { Rules::store(o, v); }) {
    Rules::store(o, v);
  } else {
    o = v;
  }
}

template <class Rules>
class TapeLoop {
 public:
  using Num = typename Rules::Num;

  explicit TapeLoop(const Tape& tape)
      : tape_(&tape), slots_(static_cast<std::size_t>(tape.size())) {
    const auto consts = tape.constants();
    for (int i = 3; i < tape.first_op(); ++i) {
      slots_[static_cast<std::size_t>(i)] = Rules::constant(consts[static_cast<std::size_t>(i)]);
    }
    if (Rules::kTracksChoices) choices_.assign(slots_.size(), 0);
  }

  const Tape& tape() const { return *tape_; }
  /// True when the last run met a partial domain or a pole (see interval.h).
  bool partial_domain() const { return dom_ == Domain::kPartial; }
  /// For modes that track them: per instruction, which min/max argument was certainly taken.
  const std::vector<std::uint8_t>& choices() const { return choices_; }

  Num run(const Num& x, const Num& y, const Num& z) {
    Num* s = slots_.data();
    s[0] = x;
    s[1] = y;
    s[2] = z;
    dom_ = Domain::kFull;
    const Instr* ins = tape_->instrs().data();
    const double* k = tape_->constants().data();
    const int n = tape_->size();
    for (int i = tape_->first_op(); i < n; ++i) {
      const Instr& in = ins[i];
      const Num& a = s[in.a];
      Num& o = s[i];
      switch (in.op) {
        case Op::kAdd:
          put<Rules>(o, Rules::add(a, s[in.b]));
          break;
        case Op::kSub:
          put<Rules>(o, Rules::sub(a, s[in.b]));
          break;
        case Op::kMul:
          put<Rules>(o, Rules::mul(a, s[in.b]));
          break;
        case Op::kScale:
          put<Rules>(o, Rules::scale(a, k[in.b]));
          break;
        case Op::kDiv:
          put<Rules>(o, Rules::div(a, s[in.b], &dom_));
          break;
        case Op::kNeg:
          put<Rules>(o, Rules::neg(a));
          break;
        case Op::kPowInt:
          put<Rules>(o, Rules::pow_int(a, in.power));
          break;
        case Op::kPow:
          put<Rules>(o, Rules::pow(a, s[in.b], &dom_));
          break;
        case Op::kSquare:
          put<Rules>(o, Rules::square(a));
          break;
        case Op::kSqrt:
          put<Rules>(o, Rules::sqrt(a, &dom_));
          break;
        case Op::kExp:
          put<Rules>(o, Rules::exp(a));
          break;
        case Op::kLog:
          put<Rules>(o, Rules::log(a, &dom_));
          break;
        case Op::kSin:
          put<Rules>(o, Rules::sin(a));
          break;
        case Op::kCos:
          put<Rules>(o, Rules::cos(a));
          break;
        case Op::kTan:
          put<Rules>(o, Rules::tan(a, &dom_));
          break;
        case Op::kAtan:
          put<Rules>(o, Rules::atan(a));
          break;
        case Op::kAbs:
          put<Rules>(o, Rules::abs(a));
          break;
        case Op::kMin:
          put<Rules>(o, Rules::min(a, s[in.b], choice(i)));
          break;
        case Op::kMax:
          put<Rules>(o, Rules::max(a, s[in.b], choice(i)));
          break;
        case Op::kVarX:
        case Op::kVarY:
        case Op::kVarZ:
        case Op::kConst:
          break;  // never after first_op
      }
    }
    return s[tape_->root()];
  }

 private:
  std::uint8_t* choice(int i) {
    return Rules::kTracksChoices ? &choices_[static_cast<std::size_t>(i)] : nullptr;
  }

  const Tape* tape_;
  std::vector<Num> slots_;
  std::vector<std::uint8_t> choices_;
  Domain dom_ = Domain::kFull;
};

}  // namespace iaa::detail
