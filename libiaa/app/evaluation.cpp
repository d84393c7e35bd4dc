// What `iaa eval` computes (evaluation.h).
#include "app/evaluation.h"

#include "expr/eval_interval.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"

namespace iaa::app {

PointValue evaluate_at(const Tape& tape, const Vec3& p) {
  PointEval pe(tape);
  PointGradEval pg(tape);
  return {pe.eval(p), pg.eval(p).g};
}

BoxValue evaluate_over(const Tape& tape, const IBox& box) {
  RoundingScope scope;
  IntervalEval ie(tape);
  IntervalGradEval ig(tape);
  BoxValue r;
  r.f = ie.eval(box);
  r.partial = ie.partial_domain();
  r.grad = ig.eval(box);
  return r;
}

}  // namespace iaa::app
