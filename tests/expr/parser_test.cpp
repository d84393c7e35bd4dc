// Parser: precedence, folding, merged subexpressions, round trips and every error message.
#include "expr/parser.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "expr/eval_point.h"
#include "expr/tape.h"

namespace iaa {
namespace {

double at(const std::string& text, double x, double y = 0, double z = 0, const Params& p = {}) {
  const Tape t = Tape::parse(text, p);
  PointEval e(t);
  return e.eval(x, y, z);
}

// Expects a ParseError at (line, column) whose message contains `fragment`.
void expect_error(const std::string& text, int line, int column, const std::string& fragment) {
  try {
    Tape::parse(text);
    ADD_FAILURE() << "no error for: " << text.substr(0, 80);
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Parser, Precedence) {
  EXPECT_EQ(at("-x^2", 3), -9);
  EXPECT_EQ(at("2^3^2", 0), 512);  // right-associative
  EXPECT_EQ(at("1 + 2 * 3 - 4 / 2", 0), 5);
  EXPECT_EQ(at("(1 + 2) * 3", 0), 9);
  EXPECT_EQ(at("x - y - z", 10, 3, 2), 5);
  EXPECT_EQ(at("x / y / z", 12, 3, 2), 2);
  EXPECT_EQ(at("--x", 4), 4);
  EXPECT_EQ(at("+x", 4), 4);
}

TEST(Parser, NumbersNamesFunctions) {
  EXPECT_EQ(at("1e-3", 0), 1e-3);
  EXPECT_EQ(at(".5 + 2.", 0), 2.5);
  EXPECT_DOUBLE_EQ(at("pi", 0), 3.141592653589793);
  EXPECT_DOUBLE_EQ(at("e", 0), 2.718281828459045);
  EXPECT_EQ(at("min(x, y, z)", 3, 1, 2), 1);
  EXPECT_EQ(at("max(x, y, z, 7)", 3, 1, 2), 7);
  EXPECT_EQ(at("abs(x) + square(y) + sqrt(z)", -2, 3, 4), 13);
  EXPECT_DOUBLE_EQ(at("exp(log(x)) + sin(0) + cos(0) + tan(0) + atan(0)", 5), 6);
  EXPECT_EQ(at("x^2 - r^2", 3, 0, 0, {{"r", 2.0}}), 5);
  EXPECT_EQ(at("x # a comment\n + 1", 1), 2);
  EXPECT_EQ(at("pow(x, 3)", -2), -8);  // integer exponent: exact power, defined for x < 0
}

TEST(Parser, IntegerAndRealPowers) {
  EXPECT_EQ(at("x^3", -2), -8);
  EXPECT_EQ(at("x^(-2)", 2), 0.25);
  EXPECT_EQ(at("x^(1+2)", -2), -8);  // folded exactly to an integer exponent
  EXPECT_EQ(at("x^0", 0), 1);
  EXPECT_TRUE(std::isnan(at("x^2.5", -1)));  // real power: x >= 0 only
  EXPECT_DOUBLE_EQ(at("x^0.5", 4), 2);
  const Tape t = Tape::parse("x^3");
  EXPECT_EQ(t.instrs()[static_cast<std::size_t>(t.root())].op, Op::kPowInt);
}

TEST(Parser, CommonSubexpressionsAreMerged) {
  const Tape t = Tape::parse("(x^2 + y^2)^2 + sin(x^2 + y^2) + (y^2 + x^2)");
  // x^2, y^2, their sum (commutative: one node), its square, its sin, two additions.
  EXPECT_EQ(t.op_count(), 7) << t.listing();
}

TEST(Parser, SinAndCosOfOneArgumentArePaired) {
  const Tape t = Tape::parse("sin(2*z) * x + cos(2*z) * y + cos(x)");
  // 2*z, one sincos pair, cos(x) alone, two products, two sums.
  EXPECT_EQ(t.op_count(), 8) << t.listing();
  int pairs = 0;
  for (int i = t.first_op(); i < t.size(); ++i) {
    const Op op = t.instrs()[static_cast<std::size_t>(i)].op;
    if (op != Op::kSinCos) continue;
    ++pairs;
    ASSERT_LT(i + 1, t.size());
    EXPECT_EQ(t.instrs()[static_cast<std::size_t>(i + 1)].op, Op::kPairedCos);
    EXPECT_EQ(t.instrs()[static_cast<std::size_t>(i + 1)].a,
              t.instrs()[static_cast<std::size_t>(i)].a);
  }
  EXPECT_EQ(pairs, 1) << t.listing();
  EXPECT_EQ(t.to_text(), "sin(2 * z) * x + cos(2 * z) * y + cos(x)");
  EXPECT_DOUBLE_EQ(at("sin(2*z) * x + cos(2*z) * y", 1.5, 0.25, 0.25),
                   1.5 * std::sin(0.5) + 0.25 * std::cos(0.5));
}

TEST(Parser, QuotientsByFiniteNonZeroConstantsAreDivc) {
  const auto root_op = [](const char* e) {
    const Tape t = Tape::parse(e);
    return t.instrs()[static_cast<std::size_t>(t.root())].op;
  };
  EXPECT_EQ(root_op("x / 0.03"), Op::kDivConst);
  EXPECT_EQ(root_op("x / (-3)"), Op::kDivConst);
  EXPECT_EQ(root_op("x / 0"), Op::kDiv);  // a pole: stays a general quotient (partial domain)
  EXPECT_EQ(root_op("x / y"), Op::kDiv);
  EXPECT_EQ(root_op("3 / x"), Op::kDiv);
  EXPECT_EQ(Tape::parse("x / 0.5").to_text(), "x / 0.5");
  EXPECT_EQ(at("x / 0.03", 3), 3 / 0.03);
  EXPECT_EQ(at("y / (-4)", 0, 2), -0.5);
}

TEST(Parser, RoundTripThroughText) {
  const char* exprs[] = {
      "x^4 + y^4 + z^4 - x^2 - y^2 - z^2 + 0.5",
      "0.5*x^5 + 0.5*x^4 - y^2 - z^2",
      "min(x, 2*y) - max(abs(z), sqrt(x^2 + 1e-3)) / (1 + exp(-x))",
      "pow(x, y) + x^(-3) + atan(tan(z)) - log(1 + x^2) * -3",
      "x / 0.03 - y / (x / 7) + sin(z / 3) * cos(z / 3)",
  };
  for (const char* e : exprs) {
    const Tape a = Tape::parse(e);
    const Tape b = Tape::parse(a.to_text());
    // Same text and the same number of slots and operations (constants may be numbered apart).
    EXPECT_EQ(a.to_text(), b.to_text()) << e;
    EXPECT_EQ(a.size(), b.size()) << e;
    EXPECT_EQ(a.op_count(), b.op_count()) << e;
  }
}

TEST(Parser, TextOfLongExpressionsIsLinearAndCut) {
  // Parentheses: tape_text_test.cpp.
  // A sum of 10^5 terms: the text is written without one string per slot, and cut on request.
  std::string sum = "x";
  for (int i = 1; i < 100000; ++i) sum += " + x";
  const Tape t = Tape::parse(sum);
  const std::string cut = t.to_text(50);
  EXPECT_EQ(cut.size(), 53u);
  EXPECT_EQ(cut.substr(50), "...");
  const std::string full = t.to_text();
  EXPECT_EQ(full.size(), 100000u + 99999u * 3);  // "x" and per addition " + "
  EXPECT_EQ(t.to_text(full.size()), full);       // exactly long enough: not cut
}

TEST(Parser, ErrorsNamePositionAndExpectation) {
  expect_error("", 1, 1, "expected an expression");
  expect_error("   \n  ", 2, 3, "expected an expression");
  expect_error("x +", 1, 4, "expected a number, a name or '('");
  expect_error("(x + 1", 1, 7, "')'");
  expect_error("x + 1)", 1, 6, "expected an operator or end of input");
  expect_error("foo + 1", 1, 1, "unknown name 'foo'");
  expect_error("x +\n  bar", 2, 3, "unknown name 'bar'");
  expect_error("sqrt(x, y)", 1, 1, "sqrt takes 1 argument, got 2");
  expect_error("min(x)", 1, 1, "min needs at least 2 arguments");
  expect_error("sqrt x", 1, 1, "sqrt is a function");
  expect_error("x(2)", 1, 1, "'x' is not a function");
  expect_error("x^1000000", 1, 3, "too large");
  expect_error("x^-3", 1, 3, "x^(-3)");
  expect_error("1e999", 1, 1, "too large for a double");
  expect_error("nan", 1, 1, "unknown name 'nan'");
  expect_error("inf * x", 1, 1, "unknown name 'inf'");
  expect_error("2x", 1, 2, "expected an operator");
  expect_error("x $ y", 1, 3, "unexpected character '$'");
  expect_error("1e+", 1, 4, "digits after the exponent");
  expect_error("sqrt()", 1, 6, "needs an argument");
}

TEST(Parser, DeepNestingFailsCleanly) {
  const std::string deep = std::string(100000, '(') + "x" + std::string(100000, ')');
  expect_error(deep, 1, kMaxNesting + 1, "nested too deeply");
  const std::string signs = std::string(100000, '-') + "x";
  expect_error(signs, 1, kMaxNesting + 1, "nested too deeply");
  // Long but flat inputs are fine: no recursion per term.
  std::string sum = "x";
  for (int i = 0; i < 100000; ++i) sum += " + x";
  EXPECT_EQ(at(sum, 1), 100001);
  // Moderate nesting below the limit works.
  EXPECT_EQ(at(std::string(150, '(') + "x" + std::string(150, ')'), 2), 2);
}

TEST(Parser, BadParameters) {
  EXPECT_THROW(Tape::parse("x", {{"x", 1.0}}), Error);
  EXPECT_THROW(Tape::parse("r", {{"r", std::nan("")}}), Error);
  EXPECT_THROW(Tape::parse("r", {{"sqrt", 1.0}}), Error);
}

}  // namespace
}  // namespace iaa
