// Tape::to_text round trips (tape_text.cpp): the text of a parsed tape parses back to a tape of
// the same shape (up to the order of commutative operands) that evaluates identically. A property
// over random expressions and random long chains, and the shapes that nest deepest: flat sums whose
// terms the DAG reorders (printed right-nested, past 200 terms unparseable, before), min/max of
// many arguments, deep calls, signs and powers, negative constants where a power needs a leaf.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "expr/eval_interval.h"
#include "expr/eval_point.h"
#include "expr/parser.h"
#include "random_expr.h"

namespace iaa {
namespace {

using iaa::testing::property_scale;
using iaa::testing::RandomExpr;

/// Equality of two point values as numbers, NaN equal to NaN. -0 equals +0: min and max of two
/// zeros give the first, and the DAG orders their operands as it met them (tape.cpp).
bool same(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

/// A hash of the expression a tape computes, blind to the order of the operands of + * min max
/// (the DAG orders them by where a subexpression first appears in the text, tape.cpp).
std::uint64_t shape(const Tape& t) {
  const auto mix = [](std::uint64_t v) {  // splitmix64's finalizer
    v = (v ^ (v >> 30)) * 0xBF58476D1CE4E5B9ull;
    v = (v ^ (v >> 27)) * 0x94D049BB133111EBull;
    return v ^ (v >> 31);
  };
  std::vector<std::uint64_t> h(static_cast<std::size_t>(t.size()));
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Instr& in = t.instrs()[i];
    // The compiler's kinds of one operation hash as that operation (scale(c, d) of two constants
    // may come out either way round).
    Op op = in.op == Op::kSinCos ? Op::kSin : in.op == Op::kPairedCos ? Op::kCos : in.op;
    if (op == Op::kScale) op = Op::kMul;
    std::uint64_t a = in.a >= 0 ? h[static_cast<std::size_t>(in.a)] : 0;
    std::uint64_t b = in.b >= 0 ? h[static_cast<std::size_t>(in.b)] : 0;
    if (is_commutative(op) && a > b) std::swap(a, b);
    const std::uint64_t value = op == Op::kConst ? std::bit_cast<std::uint64_t>(t.constants()[i])
                                                 : static_cast<std::uint64_t>(in.power);
    h[i] = mix(mix(mix(static_cast<std::uint64_t>(op) ^ value) + a) + 3 * b);
  }
  return h[static_cast<std::size_t>(t.root())];
}

/// The text parses to a tape of the same shape and size, which evaluates identically (point and
/// interval) on a few random boxes and points.
void expect_round_trip(const std::string& text, RandomExpr& gen, const Params& params = {}) {
  const Tape t = Tape::parse(text, params);
  const std::string printed = t.to_text();
  const std::string shown = text.size() > 300 ? text.substr(0, 300) + "..." : text;
  Tape back;
  try {
    back = Tape::parse(printed);
  } catch (const ParseError& e) {
    FAIL() << e.what() << "\nexpression: " << shown << "\nprinted: " << printed.substr(0, 300);
  }
  ASSERT_EQ(back.size(), t.size()) << shown;
  ASSERT_EQ(back.op_count(), t.op_count()) << shown;
  ASSERT_EQ(shape(back), shape(t)) << shown << "\nprinted: " << printed.substr(0, 300);
  PointEval pa(t), pb(back);
  IntervalEval ia(t), ib(back);
  for (int k = 0; k < 4; ++k) {
    const IBox box = gen.box();
    const Vec3 p = gen.point(box);
    ASSERT_TRUE(same(pa.eval(p), pb.eval(p))) << shown;
    ASSERT_EQ(ia.eval(box), ib.eval(box)) << shown;
  }
}

/// `n` random terms joined by random + and - (or * and /), as a user writes a long sum.
std::string chain(RandomExpr& gen, int n, const char* ops[2]) {
  std::string s = gen.make(1);
  for (int i = 1; i < n; ++i) s += std::string(ops[gen.pick(2)]) + gen.make(gen.pick(3));
  return s;
}

TEST(TapeTextProperty, RandomExpressionsAndChainsRoundTrip) {
  RandomExpr gen(0x7E47 + 131 * (property_scale() - 1));
  const char* sums[2] = {" + ", " - "};
  const char* products[2] = {" * ", " / "};
  const int n = 4000 * property_scale();
  for (int i = 0; i < n; ++i) {
    std::string e;
    switch (gen.pick(8)) {
      case 0:
        e = chain(gen, 1 + gen.pick(1000), sums);
        break;
      case 1:
        e = chain(gen, 1 + gen.pick(300), products);
        break;
      case 2:
        e = (gen.pick(2) ? "min(" : "max(") + chain(gen, 2, sums);
        for (int k = gen.pick(300); k >= 0; --k) e += ", " + gen.make(gen.pick(3));
        e += ")";
        break;
      default:
        e = gen.make(1 + gen.pick(6));
    }
    if (!gen.parses(e)) continue;
    expect_round_trip(e, gen);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

/// `open` repeated n times, then `core`, then `close` repeated n times.
std::string nest(const std::string& open, int n, const std::string& core,
                 const std::string& close) {
  std::string s;
  for (int i = 0; i < n; ++i) s += open;
  s += core;
  for (int i = 0; i < n; ++i) s += close;
  return s;
}

TEST(TapeText, DeepestShapesRoundTrip) {
  RandomExpr gen(5);
  // Terms that the DAG merges or met before: the sum's chain lands on the right of each addition.
  std::string sum = "x";
  const char* terms[] = {" + y", " + z", " + x", " - y", " + 2 * x", " + x * y"};
  for (int i = 0; i < 1000; ++i) sum += terms[i % 6];
  expect_round_trip(sum, gen);
  std::string product = "x";
  for (int i = 0; i < 300; ++i) product += i % 3 ? " * y" : " * x";
  expect_round_trip(product, gen);
  std::string many = "min(x";
  for (int i = 0; i < 1000; ++i) many += i % 2 ? ", y" : ", x + " + std::to_string(i);
  expect_round_trip(many + ")", gen);
  expect_round_trip("max(" + many.substr(4) + ", " + many + "), z)", gen);
  // As deep as the parser allows: the text must not nest deeper than the input did.
  const int d = kMaxNesting - 1;
  expect_round_trip(nest("x + (", d, "y", ")"), gen);
  expect_round_trip(nest("sin(", d, "x", ")"), gen);
  expect_round_trip(nest("-", d, "x", ""), gen);
  expect_round_trip(nest("x^", d, "y", ""), gen);
  expect_round_trip(nest("sqrt(2 * ", d, "x", ")"), gen);
  expect_round_trip(nest("min(x, ", d, "y", ")"), gen);
  expect_round_trip(nest("abs(", d - 1, "x^2", ")"), gen);
  // Negative constants (a parameter, a fold) where a power needs a leaf.
  const Params r{{"r", -0.5}};
  expect_round_trip(nest("sin(", d - 1, "r^x", ")"), gen, r);
  expect_round_trip(nest("sin(", d - 1, "x^r", ")"), gen, r);
  expect_round_trip(nest("cos(", d - 1, "pow(r, 2.5) * (0 - 3)", ")"), gen, r);
  expect_round_trip("square(3) + 1 / x^3 + (x * y)^3 + 2 * (x * y) + x - -y * -3", gen);
  // Integer powers of integers fold, except under a negative exponent.
  expect_round_trip(
      "2^(-3) + x^(-3) + (-2)^(-5) + 2.5^(-4) + 3^(-2) + 3^40 + pow(2, -3) + 1 / pi^0", gen);
}

TEST(TapeText, MinimalParentheses) {
  const auto text = [](const char* e) { return Tape::parse(e).to_text(); };
  EXPECT_EQ(text("x - y - z + 1"), "x - y - z + 1");
  EXPECT_EQ(text("x / y * z"), "x / y * z");
  EXPECT_EQ(text("x - (y - z)"), "x - (y - z)");
  EXPECT_EQ(text("(x + y) * (x - y)"), "(x + y) * (x - y)");
  EXPECT_EQ(text("-x^2 + (-x)^3"), "-x^2 + (-x)^3");
  // A power as a base is written as a call, which nests less than parentheses.
  EXPECT_EQ(text("x^y^z + (x^y)^z"), "x^y^z + pow(x, y)^z");
  EXPECT_EQ(text("min(min(x, y), z, max(x, 1))"), "min(x, y, z, max(x, 1))");
  EXPECT_EQ(text("x * -3 + (-2)^x"), "(-3) * x + (-2)^x");
  EXPECT_EQ(text("2 * x + x * y * 2"), "2 * x + x * y * 2");
  // The DAG puts x (met first) before the chain: the printer writes the chain on the left.
  EXPECT_EQ(text("x + y + z + x"), "x + y + z + x");
}

}  // namespace
}  // namespace iaa
