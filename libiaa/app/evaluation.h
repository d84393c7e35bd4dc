// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// What `iaa eval` computes, for the command and the Python module's eval(): an expression's value
// and gradient at a point, and its interval value and interval gradient over a box.
#pragma once

#include "core/interval.h"
#include "core/vec.h"
#include "expr/eval_interval_grad.h"
#include "expr/tape.h"

namespace iaa::app {

/// f and its gradient at a point; f is not finite where f is undefined.
struct PointValue {
  double f = 0;
  Vec3 grad;
};
PointValue evaluate_at(const Tape& tape, const Vec3& p);

/// Outward-rounded enclosures of f and of its gradient over a box, and whether f is undefined or
/// has a pole somewhere in it. Evaluated inside a rounding scope of its own: the caller prints
/// (or converts) the bounds outside it, where printf rounds to nearest and a lower bound printed
/// upward would no longer be one.
struct BoxValue {
  Interval f;
  IGrad grad;
  bool partial = false;
};
BoxValue evaluate_over(const Tape& tape, const IBox& box);

}  // namespace iaa::app
