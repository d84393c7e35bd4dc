// Batched interval + gradient evaluation: one pass over the tape for up to K boxes at once, the
// batched counterpart of IntervalGradEval (eval_interval_grad.h) as BatchIntervalEvalK
// (eval_batch.h) is IntervalEval's.
//
// Each tape slot holds four batched slots (the value and the three partials, K lower and K upper
// bounds each). Each operation is dispatched once for all K boxes and its rule runs over the lanes
// in SIMD vectors (batch_lanes.h; SSE2 on the baseline, AVX2 chosen at run time, never FMA). As
// IntervalGradEval does, it computes a slot's partial only along the variables the slot depends on
// (and, with `partials`, only those wanted); the others stay exactly [0,0] and cost nothing.
//
// Same results: every lane's value and partials are the same double pairs as IntervalGradEval
// gives for that box, the signs of zeros included, and its partial-domain flag is the same. The
// fast rules (add, sub, mul, scale, divc, neg, square, integer powers) compute each interval with
// the operations of core/interval.h in the order of IntervalGradRules (the product rule's
// a' * b + b' * a, square's a' * (2 a), the power's a' * (n a^(n-1))); a lane they do not cover (an
// empty or unbounded argument or partial, a NaN bound) is recomputed by the scalar rule, and every
// other operation (div, sqrt, the transcendentals, abs, min, max, the real power) runs the scalar
// rule of IntervalGradRules lane by lane. tests/expr/eval_batch_test.cpp checks bit equality.
// No min/max choices are recorded (SpecializingEval's regions need them: callers batch only tapes
// without min and max).
#pragma once

#include <cstdint>
#include <vector>

#include "expr/eval_batch.h"
#include "expr/eval_interval_grad.h"

namespace iaa {

/// Evaluates one tape and its gradient over up to K boxes per call. One per thread; no
/// allocation per call. Opens a RoundingScope itself when the caller has none.
template <int K>
class BatchIntervalGradEvalK : public detail::BatchIsa {
 public:
  static_assert(K == 2 || K == 4 || K == 8 || K == 16, "lane counts that are instantiated");
  /// The most boxes one call evaluates.
  static constexpr int kLanes = K;

  /// The evaluator keeps a pointer to its tape, which must outlive it. `partials` as in
  /// IntervalGradEval(tape, partials): only the partials along these variables (x = 1, y = 2,
  /// z = 4) are computed, each exactly as the full evaluation does; the others are [0,0].
  explicit BatchIntervalGradEvalK(const Tape& tape, detail::VarMask partials = detail::kAllVars);
  explicit BatchIntervalGradEvalK(Tape&&, detail::VarMask = detail::kAllVars) = delete;

  /// out[j] = F and its gradient over boxes[j] for j < n, 1 <= n <= K: what IntervalGradEval
  /// gives.
  void eval(const IBox* boxes, int n, IGrad* out);

  /// True when the last evaluation of box `lane` met a partial domain or a pole
  /// (IntervalGradEval::partial_domain).
  bool partial_domain(int lane) const { return partial_[static_cast<std::size_t>(lane)] != 0; }
  const Tape& tape() const { return *tape_; }

 private:
  using Slot = detail::BatchSlot<K>;
  /// Tape slot i's value (c = 0) or its partial along variable c - 1.
  Slot& slot(int i, int c) { return slots_[static_cast<std::size_t>(4 * i + c)]; }

  // The loop, forced inline into the baseline and the AVX2 code (batch_lanes.h, Runner).
  friend struct detail::batch::Runner;
  template <int W>
  void run_impl(int n);
  /// The scalar rule of instruction i for lane j (IntervalGradRules).
  void scalar_op(int i, int j);
  /// Copies lane 0 of tape slot i (value and partials) to the lanes n..K-1, so that the unused
  /// lanes compute what lane 0 does and never leave the fast rules.
  void fill_unused(int i, int n);

  std::uint8_t partial_[K] = {};
  detail::VarMask wanted_;
  bool bare_variable_;  ///< the tape is a variable or a constant and not every partial is wanted
  const Tape* tape_;
  std::vector<detail::VarMask> masks_;  ///< per tape slot, the partials computed there
  std::vector<Slot> slots_;             ///< 4 per tape slot: value, d/dx, d/dy, d/dz
};

extern template class BatchIntervalGradEvalK<2>;
extern template class BatchIntervalGradEvalK<4>;
extern template class BatchIntervalGradEvalK<8>;
extern template class BatchIntervalGradEvalK<16>;

/// The lane count that measured best (docs/eval.md, "The batched interval + gradient evaluator").
using BatchIntervalGradEval = BatchIntervalGradEvalK<8>;

}  // namespace iaa
