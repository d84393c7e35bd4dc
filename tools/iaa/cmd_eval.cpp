// `iaa eval`: evaluates an expression at a point or over a box, with its gradient, and prints the
// compiled tape. This is how a user checks a formula before rendering it.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/evaluation.h"
#include "app/files.h"
#include "core/error.h"
#include "expr/tape.h"
#include "iaa/command.h"

namespace iaa::cli {
namespace {

struct EvalOptions {
  std::string expr;
  bool has_expr = false;
  std::string file;
  std::string at;
  std::string box;
  std::vector<std::string> params;
  bool tape = false;
};

std::string fmt(double v) {
  if (v == 0.0) v = 0.0;  // print -0 as 0
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string fmt(const Interval& i) {
  if (i.is_empty()) return "empty";
  return "[" + fmt(i.lo()) + ", " + fmt(i.hi()) + "]";
}

void run(const EvalOptions& o) {
  if (o.has_expr == !o.file.empty()) {
    throw Error("give the expression either as an argument or with --file (exactly one)");
  }
  const std::string text = o.file.empty() ? o.expr : app::read_file(o.file);
  const Tape tape = Tape::parse(text, parse_params(o.params));
  // The expression as the tape reads it, cut for long input (a sum of 10^5 terms): --tape lists
  // every operation.
  constexpr std::size_t kShownChars = 2000;
  const std::string shown = tape.to_text(kShownChars);
  std::printf("expression  %s\n", shown.c_str());
  if (shown.size() > kShownChars) {
    std::printf("            (the first %zu characters; --tape lists every operation)\n",
                kShownChars);
  }
  std::printf("tape        %d slots, %d operations\n", tape.size(), tape.op_count());
  if (o.tape) std::printf("\n%s", tape.listing().c_str());
  if (!o.at.empty()) {
    const auto p = parse_triple(o.at, "--at");
    const app::PointValue v = app::evaluate_at(tape, {p[0], p[1], p[2]});
    std::printf("\nat (%s, %s, %s)\n", fmt(p[0]).c_str(), fmt(p[1]).c_str(), fmt(p[2]).c_str());
    if (std::isfinite(v.f)) {
      std::printf("  f       = %s\n", fmt(v.f).c_str());
      std::printf("  grad f  = (%s, %s, %s)\n", fmt(v.grad.x).c_str(), fmt(v.grad.y).c_str(),
                  fmt(v.grad.z).c_str());
    } else {
      std::printf("  f       = undefined here (%s)\n", fmt(v.f).c_str());
    }
  }
  if (!o.box.empty()) {
    const IBox box(parse_box(o.box, "--box"));
    // Evaluated inside a rounding scope, printed outside it (evaluation.h).
    const app::BoxValue bv = app::evaluate_over(tape, box);
    const Interval& v = bv.f;
    const IGrad& g = bv.grad;
    const bool partial = bv.partial;
    std::printf("\nover %s x %s x %s\n", fmt(box.x).c_str(), fmt(box.y).c_str(),
                fmt(box.z).c_str());
    std::printf(
        "  F       = %s%s\n", fmt(v).c_str(),
        partial ? "  (partial domain: f is undefined or has a pole somewhere in the box)" : "");
    std::printf("  grad F  = (%s, %s, %s)\n", fmt(g.g[0]).c_str(), fmt(g.g[1]).c_str(),
                fmt(g.g[2]).c_str());
    if (v.is_empty()) {
      std::printf("  verdict   certified empty: f is undefined everywhere in the box\n");
    } else if (!v.contains_zero()) {
      std::printf(
          "  verdict   certified empty: 0 is not in F, the box holds no point of the surface\n");
    } else {
      std::printf("  verdict   possible: 0 is in F, the box may hold part of the surface\n");
    }
  }
}

void setup(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  CLI::Option* expr =
      app.add_option("expr", opts->expr, "the expression f(x,y,z), e.g. 'x^2 + y^2 + z^2 - 1'");
  app.add_option("-f,--file", opts->file, "read the expression from this file instead");
  app.add_option("--at", opts->at, "evaluate f and its gradient at the point X,Y,Z");
  app.add_option("--box", opts->box, "evaluate F and its interval gradient over X0:X1,Y0:Y1,Z0:Z1");
  app.add_option("-p,--param", opts->params, "a named parameter NAME=VALUE (repeatable)");
  app.add_flag("--tape", opts->tape, "print the compiled tape");
  app.footer(
      "Examples:\n"
      "  iaa eval 'x^2 + y^2 + z^2 - r^2' --param r=0.5 --at 0.5,0,0\n"
      "  iaa eval '0.5*x^5 + 0.5*x^4 - y^2 - z^2' --box -0.1:0.1,-0.01:0.01,-0.01:0.01\n"
      "  iaa eval 'min(x, y) + sqrt(z)' --tape\n"
      "  iaa eval --file surface.txt --at 0,0,0");
  app.callback([opts, expr] {
    opts->has_expr = expr->count() > 0;
    run(*opts);
  });
}

CommandRegistrar reg{
    {"eval", "evaluate an expression at a point or over a box, print its tape", 10, setup}};

}  // namespace
}  // namespace iaa::cli
