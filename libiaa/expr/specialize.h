// Interval evaluation that prunes the min/max branches an interval proves inactive (the idea of
// libfive and Fidget; docs/design.md, "Speed").
//
// When an evaluation over a box B decides some min/max (min(a, b) takes a on all of B, say), the
// tape specialized by those choices (Tape::simplify) computes the same function on B with fewer
// instructions. B is remembered as a *region* with its specialized tape; a later box inside a
// region is evaluated with that region's tape. The searches of the renderer evaluate boxes
// nested inside boxes they evaluated just before (the halves of a depth piece, the slices and
// pieces of a hit segment, the sub-beams of a beam), so a few regions catch most evaluations.
//
// Same results: on a box inside B every decided min/max still takes the same argument (its
// enclosures only shrink), and the min/max rules then return that argument exactly, in every
// mode (ties go to the first argument everywhere: min_choice in eval_loop.h). Only the sign of a
// zero bound can differ (a partial derivative that is structurally zero in the shorter tape is
// not computed there, where the whole tape adds 0 rounded downward: -0).
// (A point value can differ where a left-out branch overflows or is NaN at that point although
// its interval enclosure was defined, e.g. exp(x) / exp(x) at x = 710.7, inf / inf: only the
// shading point, never a certificate, depends on point values.)
// A region is only made from an evaluation without partial domain: a branch left out is defined
// and continuous on the whole region, so leaving it out never hides a partial domain.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec.h"
#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "expr/tape.h"

namespace iaa {

class SpecializingEval {
 public:
  /// The evaluator keeps a pointer to `tape`, which must outlive it.
  explicit SpecializingEval(const Tape& tape);
  explicit SpecializingEval(Tape&&) = delete;
  SpecializingEval(const SpecializingEval&) = delete;
  SpecializingEval& operator=(const SpecializingEval&) = delete;

  /// F over a box: the same interval as IntervalEval over the whole tape.
  Interval eval(const IBox& b);
  /// F and its gradient over a box: the same as IntervalGradEval over the whole tape.
  IGrad eval_grad(const IBox& b);
  /// True when the last interval evaluation met a partial domain or a pole
  /// (IntervalEval::partial_domain).
  bool partial_domain() const { return partial_; }

  /// The most boxes of one batched evaluation.
  static constexpr int kBatch = 4;
  /// F over boxes[0..n), 1 <= n <= kBatch, in one pass of a batched evaluator
  /// (BatchIntervalEvalK), with the specialized tape of the newest region that holds every box
  /// (the whole tape when none does): for each box the interval eval() gives, and in partial[j]
  /// its partial_domain(). Makes no region (the batch records no choices). Worth it where
  /// few of the tape's operations run lane by lane (lane_by_lane_share).
  void eval_batch(const IBox* boxes, int n, Interval* out, bool* partial);
  /// F and its gradient over boxes[0..n) the same way (BatchIntervalGradEvalK): what eval_grad()
  /// gives each box, but for the signs of zero bounds of partial derivatives (see the top of
  /// this file).
  void eval_grad_batch(const IBox* boxes, int n, IGrad* out, bool* partial);
  /// Runs the batched evaluators' baseline (SSE2) code even where AVX2 is there (tests).
  void use_baseline(bool baseline);
  /// f and its gradient at a point: the same as PointEval and PointGradEval over the whole tape
  /// but where a left-out branch overflows or is NaN at that point (see the top of this file);
  /// a point inside a region takes the region's tape; points make no regions.
  double eval_point(const Vec3& p) { return variant_at(p).pe.eval(p); }
  PGrad eval_point_grad(const Vec3& p) { return variant_at(p).pg.eval(p); }

  /// Forgets every region and specialized tape: what follows is evaluated exactly as by a new
  /// evaluator, the count of specialized evaluations included (which, once kMaxVariants tapes
  /// exist, would otherwise depend on what was evaluated before).
  void reset();

  /// Interval evaluations that used a specialized tape, and the specialized tapes made so far.
  std::uint64_t specialized_evals() const { return specialized_evals_; }
  int variants() const { return static_cast<int>(variants_.size()) - 1; }

  /// Most specialized tapes kept (the choices of a tape with many min/max can combine in many
  /// ways; beyond this number boxes outside the regions use the whole tape).
  static constexpr int kMaxVariants = 64;
  /// Regions remembered, most recently made first.
  static constexpr int kRegions = 4;

 private:
  struct Variant {
    std::vector<std::uint8_t> key;     ///< per instruction of the whole tape: 0, 1 or 2
    std::unique_ptr<Tape> tape;        ///< the whole tape's, or its specialization by `key`
    std::vector<std::int32_t> origin;  ///< instruction j of `tape` is origin[j] of the whole tape
    std::vector<std::int32_t> undecided;  ///< the min/max instructions left in `tape`
    IntervalEval ie;
    IntervalGradEval ig;
    PointEval pe;
    PointGradEval pg;
    /// The batched evaluators of `tape`, made on first use.
    std::unique_ptr<BatchIntervalEvalK<kBatch>> be;
    std::unique_ptr<BatchIntervalGradEvalK<kBatch>> bg;
    Variant(std::vector<std::uint8_t> k, std::unique_ptr<Tape> t, std::vector<std::int32_t> o);
  };
  struct Region {
    IBox box;
    int variant = -1;  ///< -1: no region
  };

  /// The variant of the newest region that contains `b` (0, the whole tape, when none does).
  Variant& variant_for(const IBox& b);
  /// The same for a point.
  Variant& variant_at(const Vec3& p);
  /// The variant of the newest region that contains every box of boxes[0..n).
  Variant& variant_for(const IBox* boxes, int n);
  /// After an evaluation of `b` with `v`: when it decided more min/max, remembers `b` as a region
  /// with the tape specialized by everything decided.
  void learn(const IBox& b, const Variant& v, const std::vector<std::uint8_t>& choices);

  const Tape* tape_;
  std::vector<std::unique_ptr<Variant>> variants_;  ///< [0]: the whole tape
  std::array<Region, kRegions> regions_{};
  std::vector<std::uint8_t> key_;  ///< scratch for learn()
  bool partial_ = false;
  bool baseline_ = false;  ///< the batches run their baseline code
  std::uint64_t specialized_evals_ = 0;
};

}  // namespace iaa
