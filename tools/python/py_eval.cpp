// iaa.eval: an expression's value and gradient at a point, and its interval value and interval
// gradient over a box, as `iaa eval --at/--box` computes them (app/evaluation.h).
#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include "app/evaluation.h"
#include "core/error.h"
#include "expr/tape.h"
#include "py_common.h"

namespace iaa::py {
namespace {

/// What iaa.eval returns; a part that was not asked for is None.
struct EvalResult {
  std::string expression;  ///< as the tape reads it
  int slots = 0, operations = 0;
  pb::object value = pb::none(), gradient = pb::none();
  pb::object interval = pb::none(), interval_gradient = pb::none();
  pb::object partial_domain = pb::none(), certified_empty = pb::none();
};

/// A box as ((x0, x1), (y0, y1), (z0, z1)) or (x0, x1, y0, y1, z0, z1) (a row of enclose()'s
/// boxes); ValueError unless every range is finite with lo <= hi.
Box3 box_from(const pb::object& o) {
  std::vector<double> v;
  for (const pb::handle& e : pb::iter(o)) {
    if (pb::isinstance<pb::sequence>(e)) {
      for (const pb::handle& x : pb::iter(e)) v.push_back(x.cast<double>());
    } else {
      v.push_back(e.cast<double>());
    }
  }
  if (v.size() != 6) throw Error("box: expected ((x0, x1), (y0, y1), (z0, z1))");
  Box3 b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = v[2 * i];
    b.hi[i] = v[2 * i + 1];
  }
  if (!b.valid()) throw Error("box: every range must be finite numbers with lo <= hi");
  return b;
}

pb::object interval_or_none(const Interval& i) {
  if (i.is_empty()) return pb::none();
  return pb::make_tuple(i.lo(), i.hi());
}

/// f and its gradient at p; None for both where f is undefined (not finite).
void eval_at(const Tape& tape, const std::array<double, 3>& p, EvalResult& r) {
  for (double c : p) {
    if (!std::isfinite(c)) throw Error("point: coordinates must be finite numbers");
  }
  const app::PointValue v = app::evaluate_at(tape, {p[0], p[1], p[2]});
  if (!std::isfinite(v.f)) return;
  r.value = pb::float_(v.f);
  r.gradient = pb::make_tuple(v.grad.x, v.grad.y, v.grad.z);
}

/// F and its interval gradient over the box.
void eval_over(const Tape& tape, const Box3& box, EvalResult& r) {
  const app::BoxValue v = app::evaluate_over(tape, IBox(box));
  r.interval = interval_or_none(v.f);
  r.interval_gradient = pb::make_tuple(interval_or_none(v.grad.g[0]), interval_or_none(v.grad.g[1]),
                                       interval_or_none(v.grad.g[2]));
  r.partial_domain = pb::bool_(v.partial);
  r.certified_empty = pb::bool_(v.f.is_empty() || !v.f.contains_zero());
}

EvalResult eval(const std::string& expr, const std::optional<std::array<double, 3>>& point,
                const pb::object& box, const Params& params) {
  const Tape tape = Tape::parse(expr, params);
  EvalResult r;
  r.expression = tape.to_text();
  r.slots = tape.size();
  r.operations = tape.op_count();
  if (point) eval_at(tape, *point, r);
  if (!box.is_none()) eval_over(tape, box_from(box), r);
  return r;
}

}  // namespace

void bind_eval(pb::module_& m) {
  pb::class_<EvalResult>(m, "EvalResult", "What iaa.eval found; parts not asked for are None.")
      .def_readonly("expression", &EvalResult::expression, "the expression as the tape reads it")
      .def_readonly("slots", &EvalResult::slots, "slots of the compiled tape")
      .def_readonly("operations", &EvalResult::operations, "operations of the compiled tape")
      .def_readonly("value", &EvalResult::value, "f at the point (None where f is undefined)")
      .def_readonly("gradient", &EvalResult::gradient, "(df/dx, df/dy, df/dz) at the point")
      .def_readonly("interval", &EvalResult::interval,
                    "(lo, hi) enclosing f over the box, outward rounded (None: f is undefined "
                    "everywhere in it)")
      .def_readonly("interval_gradient", &EvalResult::interval_gradient,
                    "three (lo, hi) enclosing the partial derivatives over the box")
      .def_readonly("partial_domain", &EvalResult::partial_domain,
                    "True when f is undefined or has a pole somewhere in the box")
      .def_readonly("certified_empty", &EvalResult::certified_empty,
                    "True when 0 is not in the interval: the box holds no point of the surface")
      .def("__repr__", [](const EvalResult& r) {
        return "<iaa.EvalResult value=" + std::string(pb::repr(r.value)) +
               " interval=" + std::string(pb::repr(r.interval)) + ">";
      });
  m.def("eval", &eval, pb::arg("expr"), pb::arg("point") = pb::none(), pb::arg("box") = pb::none(),
        pb::arg("params") = Params{}, R"doc(
Evaluates an expression as `iaa eval` does: at a point, f and its gradient; over a box, the
outward-rounded interval of f and of its gradient, and whether the box is certified empty.

point: (x, y, z); box: ((x0, x1), (y0, y1), (z0, z1)) or (x0, x1, y0, y1, z0, z1);
params: {"r": 0.5} for the expression's named parameters. Raises ValueError with the parser's
message (line and column) for a bad expression.)doc");
}

}  // namespace iaa::py
