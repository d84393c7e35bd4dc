// Batched interval evaluation: one pass over the tape for up to K boxes at once.
//
// The scalar tape loop (eval_loop.h) spends most of its time on the dispatch of each operation and
// on the chain of dependent operations, not on arithmetic (docs/eval.md, "How fast the evaluators
// are"). Here each slot holds K lower and K upper bounds (struct of arrays), each operation is
// dispatched once for all K boxes, and its rule runs over the lanes in SIMD vectors (SSE2 on the
// baseline x86-64; an AVX2 copy of the loop is chosen at run time where the processor has it;
// never FMA, which would change bounds).
//
// Same results: every lane's interval is the same double pair as IntervalEval gives for that box,
// the signs of zeros included, and its partial-domain flag is the same. The fast rules (add, sub,
// mul of finite intervals, scale, divc, div by an interval that excludes 0, neg, square, integer
// powers, abs, min, max) compute the bounds with the operations of core/interval.h in the same
// order; a lane the fast rule does not cover (an empty or unbounded argument, a NaN bound, a
// divisor containing 0) is recomputed by the scalar rule, and every other operation (sqrt, the
// transcendentals, the real power) runs the scalar rule lane by lane.
// tests/expr/eval_batch_test.cpp checks bit equality on random expressions and boxes.
#pragma once

#include <cstdint>
#include <vector>

#include "core/interval.h"
#include "core/vec.h"
#include "expr/tape.h"

namespace iaa {

namespace detail {

namespace batch {
struct Runner;
}  // namespace batch

/// One slot of a batched evaluator: K lower bounds, then K upper bounds, on one or two cache
/// lines.
template <int K>
struct alignas(64) BatchSlot {
  double lo[K];
  double hi[K];
};

/// The instruction-set choice of the batched evaluators (this one and eval_batch_grad.h).
class BatchIsa {
 public:
  /// Which code runs the lanes: "avx2" where the processor has AVX2, else "sse2" (the baseline).
  const char* isa() const { return use_avx2_ ? "avx2" : "sse2"; }
  /// With true, runs the baseline (SSE2) code even where AVX2 is there: for tests and benchmarks.
  void use_baseline(bool baseline);

 protected:
  BatchIsa();
  bool use_avx2_ = false;
};

}  // namespace detail

/// Evaluates one tape over up to K boxes per call. One per thread; no allocation per call.
/// Opens a RoundingScope itself when the caller has none.
template <int K>
class BatchIntervalEvalK : public detail::BatchIsa {
 public:
  static_assert(K == 2 || K == 4 || K == 8 || K == 16, "lane counts that are instantiated");
  /// The most boxes one call evaluates.
  static constexpr int kLanes = K;

  /// The evaluator keeps a pointer to its tape, which must outlive it.
  explicit BatchIntervalEvalK(const Tape& tape);
  explicit BatchIntervalEvalK(Tape&&) = delete;

  /// out[j] = F(boxes[j]) for j < n, 1 <= n <= K: the intervals IntervalEval gives.
  void eval(const IBox* boxes, int n, Interval* out);

  /// True when the last evaluation of box `lane` met a partial domain or a pole
  /// (IntervalEval::partial_domain).
  bool partial_domain(int lane) const { return partial_[static_cast<std::size_t>(lane)] != 0; }
  const Tape& tape() const { return *tape_; }

 private:
  using Slot = detail::BatchSlot<K>;

  // The loop, forced inline into the baseline and the AVX2 code (batch_lanes.h, Runner).
  friend struct detail::batch::Runner;
  template <int W>
  void run_impl(int n);
  /// The scalar rule of instruction i for lane j (IntervalRules of eval_interval.h).
  void scalar_op(int i, int j);
  /// Copies lane 0 of slot i to the lanes n..K-1, so that the unused lanes compute what lane 0
  /// does and never leave the fast rules.
  void fill_unused(int i, int n);

  const Tape* tape_;
  std::vector<Slot> slots_;
  std::uint8_t partial_[K] = {};
};

/// The lane count that measured best (docs/eval.md, "The batched interval evaluator").
using BatchIntervalEval = BatchIntervalEvalK<8>;

/// The share of the tape's operations (a sincos's paired cos not counted) that a batched
/// evaluator runs lane by lane with the scalar rule, having no vector rule in it: sqrt, exp, log,
/// the trigonometric functions, the real power (both), division, abs, min and max (the interval +
/// gradient batch, eval_batch_grad.h). Where these are much of a tape, a pass over K boxes costs
/// about K one-box evaluations, and batching gains nothing (the render's gyroid: 1.17x the CPU
/// time with its sibling beams batched, docs/render.md).
double lane_by_lane_share(const Tape& tape);

extern template class BatchIntervalEvalK<2>;
extern template class BatchIntervalEvalK<4>;
extern template class BatchIntervalEvalK<8>;
extern template class BatchIntervalEvalK<16>;

}  // namespace iaa
