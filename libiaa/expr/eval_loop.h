// The one tape loop shared by every evaluator. Each evaluation mode supplies a `Rules` struct
// with its number type and one static function per operation (eval_point.h, eval_interval.h,
// eval_interval_grad.h, eval_point_grad.h); this template runs them over the tape. Keeping the
// loop in one place means every mode sees every opcode: a missing rule does not compile.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/interval.h"
#include "expr/tape.h"

namespace iaa::detail {

/// Writes an operation's result to its slot, with the mode's own store when it has one
/// (Rules::store: the interval modes write each interval with one 16-byte store, see
/// Interval::store). A mode that uses variable masks (below) gets the slot's mask as well.
template <class Rules, class Num, class... Mask>
inline void put(Num& o, const Num& v, Mask... m) {
  if constexpr (requires { Rules::store(o, v, m...); }) {
    Rules::store(o, v, m...);
  } else {
    o = v;
  }
}

/// Which argument of min(a, b) every point of a box takes, from their enclosures over it: 1 when
/// a <= b everywhere, 2 when b < a everywhere, else 0. Ties go to the first argument, as in the
/// point and gradient rules, so that a tape specialized by these choices (Tape::simplify) gives
/// the same values and gradients as the whole tape on the box and on every box inside it.
inline std::uint8_t min_choice(const Interval& a, const Interval& b) {
  return a.hi() <= b.lo() ? 1 : (b.hi() < a.lo() ? 2 : 0);
}
/// The same for max(a, b): 1 when a >= b everywhere, 2 when b > a everywhere.
inline std::uint8_t max_choice(const Interval& a, const Interval& b) {
  return a.lo() >= b.hi() ? 1 : (b.lo() > a.hi() ? 2 : 0);
}

/// Bits of the variables a slot depends on by structure: x = 1, y = 2, z = 4.
using VarMask = std::uint8_t;
inline constexpr VarMask kAllVars = 7;

/// Per slot, the variables its value depends on by structure: x, y, z their own bit, constants
/// none, an instruction the union of its arguments'. A partial derivative along a variable
/// outside the mask is exactly 0. Computed once per evaluator, linear in the tape.
inline std::vector<VarMask> var_masks(const Tape& tape) {
  std::vector<VarMask> m(static_cast<std::size_t>(tape.size()), 0);
  m[0] = 1;
  m[1] = 2;
  m[2] = 4;
  const auto ins = tape.instrs();
  for (int i = tape.first_op(); i < tape.size(); ++i) {
    const Instr& in = ins[static_cast<std::size_t>(i)];
    // kScale's and kDivConst's b is a constant slot (mask 0), kPowInt has no b.
    VarMask v = m[static_cast<std::size_t>(in.a)];
    if (in.b >= 0) v |= m[static_cast<std::size_t>(in.b)];
    m[static_cast<std::size_t>(i)] = v;
  }
  return m;
}

/// A mode whose rules take the output slot's VarMask as a last argument (and compute only the
/// components it names; the others stay as the slot was initialized).
template <class Rules>
concept UsesVarMasks = requires {
  requires Rules::kUsesVarMasks;
};

template <class Rules>
class TapeLoop {
 public:
  using Num = typename Rules::Num;

  /// `dense` (masked modes only): every slot's mask is kAllVars, so every component is computed,
  /// as without masks (a reference for tests). `wanted` (masked modes only): only the components
  /// of these variables are computed, each exactly as with all of them (a component depends on
  /// the same component of the arguments only); the others stay [0,0] in every result.
  explicit TapeLoop(const Tape& tape, bool dense = false, VarMask wanted = kAllVars)
      : tape_(&tape), slots_(static_cast<std::size_t>(tape.size())) {
    if constexpr (UsesVarMasks<Rules>) {
      masks_ = dense ? std::vector<VarMask>(slots_.size(), kAllVars) : var_masks(tape);
      for (VarMask& m : masks_) m = VarMask(m & wanted);
    }
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
      // `m` is empty, or the slot's mask for a mode that uses masks. Forced inline: with the
      // eight mask copies below GCC otherwise keeps the step (and the rules in it) out of line,
      // which is slower even though it runs fewer instructions (docs/eval.md).
      const auto step = [&](auto... m) __attribute__((always_inline)) {
        switch (in.op) {
          case Op::kAdd:
            put<Rules>(o, Rules::add(a, s[in.b], m...), m...);
            break;
          case Op::kSub:
            put<Rules>(o, Rules::sub(a, s[in.b], m...), m...);
            break;
          case Op::kMul:
            put<Rules>(o, Rules::mul(a, s[in.b], m...), m...);
            break;
          case Op::kScale:
            put<Rules>(o, Rules::scale(a, k[in.b], m...), m...);
            break;
          case Op::kDiv:
            put<Rules>(o, Rules::div(a, s[in.b], &dom_, m...), m...);
            break;
          case Op::kDivConst:
            put<Rules>(o, Rules::div_const(a, k[in.b], m...), m...);
            break;
          case Op::kNeg:
            put<Rules>(o, Rules::neg(a, m...), m...);
            break;
          case Op::kPowInt:
            put<Rules>(o, Rules::pow_int(a, in.power, m...), m...);
            break;
          case Op::kPow:
            put<Rules>(o, Rules::pow(a, s[in.b], &dom_, m...), m...);
            break;
          case Op::kSquare:
            put<Rules>(o, Rules::square(a, m...), m...);
            break;
          case Op::kSqrt:
            put<Rules>(o, Rules::sqrt(a, &dom_, m...), m...);
            break;
          case Op::kExp:
            put<Rules>(o, Rules::exp(a, m...), m...);
            break;
          case Op::kLog:
            put<Rules>(o, Rules::log(a, &dom_, m...), m...);
            break;
          case Op::kSin:
            put<Rules>(o, Rules::sin(a, m...), m...);
            break;
          case Op::kCos:
            put<Rules>(o, Rules::cos(a, m...), m...);
            break;
          case Op::kSinCos: {
            // Slot i + 1 is the paired cos of the same argument, so it has this slot's mask.
            const auto [sv, cv] = Rules::sincos(a, m...);
            put<Rules>(o, sv, m...);
            put<Rules>(s[i + 1], cv, m...);
            break;
          }
          case Op::kPairedCos:
            break;  // written by the sincos before it
          case Op::kTan:
            put<Rules>(o, Rules::tan(a, &dom_, m...), m...);
            break;
          case Op::kAtan:
            put<Rules>(o, Rules::atan(a, m...), m...);
            break;
          case Op::kAbs:
            put<Rules>(o, Rules::abs(a, m...), m...);
            break;
          case Op::kMin:
            put<Rules>(o, Rules::min(a, s[in.b], choice(i), m...), m...);
            break;
          case Op::kMax:
            put<Rules>(o, Rules::max(a, s[in.b], choice(i), m...), m...);
            break;
          case Op::kVarX:
          case Op::kVarY:
          case Op::kVarZ:
          case Op::kConst:
            break;  // never after first_op
        }
      };
      if constexpr (UsesVarMasks<Rules>) {
        // One copy of the step per mask value, the mask a compile-time constant in each, so the
        // rules' per-component tests fold away.
        switch (masks_[static_cast<std::size_t>(i)]) {
          case 0:
            step(std::integral_constant<VarMask, 0>{});
            break;
          case 1:
            step(std::integral_constant<VarMask, 1>{});
            break;
          case 2:
            step(std::integral_constant<VarMask, 2>{});
            break;
          case 3:
            step(std::integral_constant<VarMask, 3>{});
            break;
          case 4:
            step(std::integral_constant<VarMask, 4>{});
            break;
          case 5:
            step(std::integral_constant<VarMask, 5>{});
            break;
          case 6:
            step(std::integral_constant<VarMask, 6>{});
            break;
          default:
            step(std::integral_constant<VarMask, kAllVars>{});
            break;
        }
      } else {
        step();
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
  std::vector<VarMask> masks_;  ///< per slot, for modes that use masks
  Domain dom_ = Domain::kFull;
};

}  // namespace iaa::detail
