#include "expr/parser.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

#include "core/error.h"

namespace iaa {

namespace {

enum class Tok {
  kNumber,
  kName,
  kPlus,
  kMinus,
  kStar,
  kSlash,
  kCaret,
  kLParen,
  kRParen,
  kComma,
  kEnd
};

struct Token {
  Tok kind;
  std::string_view text;
  int line, column;
  double number = 0.0;
};

std::string describe(const Token& t) {
  switch (t.kind) {
    case Tok::kEnd:
      return "end of input";
    case Tok::kNumber:
      return "number '" + std::string(t.text) + "'";
    case Tok::kName:
      return "name '" + std::string(t.text) + "'";
    default:
      return "'" + std::string(t.text) + "'";
  }
}

// Splits the text into tokens, tracking 1-based lines and columns.
class Lexer {
 public:
  explicit Lexer(std::string_view s) : s_(s) {}

  Token next() {
    skip_space();
    Token t{Tok::kEnd, {}, line_, col_};
    if (pos_ >= s_.size()) return t;
    const char c = s_[pos_];
    const std::size_t start = pos_;
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      lex_number(&t);
      return t;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      while (pos_ < s_.size() &&
             (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) {
        advance();
      }
      t.kind = Tok::kName;
      t.text = s_.substr(start, pos_ - start);
      return t;
    }
    static constexpr struct {
      char c;
      Tok kind;
    } kPunct[] = {{'+', Tok::kPlus},  {'-', Tok::kMinus},  {'*', Tok::kStar},   {'/', Tok::kSlash},
                  {'^', Tok::kCaret}, {'(', Tok::kLParen}, {')', Tok::kRParen}, {',', Tok::kComma}};
    for (const auto& p : kPunct) {
      if (c == p.c) {
        advance();
        t.kind = p.kind;
        t.text = s_.substr(start, 1);
        return t;
      }
    }
    std::string shown = std::isprint(static_cast<unsigned char>(c))
                            ? std::string("'") + c + "'"
                            : "byte " + std::to_string(static_cast<unsigned char>(c));
    throw ParseError("unexpected character " + shown +
                         "; expected a number, a name, an operator or a parenthesis",
                     t.line, t.column);
  }

 private:
  void advance() {
    if (s_[pos_] == '\n') {
      ++line_;
      col_ = 1;
    } else {
      ++col_;
    }
    ++pos_;
  }
  void skip_space() {
    while (pos_ < s_.size()) {
      const char c = s_[pos_];
      if (c == '#') {
        while (pos_ < s_.size() && s_[pos_] != '\n') advance();
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        advance();
      } else {
        break;
      }
    }
  }
  void lex_number(Token* t) {
    const std::size_t start = pos_;
    auto digits = [&] {
      int n = 0;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
        advance();
        ++n;
      }
      return n;
    };
    int n = digits();
    if (pos_ < s_.size() && s_[pos_] == '.') {
      advance();
      n += digits();
    }
    if (n == 0) throw ParseError("expected digits in a number", t->line, t->column);
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      // An exponent only if digits follow (so `2e` is an error, not 2 times e).
      std::size_t look = pos_ + 1;
      if (look < s_.size() && (s_[look] == '+' || s_[look] == '-')) ++look;
      if (look < s_.size() && std::isdigit(static_cast<unsigned char>(s_[look]))) {
        while (pos_ < look) advance();
        digits();
      } else {
        throw ParseError("expected digits after the exponent mark in a number", line_,
                         col_ + static_cast<int>(look - pos_));
      }
    }
    t->kind = Tok::kNumber;
    t->text = s_.substr(start, pos_ - start);
    const std::string copy(t->text);
    errno = 0;
    t->number = std::strtod(copy.c_str(), nullptr);
    if (!std::isfinite(t->number)) {
      throw ParseError("number " + copy + " is too large for a double (limit about 1.8e308)",
                       t->line, t->column);
    }
  }

  std::string_view s_;
  std::size_t pos_ = 0;
  int line_ = 1, col_ = 1;
};

constexpr double kTwo53 = 9007199254740992.0;

bool is_exact_int(double v) {
  return std::floor(v) == v && std::fabs(v) <= kTwo53;
}

std::optional<Op> function_op(std::string_view name) {
  for (int i = 0; i < kOpCount; ++i) {
    if (kOpInfo[i].callable && kOpInfo[i].text == name) return static_cast<Op>(i);
  }
  return std::nullopt;
}

class Parser {
 public:
  Parser(std::string_view text, const Params& params) : lex_(text), params_(params) {
    tok_ = lex_.next();
  }

  Dag run() {
    if (tok_.kind == Tok::kEnd) throw error("expected an expression, found end of input");
    dag_.root = expr();
    if (tok_.kind != Tok::kEnd) {
      throw error("expected an operator or end of input, found " + describe(tok_));
    }
    return std::move(dag_);
  }

 private:
  ParseError error(const std::string& msg) const { return ParseError(msg, tok_.line, tok_.column); }
  ParseError error_at(const Token& t, const std::string& msg) const {
    return ParseError(msg, t.line, t.column);
  }
  void eat() { tok_ = lex_.next(); }
  void expect(Tok kind, const char* what) {
    if (tok_.kind != kind)
      throw error(std::string("expected ") + what + ", found " + describe(tok_));
    eat();
  }

  // Counts nesting so that deep inputs fail cleanly instead of overflowing the stack.
  struct Nest {
    explicit Nest(Parser* p) : p_(p) {
      if (++p_->depth_ > kMaxNesting) {
        throw p_->error("expression is nested too deeply (at most " + std::to_string(kMaxNesting) +
                        " levels of parentheses, calls and signs)");
      }
    }
    ~Nest() { --p_->depth_; }
    Parser* p_;
  };

  // Folds + - * of integer constants when the result is exact; everything else becomes a node.
  NodeId arith(Op op, NodeId a, NodeId b) {
    double va, vb;
    if (dag_.is_constant(a, &va) && dag_.is_constant(b, &vb) && is_exact_int(va) &&
        is_exact_int(vb)) {
      const double r = op == Op::kAdd   ? va + vb
                       : op == Op::kSub ? va - vb
                       : op == Op::kMul ? va * vb
                                        : NAN;
      if (op != Op::kDiv && is_exact_int(r)) return dag_.constant(r);
    }
    return dag_.binary(op, a, b);
  }

  NodeId expr() {
    NodeId lhs = term();
    while (tok_.kind == Tok::kPlus || tok_.kind == Tok::kMinus) {
      const Op op = tok_.kind == Tok::kPlus ? Op::kAdd : Op::kSub;
      eat();
      lhs = arith(op, lhs, term());
    }
    return lhs;
  }

  NodeId term() {
    NodeId lhs = unary();
    while (tok_.kind == Tok::kStar || tok_.kind == Tok::kSlash) {
      const Op op = tok_.kind == Tok::kStar ? Op::kMul : Op::kDiv;
      eat();
      lhs = arith(op, lhs, unary());
    }
    return lhs;
  }

  NodeId unary() {
    if (tok_.kind == Tok::kMinus || tok_.kind == Tok::kPlus) {
      const bool neg = tok_.kind == Tok::kMinus;
      Nest nest(this);
      eat();
      const NodeId a = unary();
      return neg ? dag_.unary(Op::kNeg, a) : a;
    }
    return power();
  }

  NodeId power() {
    const NodeId base = primary();
    if (tok_.kind != Tok::kCaret) return base;
    Nest nest(this);
    eat();
    if (tok_.kind == Tok::kMinus || tok_.kind == Tok::kPlus) {
      throw error(
          "a sign cannot follow '^' directly; put a negative exponent in parentheses, "
          "as in x^(-3)");
    }
    const Token at = tok_;
    const NodeId e = power();  // right-associative
    return make_power(base, e, at);
  }

  NodeId make_power(NodeId base, NodeId e, const Token& at) {
    double ve;
    if (!dag_.is_constant(e, &ve) || std::floor(ve) != ve) return dag_.binary(Op::kPow, base, e);
    if (std::fabs(ve) > kMaxIntPower) {
      char shown[32];
      std::snprintf(shown, sizeof shown, "%.17g", ve);
      throw error_at(at, std::string("integer exponent ") + shown + " is too large (at most " +
                             std::to_string(kMaxIntPower) + " in absolute value)");
    }
    const int n = static_cast<int>(std::fabs(ve));
    double vb;
    if (dag_.is_constant(base, &vb) && is_exact_int(vb) && ve >= 0) {
      // Exact integer power of an integer constant (2^10): fold while it stays exact.
      double r = 1.0;
      bool exact = true;
      for (int i = 0; i < n && exact; ++i) {
        r *= vb;
        exact = is_exact_int(r);
      }
      if (exact) return dag_.constant(r);
    }
    NodeId p = n == 1 ? base : (n == 2 ? dag_.unary(Op::kSquare, base) : dag_.pow_int(base, n));
    if (ve < 0) p = dag_.binary(Op::kDiv, dag_.constant(1.0), p);
    return p;
  }

  NodeId primary() {
    const Token t = tok_;
    switch (t.kind) {
      case Tok::kNumber:
        eat();
        return dag_.constant(t.number);
      case Tok::kLParen: {
        if (const std::optional<double> v = signed_literal()) return dag_.constant(*v);
        Nest nest(this);
        eat();
        const NodeId e = expr();
        expect(Tok::kRParen, "')' to close the parenthesis");
        return e;
      }
      case Tok::kName:
        eat();
        return name(t);
      default:
        throw error("expected a number, a name or '(', found " + describe(t));
    }
  }

  /// At '(': a signed number in parentheses, "(-2.5)", read whole. It is a leaf, the way the
  /// tape's text writes a negative constant, so it takes no level of nesting (the text of any
  /// parsed tape then nests no deeper than the text it came from, tape.h).
  std::optional<double> signed_literal() {
    Lexer look = lex_;
    Token sign{}, number{};
    try {  // a bad token is reported where the ordinary path meets it
      sign = look.next();
      if (sign.kind != Tok::kMinus && sign.kind != Tok::kPlus) return std::nullopt;
      number = look.next();
      if (number.kind != Tok::kNumber || look.next().kind != Tok::kRParen) return std::nullopt;
    } catch (const ParseError&) {
      return std::nullopt;
    }
    lex_ = look;
    eat();
    return sign.kind == Tok::kMinus ? -number.number : number.number;
  }

  NodeId name(const Token& t) {
    const std::string_view n = t.text;
    const bool call = tok_.kind == Tok::kLParen;
    if (auto op = function_op(n)) {
      if (!call)
        throw error_at(t, std::string(n) + " is a function: write " + std::string(n) + "(...)");
      return call_function(t, *op);
    }
    if (call) throw error_at(t, "'" + std::string(n) + "' is not a function");
    if (n == "x") return dag_.var(0);
    if (n == "y") return dag_.var(1);
    if (n == "z") return dag_.var(2);
    if (n == "pi") return dag_.constant(3.141592653589793);
    if (n == "e") return dag_.constant(2.718281828459045);
    if (auto it = params_.find(n); it != params_.end()) return dag_.constant(it->second);
    std::string known;
    for (const auto& [k, v] : params_) known += (known.empty() ? "" : ", ") + k;
    throw error_at(t, "unknown name '" + std::string(n) +
                          "'; expected x, y, z, pi, e, a function call" +
                          (known.empty() ? std::string() : " or a parameter (" + known + ")"));
  }

  NodeId call_function(const Token& t, Op op) {
    Nest nest(this);
    eat();  // '('
    std::vector<NodeId> args;
    if (tok_.kind == Tok::kRParen) {
      throw error(std::string(t.text) + " needs an argument, found ')'");
    }
    args.push_back(expr());
    while (tok_.kind == Tok::kComma) {
      eat();
      args.push_back(expr());
    }
    expect(Tok::kRParen, "',' or ')' in the argument list");
    const std::string fname(t.text);
    const int n = static_cast<int>(args.size());
    if (op == Op::kMin || op == Op::kMax) {
      if (n < 2) {
        throw error_at(t, fname + " needs at least 2 arguments, got " + std::to_string(n));
      }
      NodeId acc = args[0];
      for (int i = 1; i < n; ++i) acc = dag_.binary(op, acc, args[static_cast<std::size_t>(i)]);
      return acc;
    }
    const int want = info(op).arity;
    if (n != want) {
      throw error_at(t, fname + " takes " + std::to_string(want) + " argument" +
                            (want == 1 ? "" : "s") + ", got " + std::to_string(n));
    }
    if (op == Op::kPow) return make_power(args[0], args[1], t);
    return want == 1 ? dag_.unary(op, args[0]) : dag_.binary(op, args[0], args[1]);
  }

  Lexer lex_;
  const Params& params_;
  Token tok_;
  Dag dag_;
  int depth_ = 0;
};

}  // namespace

bool is_reserved_name(std::string_view name) {
  return name == "x" || name == "y" || name == "z" || name == "pi" || name == "e" ||
         function_op(name).has_value();
}

Dag parse_expression(std::string_view text, const Params& params) {
  for (const auto& [k, v] : params) {
    if (is_reserved_name(k)) throw Error("parameter '" + k + "' has a reserved name");
    if (!std::isfinite(v)) throw Error("parameter '" + k + "' is not a finite number");
  }
  return Parser(text, params).run();
}

}  // namespace iaa
