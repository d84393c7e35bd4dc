// The one list of operations (docs/design.md, "Expressions and tapes"). Each entry names an
// operation once:
//   X(enumerator, text name, arity, callable)
// `callable` operations can be written as functions in the surface language (`sqrt(x)`); the
// others come from operators (`+ - * / ^`) or are leaves. Parser, tape printer and evaluators are
// driven by this list; adding a function is one line here plus its evaluation rule in each
// evaluator (the compiler points at every switch that misses it). `scale` is a product whose second
// argument is a finite non-zero constant; only the tape compiler makes it (Tape::compile), so
// that evaluators multiply by a known number without the tests a general product needs. `divc`
// likewise is a quotient by a finite non-zero constant (second): never partial, and its
// derivative is the numerator's divided by the constant.
// `sincos` and the `cos` after it are also the tape compiler's: where an expression takes both
// sin(a) and cos(a), slot i (sincos) gets sin(a) and slot i + 1 (paired cos) cos(a), both from one
// evaluation of the pair, as the interval and gradient rules share their work on a.
#pragma once

#include <cstdint>
#include <string_view>

namespace iaa {

#define IAA_OPCODES(X)           \
  X(kVarX, "x", 0, false)        \
  X(kVarY, "y", 0, false)        \
  X(kVarZ, "z", 0, false)        \
  X(kConst, "const", 0, false)   \
  X(kAdd, "add", 2, false)       \
  X(kSub, "sub", 2, false)       \
  X(kMul, "mul", 2, false)       \
  X(kScale, "scale", 2, false)   \
  X(kDiv, "div", 2, false)       \
  X(kDivConst, "divc", 2, false) \
  X(kNeg, "neg", 1, false)       \
  X(kPowInt, "powi", 1, false)   \
  X(kPow, "pow", 2, true)        \
  X(kSquare, "square", 1, true)  \
  X(kSqrt, "sqrt", 1, true)      \
  X(kExp, "exp", 1, true)        \
  X(kLog, "log", 1, true)        \
  X(kSin, "sin", 1, true)        \
  X(kCos, "cos", 1, true)        \
  X(kTan, "tan", 1, true)        \
  X(kAtan, "atan", 1, true)      \
  X(kAbs, "abs", 1, true)        \
  X(kMin, "min", 2, true)        \
  X(kMax, "max", 2, true)        \
  X(kSinCos, "sincos", 1, false) \
  X(kPairedCos, "cos", 1, false)

/// An operation of the expression language.
enum class Op : std::uint8_t {
#define IAA_OP_ENUM(name, text, arity, callable) name,
  IAA_OPCODES(IAA_OP_ENUM)
#undef IAA_OP_ENUM
};

/// Static facts about an operation, from IAA_OPCODES.
struct OpInfo {
  std::string_view text;
  int arity;
  bool callable;
};

inline constexpr OpInfo kOpInfo[] = {
#define IAA_OP_INFO(name, text, arity, callable) {text, arity, callable},
    IAA_OPCODES(IAA_OP_INFO)
#undef IAA_OP_INFO
};

inline constexpr int kOpCount = sizeof(kOpInfo) / sizeof(kOpInfo[0]);

inline const OpInfo& info(Op op) {
  return kOpInfo[static_cast<int>(op)];
}

/// True for operations whose arguments can be swapped (merged as one node either way).
inline bool is_commutative(Op op) {
  return op == Op::kAdd || op == Op::kMul || op == Op::kMin || op == Op::kMax;
}

/// Largest integer exponent accepted in `x^n` (larger powers overflow doubles for |x| > 16).
inline constexpr int kMaxIntPower = 256;

}  // namespace iaa
