// EvalRaySet (docs/render.md, "How"; the paper's Fig. 2, made sound).
//
// A beam is a rectangle R of pixel coordinates; its segment over depths [t0, t1] is enclosed by
// the outward-rounded box of its 8 corners, clipped to the scene bounds. The depth range is
// searched front to back by an adaptive march (beam.cpp, DepthSearch); a piece whose box gives
// 0 not in F is certified empty.
// - Miss: every piece was excluded. Certified: no ray of the beam meets the surface there.
// - Full: a sign change between the slices at t_near and t_far, proved with intervals on slices
//   inside the bounds, with f continuous (no partial domain) on the box of [t_near, t_far].
//   Certified: every ray of the beam meets the surface in [t_near, t_far].
// - Partial: anything else. Some ray may hit; none hits before t_near.
#pragma once

#include <cstdint>
#include <vector>

#include "core/interval.h"
#include "render/context.h"
#include "render/trace.h"

namespace iaa {

/// What EvalRaySet found for one beam.
struct BeamSearch {
  BeamResult result = BeamResult::kMiss;
  double t_near = 0;  ///< no ray of the beam meets the surface before it (not for kMiss)
  double t_far = 0;   ///< kFull: every ray meets the surface at or before it; else the end searched
  IBox hit_box;       ///< kFull: box over [t_near, t_far]; kPartial: box of the kept piece
  IBox dirs;          ///< enclosure of the beam's directions
  // kFull only: the proof. f has the proved sign `sign` on the whole slice at t_s <= t_near and
  // the opposite sign on the slice at t_far, and is continuous on the box of [t_s, t_far].
  double t_s = 0;
  int sign = 0;
};

/// The first depth piece of a beam that may hold the surface (EvalRaySet's depth search), found
/// ahead of the rest of its EvalRaySet by first_pieces().
struct FirstPiece {
  bool found = false;  ///< false: every piece was excluded (a Miss)
  double a = 0, b = 0;
  IBox box;
  std::uint64_t evals = 0;              ///< interval evaluations the search made
  std::vector<DepthPieceTrace> pieces;  ///< its pieces, when traced
};

/// The depth searches of the sibling beams `rects[0..n)` (1 <= n <= 4: the children of one beam,
/// over the same depth range), side by side: each round takes one piece of each beam and
/// evaluates them in one pass of the batched evaluators where the context has them. Each beam's
/// search is the one eval_ray_set() makes, piece by piece, with the same intervals. Mean-value
/// budgets: with `budgets`, beam i follows budgets[i] (then its search is exactly the one
/// eval_ray_set() makes from that budget); else all follow `ctx.mv`, updated in the order of the
/// rounds rather than beam after beam. `traced`: record each beam's pieces in `out`.
void first_pieces(RenderContext& ctx, const PixelRect* rects, int n, Interval range, bool traced,
                  FirstPiece* out, MeanValueBudget* budgets = nullptr);

/// Runs EvalRaySet on the beam `rect` over depths `range`. A piece stops being halved when its
/// depth extent is at most settings.depth_tolerance times the beam's lateral width at its far
/// end. Records every piece into `trace` when it is not null. Needs a RoundingScope.
///
/// `parent`, when not null, is a Full result of a beam that contains this one: its slices
/// contain this beam's slices, so its proof carries over and this beam is Full without new
/// slice evaluations (its t_far is the parent's; see tighten_far()).
///
/// With `prove_full` false a beam that is not a Miss is returned as Partial without trying the
/// slices for full coverage (a caller that would gain nothing from the proof).
///
/// `first`, when not null, is this beam's depth search already made (first_pieces()): the rest of
/// EvalRaySet starts from it (its pieces go to `trace`).
BeamSearch eval_ray_set(RenderContext& ctx, const PixelRect& rect, Interval range,
                        const BeamSearch* parent, BeamTrace* trace, bool prove_full = true,
                        FirstPiece* first = nullptr);

/// A beam inside a Full beam `parent`, without any search: every ray of the parent, so every ray
/// of this beam, meets the surface in [parent t_near, parent t_far], and the parent's proof (its
/// slices contain this beam's slices) carries over. Used at the last level, where a tighter
/// t_near would change nothing but the shading point's bracket, and above it when the estimator
/// over this hit box is already within the threshold. Records `trace` when not null.
BeamSearch inherit_full(const RenderContext& ctx, const PixelRect& rect, const BeamSearch& parent,
                        BeamTrace* trace);

/// Tightens t_far of a Full beam: the slices at t_near + step 2^k (below t_far) are tried
/// front to back, and the first with the sign opposite to the proof's near slice becomes t_far
/// (then a few bisections towards t_near). The proof stays valid: its near slice and continuity
/// cover the shorter range. Returns true when t_far moved. Needs a RoundingScope.
bool tighten_far(RenderContext& ctx, BeamSearch* s, double step);

/// The estimator of a Full beam (docs/render.md, "How"; the paper's step 3): the interval dot
/// product of the unit normal grad F / |grad F| over the hit box with the unit beam direction.
/// Returns the whole line when |grad F| cannot be bounded away from 0 (or f is partial there).
///
/// With `pieces` > 1 the hit segment is cut into depth pieces, those whose F excludes 0 (no hit
/// there) are left out and the result is the hull over the others: halves first, and while that
/// hull is wider than `stop_above` (the caller's threshold) the halves of the pieces not left out,
/// down to `pieces` pieces. Every level encloses the same normals, finer ones more tightly; the
/// result is the first within `stop_above`, or the finest level's hull (evaluated only until it
/// is wider than `stop_above`: the decision is made).
Interval beam_estimator(RenderContext& ctx, const BeamSearch& s, int pieces = 1,
                        double stop_above = 2.0);

}  // namespace iaa
