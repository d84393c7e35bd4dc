// Per-task state of a render: the scene's derived data shared by every part of the renderer and
// one set of evaluators (they own scratch space, so one per task/thread, never shared).
#pragma once

#include <cstdint>
#include <optional>

#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_batch_point.h"
#include "expr/ray_poly.h"
#include "expr/specialize.h"
#include "render/mean_value_budget.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace iaa {

/// Read-only facts of one render, computed once.
struct RenderSetup {
  const Scene* scene;
  RenderSettings settings;
  CameraFrame frame;
  Interval depth;     ///< depth range of the bounds in front of the eye (may be empty)
  bool may_partial;   ///< the tape has operations that can be undefined or discontinuous
  double diag;        ///< diagonal of the bounds
  double ray_tol;     ///< depth tolerance of point rays (absolute)
  double shadow_eps;  ///< offset of shadow-ray origins along the normal

  RenderSetup(const Scene& scene, const RenderSettings& settings);
};

/// Evaluators and counters of one task.
struct RenderContext {
  const RenderSetup& setup;
  SpecializingEval se;      ///< every evaluation of f, with min/max branches pruned by regions
  std::uint64_t evals = 0;  ///< interval evaluations so far (both interval modes)
  MeanValueBudget mv;       ///< of the current screen block or pixel
  /// Whether the batched interval evaluators serve this tape (eval_batch, eval_grad_batch): four
  /// boxes per pass (the depth pieces of sibling beams searched side by side, beam.h; the
  /// estimator's pieces; the pieces of a shadow ray), where at most a quarter of the tape's
  /// operations run lane by lane (the gyroid's sin and cos, 0.375 of its operations, were 1.17x
  /// the CPU time batched before they ran in vectors).
  bool batched = false;
  /// Sixteen points per pass (the coverage rays of a Partial part marched side by side, a few
  /// steps of each), where at most a quarter of the tape's operations run lane by lane there
  /// (sin and cos do not: the gyroid has it): the whole tape's values, which are `se`'s but
  /// where a branch that `se` dropped overflows at the point (specialize.h; they shade, they
  /// certify nothing).
  std::optional<BatchPointEvalK<16>> batch_point;
  /// Four points per pass (the steps of a Full part's shading march, kernel_iaa.cpp), on the
  /// same tapes as batch_point.
  std::optional<BatchPointEvalK<4>> batch_point4;
  /// Where f is a polynomial (of degree at most RayPolynomial::kMaxDegree): its restriction to a
  /// ray, for the searches of shading rays (search_shading_ray).
  std::optional<RayPolynomial> ray_poly;

  explicit RenderContext(const RenderSetup& s) : setup(s), se(*s.scene->tape) {
    const Tape& tape = *s.scene->tape;
    batched = lane_by_lane_share(tape) <= 0.25;
    if (point_lane_by_lane_share(tape) <= 0.25) {
      batch_point.emplace(tape);
      batch_point4.emplace(tape);
    }
    ray_poly.emplace(tape);
    if (!ray_poly->usable()) ray_poly.reset();
  }

  /// F over a box, counted. `partial` receives partial_domain().
  Interval eval(const IBox& b, bool* partial = nullptr) {
    ++evals;
    const Interval f = se.eval(b);
    if (partial) *partial = se.partial_domain();
    return f;
  }
  /// F and its gradient over a box, counted.
  IGrad eval_grad(const IBox& b, bool* partial = nullptr) {
    ++evals;
    const IGrad g = se.eval_grad(b);
    if (partial) *partial = se.partial_domain();
    return g;
  }
  /// F over boxes[0..n), 1 <= n <= 4, each counted, the partial-domain flags into
  /// partial[0..n): in one pass of `se`'s batch for two or more where `batched` (the interval
  /// eval() gives each box; with min or max, the tape of a region that holds them all), else
  /// one at a time, in order.
  void eval_batch(const IBox* boxes, int n, Interval* out, bool* partial) {
    if (n < 2 || !batched) {
      for (int j = 0; j < n; ++j) out[j] = eval(boxes[j], &partial[j]);
      return;
    }
    evals += static_cast<std::uint64_t>(n);
    se.eval_batch(boxes, n, out, partial);
  }
  /// F and its gradient over boxes[0..n) the same way (eval_grad()'s, but for the signs of zero
  /// bounds of partial derivatives on tapes with min or max, which no test of the renderer tells
  /// apart).
  void eval_grad_batch(const IBox* boxes, int n, IGrad* out, bool* partial) {
    if (n < 2 || !batched) {
      for (int j = 0; j < n; ++j) out[j] = eval_grad(boxes[j], &partial[j]);
      return;
    }
    evals += static_cast<std::uint64_t>(n);
    se.eval_grad_batch(boxes, n, out, partial);
  }
  const Box3& bounds() const { return setup.scene->bounds; }
};

}  // namespace iaa
