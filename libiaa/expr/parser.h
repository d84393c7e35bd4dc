// Parser of the surface language.
//
//   expr     := term (('+' | '-') term)*
//   term     := unary (('*' | '/') unary)*
//   unary    := ('-' | '+') unary | power
//   power    := primary ('^' exponent)?        right-associative: x^2^3 = x^(2^3)
//   exponent := primary ('^' exponent)?        no sign here: write x^(-3)
//   primary  := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
//             | '(' ('-' | '+') number ')'      a signed number: one leaf, as the tape writes it
//
// `^` binds tighter than unary minus (-x^2 is -(x^2)). An exponent that is an integer constant is
// an exact integer power (x^3 is x*x*x, defined for negative x); a negative one is a reciprocal
// (x^(-2) = 1/x^2); any other exponent is the real power exp(y log x), defined for x >= 0 only.
// Names: x y z, the constants pi and e, parameters supplied by the caller, and the functions of
// opcodes.h (min and max take two or more arguments). `#` starts a comment to the end of the line.
// Numeric literals are rounded to the nearest double: the surface iaa certifies is the one with
// those doubles. Sums, differences, products and powers of integer constants are folded when exact.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <string_view>

#include "expr/dag.h"

namespace iaa {

/// Named parameters of an expression (a scene's `r = 0.3`).
using Params = std::map<std::string, double, std::less<>>;

/// Deepest nesting of parentheses, calls, unary signs and exponents the parser accepts (a signed
/// number in parentheses, `(-2.5)`, is a leaf and does not count). The parser recurses once per
/// level, so the limit keeps a hostile input from overflowing the stack.
inline constexpr int kMaxNesting = 200;

/// Parses `text` into a DAG whose `root` is the expression. Throws ParseError with the line and
/// column of the problem and what was expected there.
Dag parse_expression(std::string_view text, const Params& params = {});

/// True for names reserved by the language (x y z pi e and function names); a parameter may not
/// use them.
bool is_reserved_name(std::string_view name);

}  // namespace iaa
