// Batched point evaluation: one pass over the tape for up to K points at once.
//
// The point tape loop (eval_point.h) spends most of its time on the dispatch of each operation,
// as the interval loop does (docs/eval.md). Here each slot holds K values, each operation is
// dispatched once for all K points, and the arithmetic (add, sub, mul, scale, divc, div, neg,
// square, abs, integer powers, min, max) and sin and cos (elementary.h's kernels, on vectors)
// run over the lanes in SIMD vectors (SSE2, or the AVX2 copy of the loop chosen at run time;
// never FMA); every other operation (sqrt, exp, log, tan, atan, the real power, and sin and cos
// of an argument beyond the kernels' range) runs PointRules lane by lane.
//
// Same results: every lane's value is the double PointEval gives at that point (the same IEEE
// operations in the same order, in the caller's rounding mode), NaN where it gives NaN.
// tests/expr/eval_batch_test.cpp checks bit equality on random expressions and points.
#pragma once

#include <vector>

#include "core/vec.h"
#include "expr/eval_batch.h"
#include "expr/tape.h"

namespace iaa {

/// Evaluates one tape at up to K points per call. One per thread; no allocation per call. Unlike
/// the interval evaluators it keeps the caller's rounding mode, as PointEval does.
template <int K>
class BatchPointEvalK : public detail::BatchIsa {
 public:
  static_assert(K == 4 || K == 8 || K == 16, "lane counts that are instantiated");
  /// The most points one call evaluates.
  static constexpr int kLanes = K;

  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit BatchPointEvalK(const Tape& tape);
  explicit BatchPointEvalK(Tape&&) = delete;

  /// out[j] = f(points[j]) for j < n, 1 <= n <= K: the values PointEval gives.
  void eval(const Vec3* points, int n, double* out);
  const Tape& tape() const { return *tape_; }

 private:
  struct alignas(64) Slot {
    double v[K];
  };

  friend struct detail::batch::Runner;
  template <int W>
  void run_impl(int n);
  /// PointRules' rule of instruction i for lane j.
  void scalar_op(int i, int j);
  /// Copies lane 0 of slot i to the lanes n..K-1 (they then compute what lane 0 does).
  void fill_unused(int i, int n);

  const Tape* tape_;
  std::vector<Slot> slots_;
};

/// The share of the tape's operations (a sincos's paired cos not counted) that BatchPointEvalK
/// runs lane by lane: sqrt, exp, log, tan, atan, the real power.
double point_lane_by_lane_share(const Tape& tape);

extern template class BatchPointEvalK<4>;
extern template class BatchPointEvalK<8>;
extern template class BatchPointEvalK<16>;

}  // namespace iaa
