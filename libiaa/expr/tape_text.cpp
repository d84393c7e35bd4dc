// Tape::to_text: a tape written back as expression text that the parser reads to the same tape.
//
// The parser limits nesting (parentheses, calls, signs and exponents, kMaxNesting) and reads
// chains of + - * / and the arguments of min/max from the left. The text is therefore laid out
// for the least nesting: parentheses only where precedence needs them, chains written flat, and
// the operands of commutative operations (+ * min max, whose order the DAG does not keep) ordered
// so that a chain stays on the left. A first pass computes, for every slot, how deeply its text
// nests in each form; the second writes the text from an explicit stack (a sum of 10^5 terms is
// a chain 10^5 deep: no recursion, and no string per slot).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "expr/tape.h"

namespace iaa {

namespace {

// Precedence levels of a written form, lowest first. An operand written at a lower level than
// its position requires is parenthesized.
enum Level : std::uint8_t {
  kAny = 1,      // a sum or difference; also what a call argument or the whole text accepts
  kProduct = 2,  // a product or quotient
  kSigned = 3,   // -a
  kPower = 4,    // a^b
  kPrimary = 5,  // a name, a number, a call, a parenthesized expression
};

std::string format_number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s(buf);
  // A negative constant is parenthesized: "(-2.5)", a single leaf to the parser.
  return v < 0 ? "(" + s + ")" : s;
}

bool is_sum(Op op) {
  return op == Op::kAdd || op == Op::kSub;
}
bool is_product(Op op) {
  return op == Op::kMul || op == Op::kScale || op == Op::kDiv || op == Op::kDivConst;
}
bool is_commutative_infix(Op op) {
  return op == Op::kAdd || op == Op::kMul || op == Op::kScale;
}

/// How each slot is best written and how deeply that nests (the first pass).
class Layout {
 public:
  explicit Layout(const Tape& t) : t_(t) {
    const auto n = static_cast<std::size_t>(t.size());
    inner_.assign(n, 0);
    call_inner_.assign(n, 0);
    flip_.assign(n, 0);
    chain_.assign(n, 0);
    for (int i = t.first_op(); i < t.size(); ++i) measure(i);
  }

  const Instr& in(int s) const { return t_.instrs()[static_cast<std::size_t>(s)]; }
  /// True when the arguments are written b first (commutative operations only).
  bool flipped(int s) const { return flip_[static_cast<std::size_t>(s)] != 0; }
  /// For min/max: the first argument's own min/max chain is written into this call.
  bool chained(int s) const { return chain_[static_cast<std::size_t>(s)] != 0; }
  /// The first and second operand as written.
  int first(int s) const { return flipped(s) ? in(s).b : in(s).a; }
  int second(int s) const { return flipped(s) ? in(s).a : in(s).b; }

  /// kPow is written pow(a, b) rather than a^b at `level`.
  bool pow_as_call(int s, int level) const {
    return call_inner_[static_cast<std::size_t>(s)] < caret_need(s, level);
  }
  /// The level of the form slot s is written in at a position requiring `level`.
  int written_level(int s, int level) const {
    const Op op = in(s).op;
    if (op == Op::kPow) return pow_as_call(s, level) ? kPrimary : kPower;
    if (op == Op::kSquare) return square_as_call(s) ? kPrimary : kPower;
    if (reciprocal_power(s)) return kPower;
    if (is_sum(op)) return kAny;
    if (is_product(op)) return kProduct;
    if (op == Op::kNeg) return kSigned;
    if (op == Op::kPowInt) return kPower;
    return kPrimary;
  }
  /// A square of a constant is written square(c): c^2 of an integer c would be folded.
  bool square_as_call(int s) const { return in(in(s).a).op == Op::kConst; }
  /// 1 / c^n of a constant c and n > 0 (the parser's c^(-n)) is written c^(-n): 1 / c^n of an
  /// integer c would fold c^n into a number.
  bool reciprocal_power(int s) const {
    const Instr& i = in(s);
    return i.op == Op::kDiv && in(i.a).op == Op::kConst && constant(i.a) == 1.0 &&
           in(i.b).op == Op::kPowInt && in(i.b).power > 0 && in(in(i.b).a).op == Op::kConst;
  }
  double constant(int s) const { return t_.constants()[static_cast<std::size_t>(s)]; }
  /// Nesting of slot s written at a position requiring `level` (parentheses included).
  int need(int s, int level) const {
    if (in(s).op == Op::kPow) {
      return std::min(caret_need(s, level), call_inner_[static_cast<std::size_t>(s)]);
    }
    return inner_[static_cast<std::size_t>(s)] + (written_level(s, level) < level ? 1 : 0);
  }

 private:
  int caret_need(int s, int level) const {
    return inner_[static_cast<std::size_t>(s)] + (kPower < level ? 1 : 0);
  }
  /// Nesting inside the call parentheses of a min/max chain ending at s, in orientation `flip`.
  int chain_flat(int s, bool flip, bool* chain) const {
    const int f = flip ? in(s).b : in(s).a, g = flip ? in(s).a : in(s).b;
    *chain = in(f).op == in(s).op;
    // A chained first argument adds its arguments, not a call: its own flat nesting.
    const int first_cost = *chain ? inner_[static_cast<std::size_t>(f)] - 1 : need(f, kAny);
    return std::max(first_cost, need(g, kAny));
  }
  void measure(int s) {
    const Instr& i = in(s);
    const auto u = static_cast<std::size_t>(s);
    if (info(i.op).arity == 0) return;  // a name or a number: no nesting
    switch (i.op) {
      case Op::kMin:
      case Op::kMax: {
        bool chain_a, chain_b;
        const int keep = chain_flat(s, false, &chain_a), swap = chain_flat(s, true, &chain_b);
        // Of two layouts that nest alike, the one that writes a chain flat is shorter.
        flip_[u] = swap < keep || (swap == keep && chain_b && !chain_a);
        chain_[u] = flip_[u] ? chain_b : chain_a;
        inner_[u] = 1 + std::min(keep, swap);
        return;
      }
      case Op::kNeg:
        inner_[u] = 1 + need(i.a, kSigned);
        return;
      case Op::kPowInt:
        inner_[u] = std::max(need(i.a, kPrimary), 1);
        return;
      case Op::kSquare:
        inner_[u] = square_as_call(s) ? 1 : std::max(need(i.a, kPrimary), 1);
        return;
      case Op::kPow:
        inner_[u] = std::max(need(i.a, kPrimary), 1 + need(i.b, kPower));
        call_inner_[u] = 1 + std::max(need(i.a, kAny), need(i.b, kAny));
        return;
      default:
        break;
    }
    if (reciprocal_power(s)) {
      inner_[u] = 1;  // c^(-n): the exponent's level; c and (-n) are leaves
      return;
    }
    if (is_sum(i.op) || is_product(i.op)) {
      // The left operand may be of the same level (chains read from the left), the right not.
      const int left = is_sum(i.op) ? kAny : kProduct, right = left + 1;
      const int keep = std::max(need(i.a, left), need(i.b, right));
      const int swap =
          is_commutative_infix(i.op) ? std::max(need(i.b, left), need(i.a, right)) : keep;
      // `scale` keeps its constant first, as it is usually written, unless that nests deeper.
      flip_[u] = i.op == Op::kScale ? swap <= keep : swap < keep;
      inner_[u] = std::min(keep, swap);
      return;
    }
    inner_[u] = 1 + need(i.a, kAny);  // a function of one argument
  }

  const Tape& t_;
  std::vector<int> inner_;       // nesting of the slot's own text in its form (kPow: as a^b)
  std::vector<int> call_inner_;  // kPow: nesting as pow(a, b)
  std::vector<std::uint8_t> flip_, chain_;
};

/// The second pass: writes the text from a stack of pieces still to write.
class Writer {
 public:
  Writer(const Tape& t, const Layout& l) : t_(t), l_(l) {}

  std::string run(std::size_t max_chars) {
    todo_.push_back({kSlot, t_.root(), kAny, nullptr});
    while (!todo_.empty() && out_.size() <= max_chars) {
      const Piece p = todo_.back();
      todo_.pop_back();
      if (p.kind == kText) {
        out_ += p.text;
      } else if (p.kind == kPowerOf) {
        out_ += std::to_string(l_.in(p.slot).power);
      } else {
        slot(p.slot, p.level);
      }
    }
    if (out_.size() > max_chars || !todo_.empty()) {
      out_.resize(std::min(out_.size(), max_chars));
      out_ += "...";
    }
    return out_;
  }

 private:
  enum Kind : std::uint8_t { kSlot, kText, kPowerOf };
  struct Piece {
    Kind kind;
    std::int32_t slot;  // kSlot: the slot to write; kPowerOf: the powi instruction
    int level;          // kSlot: the level its position requires
    const char* text;   // kText
  };
  void text(const char* s) { todo_.push_back({kText, 0, 0, s}); }
  void at(int s, int level) { todo_.push_back({kSlot, s, level, nullptr}); }

  // Pieces are pushed in the reverse order of writing.
  void slot(int s, int level) {
    const Instr& in = l_.in(s);
    const bool paren = l_.written_level(s, level) < level;
    if (paren) {
      text(")");
      out_ += '(';
    }
    switch (in.op) {
      case Op::kVarX:
      case Op::kVarY:
      case Op::kVarZ:
        out_ += info(in.op).text;
        return;
      case Op::kConst:
        out_ += format_number(l_.constant(s));
        return;
      case Op::kNeg:
        at(in.a, kSigned);
        out_ += '-';
        return;
      case Op::kPowInt:
        todo_.push_back({kPowerOf, s, 0, nullptr});
        text("^");
        at(in.a, kPrimary);
        return;
      case Op::kMin:
      case Op::kMax:
        min_max(s);
        return;
      default:
        break;
    }
    if (l_.reciprocal_power(s)) {
      const Instr& power = l_.in(in.b);
      out_ += format_number(l_.constant(power.a)) + "^(-" + std::to_string(power.power) + ")";
    } else if (is_sum(in.op) || is_product(in.op)) {
      const int left = is_sum(in.op) ? kAny : kProduct;
      at(l_.second(s), left + 1);
      text(infix(in.op));
      at(l_.first(s), left);
    } else if (in.op == Op::kPow && !l_.pow_as_call(s, level)) {
      at(in.b, kPower);
      text("^");
      at(in.a, kPrimary);
    } else if (in.op == Op::kSquare && !l_.square_as_call(s)) {
      text("^2");
      at(in.a, kPrimary);
    } else {
      call(in);
    }
  }
  static const char* infix(Op op) {
    switch (op) {
      case Op::kAdd:
        return " + ";
      case Op::kSub:
        return " - ";
      case Op::kDiv:
      case Op::kDivConst:
        return " / ";
      default:
        return " * ";
    }
  }
  /// name(a) or name(a, b), with sincos and its paired cos written as sin and cos.
  void call(const Instr& in) {
    text(")");
    if (info(in.op).arity == 2) {
      at(in.b, kAny);
      text(", ");
    }
    at(in.a, kAny);
    out_ += in.op == Op::kSinCos ? std::string_view("sin") : info(in.op).text;
    out_ += '(';
  }
  /// min(a1, a2, ...): the chain of the same operation through the first arguments, flat.
  void min_max(int s) {
    const std::string_view name = info(l_.in(s).op).text;
    text(")");
    for (int m = s;; m = l_.first(m)) {
      at(l_.second(m), kAny);
      text(", ");
      if (!l_.chained(m)) {
        at(l_.first(m), kAny);
        break;
      }
    }
    out_ += name;
    out_ += '(';
  }

  const Tape& t_;
  const Layout& l_;
  std::vector<Piece> todo_;
  std::string out_;
};

}  // namespace

std::string Tape::to_text(std::size_t max_chars) const {
  const Layout layout(*this);
  return Writer(*this, layout).run(max_chars);
}

}  // namespace iaa
