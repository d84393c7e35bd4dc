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
    const int n = tape_->size();
    for (int i = tape_->first_op(); i < n; ++i) {
      const Instr& in = ins[i];
      const Num& a = s[in.a];
      Num& o = s[i];
      switch (in.op) {
        case Op::kAdd:
          o = Rules::add(a, s[in.b]);
          break;
        case Op::kSub:
          o = Rules::sub(a, s[in.b]);
          break;
        case Op::kMul:
          o = Rules::mul(a, s[in.b]);
          break;
        case Op::kDiv:
          o = Rules::div(a, s[in.b], &dom_);
          break;
        case Op::kNeg:
          o = Rules::neg(a);
          break;
        case Op::kPowInt:
          o = Rules::pow_int(a, in.power);
          break;
        case Op::kPow:
          o = Rules::pow(a, s[in.b], &dom_);
          break;
        case Op::kSquare:
          o = Rules::square(a);
          break;
        case Op::kSqrt:
          o = Rules::sqrt(a, &dom_);
          break;
        case Op::kExp:
          o = Rules::exp(a);
          break;
        case Op::kLog:
          o = Rules::log(a, &dom_);
          break;
        case Op::kSin:
          o = Rules::sin(a);
          break;
        case Op::kCos:
          o = Rules::cos(a);
          break;
        case Op::kTan:
          o = Rules::tan(a, &dom_);
          break;
        case Op::kAtan:
          o = Rules::atan(a);
          break;
        case Op::kAbs:
          o = Rules::abs(a);
          break;
        case Op::kMin:
          o = Rules::min(a, s[in.b], choice(i));
          break;
        case Op::kMax:
          o = Rules::max(a, s[in.b], choice(i));
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
