#include "render/beam.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include "core/error.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// slice_sign() of a slice that is not inside the bounds.
constexpr int kOutside = 2;
/// Slices tried for t_far.
constexpr int kFarTries = 10;
/// first_piece's march: a piece kMarchGrow times wider than the last after kMarchGrowAfter
/// excluded in a row (measured against 2 after 1, 2 after 2 or 3, 1.25 after 1 or 2 and 1.5
/// after 1 or 3 on chubs, the Barth sextic and the twist: docs/render.md).
constexpr double kMarchGrow = 1.5;
constexpr int kMarchGrowAfter = 2;
/// Pieces up to this many depth tolerances wide are also tried with the mean-value form.
constexpr double kMeanValueWidth = 16.0;
/// Bisection steps that tighten t_far once a candidate succeeded.
constexpr int kFarRefine = 3;

/// Mean-value form of F over a box: F(c) + sum_i dF/dx_i(box) (box_i - c_i), c the centre.
/// Valid where f is Lipschitz on the box (the interval gradient contains the generalized
/// gradients at kinks); the whole line when the gradient meets a partial domain.
Interval mean_value_form(RenderContext& ctx, const IBox& box, const IGrad& g) {
  IBox c;
  for (int i = 0; i < 3; ++i) c[i] = Interval(box[i].mid());
  Interval f = ctx.eval(c);
  for (int i = 0; i < 3; ++i) f += g.g[static_cast<std::size_t>(i)] * (box[i] - c[i]);
  return intersect(f, g.v);
}

Interval mean_value_form(RenderContext& ctx, const IBox& box) {
  bool gpartial = false;
  const IGrad g = ctx.eval_grad(box, &gpartial);
  if (gpartial) return Interval::whole();
  return mean_value_form(ctx, box, g);
}

/// Mean-value form of F over the points p = eye + t d (t in `t`, d in `dirs`) of a depth piece of
/// the beam that lie in `box` (the piece's box, clipped to the bounds), given the interval
/// gradient `g` over `box`. Around the point c = eye + tc dc of the piece's central ray,
///   p - c = (t - tc) d + tc (d - dc),
/// and f(p) = f(c) + grad f(xi) . (p - c) for some xi on the segment from c to p, which lies in
/// the box (convex, holding both). So
///   f(p) in F(c) + (G . D) (T - tc) + tc G . (D - dc),
/// and also in the box form F(c) + G . (box - c); both are kept. Along a beam that grazes the
/// surface (a silhouette) G . D, the derivative along the rays, is small while the box form adds
/// |G_i| times the box's whole extent in each axis: the ray form excludes pieces the box form
/// keeps. c is enclosed in a tiny box (the double arithmetic of eye + tc dc rounds); when that box
/// is not inside `box` (a piece clipped by the bounds), the box form around the box's centre is
/// used alone. Valid where the box form is.
///
/// In two steps, so that the depth searches of sibling beams can evaluate their points together:
/// PieceMeanValue names the point box c to evaluate, form() takes F(c).
struct PieceMeanValue {
  IBox dc;             ///< the central direction
  IBox c;              ///< the box of the point around which the form is taken
  bool rayed = false;  ///< c is on the central ray inside `box`: the ray form too
  PieceMeanValue() = default;
  PieceMeanValue(const RenderContext& ctx, const IBox& box, const IBox& dirs, const Interval& t)
      : dc(Interval(dirs.x.mid()), Interval(dirs.y.mid()), Interval(dirs.z.mid())) {
    c = segment_box(ctx.setup.frame.eye, dc, Interval(t.mid()));
    rayed = box.contains(c);
    if (!rayed) {
      for (int i = 0; i < 3; ++i) c[i] = Interval(box[i].mid());
    }
  }
  // Out of line: inlined into DepthSearch::run, GCC left that loop's interval products out of
  // line instead (chubs, the teardrop, the tri-trumpet 1.006x-1.009x the instructions).
  [[gnu::noinline]] Interval form(const Interval& fc, const IBox& box, const IGrad& g,
                                  const IBox& dirs, const Interval& t) const {
    if (!rayed) {
      Interval f = fc;
      for (int i = 0; i < 3; ++i) f += g.g[static_cast<std::size_t>(i)] * (box[i] - c[i]);
      return intersect(f, g.v);
    }
    const double tc = t.mid();
    Interval along = Interval(0.0), across = Interval(0.0), boxed = fc;
    for (int i = 0; i < 3; ++i) {
      const Interval& gi = g.g[static_cast<std::size_t>(i)];
      along += gi * dirs[i];
      across += gi * (dirs[i] - dc[i]);
      boxed += gi * (box[i] - c[i]);
    }
    const Interval rayed_form = fc + along * (t - tc) + Interval(tc) * across;
    return intersect(intersect(rayed_form, boxed), g.v);
  }
};

/// Sign of F on the (unclipped) slice of the beam at depth t: +1 / -1 when proved with intervals
/// on a slice inside the bounds without partial domain, else 0.
int slice_sign(RenderContext& ctx, const IBox& dirs, double t) {
  const IBox slice = segment_box(ctx.setup.frame.eye, dirs, Interval(t));
  if (!box_inside(slice, ctx.bounds())) return kOutside;
  bool partial = false;
  IGrad g;
  const bool have_grad = ctx.mv.gradient_first(MeanValueBudget::kSlice);
  if (have_grad) g = ctx.eval_grad(slice, &partial);
  Interval f = have_grad ? g.v : ctx.eval(slice, &partial);
  if (partial) return 0;
  ctx.mv.record_natural(MeanValueBudget::kSlice, !f.contains_zero());
  if (f.contains_zero() && ctx.mv.allowed()) {
    f = have_grad ? mean_value_form(ctx, slice, g) : mean_value_form(ctx, slice);
    ctx.mv.record(!f.contains_zero());
  }
  return f.certainly_positive() ? 1 : (f.certainly_negative() ? -1 : 0);
}

/// slice_sign() of the slice at depth t where only the sign `want` is of use (a far slice of a
/// full-coverage proof): the point value at the slice's central ray comes first, and where it
/// does not have that sign (it lies inside the slice's box, so F over the slice, which encloses
/// it, cannot have it either) the slice is not evaluated and 0 is returned. Still kOutside for
/// a slice not inside the bounds. The point costs a fraction of an interval evaluation; on the
/// slices beside a silhouette, which mostly fail, it saves the evaluation and its mean-value
/// form.
int far_slice_sign(RenderContext& ctx, const IBox& dirs, double t, int want) {
  const Vec3& eye = ctx.setup.frame.eye;
  const IBox slice = segment_box(eye, dirs, Interval(t));
  if (!box_inside(slice, ctx.bounds())) return kOutside;
  const Vec3 p = eye + t * Vec3{dirs.x.mid(), dirs.y.mid(), dirs.z.mid()};
  if (slice.contains(p)) {
    const double v = ctx.se.eval_point(p);
    if (!(want > 0 ? v > 0 : v < 0)) return 0;
  }
  return slice_sign(ctx, dirs, t);
}

Vec3 box_centre(const IBox& b) {
  return {b.x.mid(), b.y.mid(), b.z.mid()};
}

/// A cone around the box's centre that holds every vector of the box, by the cosine and sine of
/// its half-angle: the largest angle between the centre and a corner. The vectors of a box are
/// the convex hull of its corners, and a cone of half-angle below 90 degrees is convex, so the
/// corners decide. `cos` is 0 or less (no such cone) when some corner is 90 degrees or more
/// away, or the box is not finite.
struct ConeAngle {
  double cos = 0, sin = 1;
};

ConeAngle cone_half_angle(const IBox& b) {
  if (!(b.x.is_finite() && b.y.is_finite() && b.z.is_finite())) return {};
  const Vec3 c = box_centre(b);
  const double lc = length(c);
  if (!(lc > 0)) return {};
  // Per axis, each end's product with the centre and its square: a corner's dot(v, c) and
  // dot(v, v) are sums of these in dot()'s order, so the same doubles as length(v) and
  // dot(v, c) of the corner, with 12 products instead of 48.
  const double ex[2] = {b.x.lo(), b.x.hi()}, ey[2] = {b.y.lo(), b.y.hi()},
               ez[2] = {b.z.lo(), b.z.hi()};
  const double px[2] = {ex[0] * c.x, ex[1] * c.x}, py[2] = {ey[0] * c.y, ey[1] * c.y},
               pz[2] = {ez[0] * c.z, ez[1] * c.z};
  const double sx[2] = {ex[0] * ex[0], ex[1] * ex[1]}, sy[2] = {ey[0] * ey[0], ey[1] * ey[1]},
               sz[2] = {ez[0] * ez[0], ez[1] * ez[1]};
  double worst = 1.0;  // smallest cosine
  for (int k = 0; k < 8; ++k) {
    const int i = k & 1, j = (k >> 1) & 1, l = (k >> 2) & 1;
    const double lv = std::sqrt(sx[i] + sy[j] + sz[l]);
    if (!(lv > 0)) return {};
    const double cv = (px[i] + py[j] + pz[l]) / (lv * lc);
    if (!(cv > 0)) return {};  // 90 degrees or more (or NaN, which std::min would skip)
    worst = std::min(worst, cv);
  }
  worst = std::min(1.0, worst);
  return {worst, std::sqrt((1.0 - worst) * (1.0 + worst))};
}

/// Records a search's outcome in its trace (when tracing) and returns it.
const BeamSearch& traced(const BeamSearch& out, const char* reason, BeamTrace* trace) {
  if (trace) {
    trace->result = out.result;
    trace->t_near = out.t_near;
    trace->t_far = out.t_far;
    trace->hit_box = out.hit_box;
    trace->full_reason = reason;
  }
  return out;
}

/// The depth searches of EvalRaySet, for one beam or for up to 4 sibling beams side by side.
///
/// Each beam's search goes front to back for the first piece that may hold the surface, no wider
/// than the depth tolerance (times the beam's lateral width at the piece's far end); none when
/// every piece is excluded. An adaptive march: the piece at the front starts one tolerance wide;
/// a kept piece is halved (the front half is tried next), and after kMarchGrowAfter excluded
/// pieces in a row the next one is kMarchGrow times wider. Every depth in front of the piece
/// found was excluded, as with bisection; but the pieces follow how far from the surface the
/// beam runs, where bisection's halves of the whole range do not: beside a silhouette the widest
/// piece that can be excluded grows slowly along the beam, and bisection spent two evaluations
/// per level on the way down to it and halves that were kept only for being too wide.
///
/// Sibling beams (the children of one beam) search the same range in rounds: each round takes
/// the next piece of every beam still searching, evaluates their natural enclosures (or their
/// gradients first) in one pass of the batched evaluators, then the gradients and the points of
/// the mean-value forms they need in one pass each (the batch gives the intervals of the
/// one-box evaluators, bit for bit). Each beam follows its own mean-value budget: with a budget
/// per beam its search is the one it makes alone; where siblings share one (the sub-beams of a
/// pixel), it is updated in the order of the rounds rather than beam after beam.
class DepthSearch {
 public:
  static constexpr int kMost = 4;

  DepthSearch(RenderContext& ctx, Interval range) : ctx_(ctx), range_(range) {}

  /// Adds a beam with directions `dirs` `width` pixels wide; its result goes to `out`, its
  /// pieces to `pieces` when that is not null.
  void add(const IBox& dirs, double width, FirstPiece* out, std::vector<DepthPieceTrace>* pieces,
           MeanValueBudget* mv) {
    IAA_CHECK(n_ < kMost);
    Lane& l = lanes_[n_++];
    l.mv = mv;
    l.dirs = dirs;
    l.lateral = width * ctx_.setup.frame.scale;
    l.a = range_.lo();
    l.w = std::max(abs_floor(), tol_factor() * l.lateral * l.a);
    l.out = out;
    l.pieces = pieces;
    l.active = l.a <= range_.hi();  // a range of one depth is one piece, as wide as 0
    *out = FirstPiece{};
  }

  void run() {
    for (bool any = true; any;) {
      any = false;
      int nv = 0, ng = 0;
      int vi[kMost], gi[kMost];
      for (int i = 0; i < n_; ++i) {
        Lane& l = lanes_[i];
        l.evaluated = l.need_mv = false;
        if (!l.active) continue;
        any = true;
        l.b = l.w < range_.hi() - l.a ? l.a + l.w : range_.hi();
        l.box =
            clip_box(segment_box(ctx_.setup.frame.eye, l.dirs, Interval(l.a, l.b)), ctx_.bounds());
        if (l.box.is_empty()) {
          record(l, Interval::empty(), false, false, false);
          l.natural_kept = false;
          exclude(l);
          continue;
        }
        l.tol = std::max(abs_floor(), tol_factor() * l.lateral * l.b);
        l.narrow = l.b - l.a <= kMeanValueWidth * l.tol;
        // Where the natural enclosure of narrow pieces rarely excludes 0 (the budget's record),
        // or kept this beam's narrow piece before (a stretch beside a silhouette), the gradient
        // evaluation of the mean-value form comes first: its value part is that same natural
        // enclosure, so the outcome is the same either way.
        l.grad = l.narrow && (l.mv->gradient_first(MeanValueBudget::kPiece) ||
                              (l.natural_kept && l.mv->allowed()));
        l.evaluated = true;
        (l.grad ? gi[ng++] : vi[nv++]) = i;
      }
      naturals(vi, nv);
      grads(gi, ng, &Lane::partial);
      // The natural enclosures' verdicts; the mean-value form where it may exclude what they kept
      // (a narrow piece a few tolerances wide near, but off, the surface).
      int nm = 0;
      int mi[kMost];
      for (int i = 0; i < n_; ++i) {
        Lane& l = lanes_[i];
        if (!l.evaluated) continue;
        if (l.grad) l.f = l.g.v;
        const bool kept = !l.f.is_empty() && l.f.contains_zero();
        l.natural_kept = l.narrow && kept && !l.partial;
        if (l.narrow) l.mv->record_natural(MeanValueBudget::kPiece, !kept);
        record(l, l.f, kept, l.partial, false);
        if (!kept) {
          exclude(l);
        } else if (l.partial || !l.narrow || !l.mv->allowed()) {
          keep(l);
        } else {
          l.need_mv = true;
          l.gpartial = false;
          if (!l.grad) mi[nm++] = i;
        }
      }
      grads(mi, nm, &Lane::gpartial);
      int np = 0;
      int pi[kMost];
      for (int i = 0; i < n_; ++i) {
        Lane& l = lanes_[i];
        if (!l.need_mv || l.gpartial) continue;
        l.mvf = PieceMeanValue(ctx_, l.box, l.dirs, Interval(l.a, l.b));
        pi[np++] = i;
      }
      points(pi, np);
      for (int i = 0; i < n_; ++i) {
        Lane& l = lanes_[i];
        if (!l.need_mv) continue;
        const Interval fm = l.gpartial ? Interval::whole()
                                       : l.mvf.form(l.fc, l.box, l.g, l.dirs, Interval(l.a, l.b));
        l.mv->record(!fm.contains_zero());
        record(l, fm, fm.contains_zero(), false, true);
        if (fm.contains_zero()) {
          keep(l);
        } else {
          exclude(l);
        }
      }
    }
  }

 private:
  struct Lane {
    IBox dirs;
    double lateral = 0;
    double a = 0, w = 0, b = 0, tol = 0;
    int run = 0;                // pieces excluded in a row
    bool natural_kept = false;  // the last piece was narrow and its natural enclosure kept it
    bool active = false;
    FirstPiece* out = nullptr;
    std::vector<DepthPieceTrace>* pieces = nullptr;
    MeanValueBudget* mv = nullptr;  ///< the budget its mean-value forms follow
    // This round's piece:
    IBox box;
    bool evaluated = false, narrow = false, grad = false, partial = false;
    bool need_mv = false, gpartial = false;
    Interval f, fc;
    IGrad g;
    PieceMeanValue mvf;
  };

  double abs_floor() const { return 1e-12 * std::max(1.0, range_.hi()); }
  double tol_factor() const { return ctx_.setup.settings.depth_tolerance; }

  void record(Lane& l, const Interval& f, bool kept, bool partial, bool mean_value) {
    if (l.pieces) l.pieces->push_back({Interval(l.a, l.b), l.box, f, kept, partial, mean_value});
  }
  void exclude(Lane& l) {
    l.a = l.b;
    if (++l.run >= kMarchGrowAfter) l.w *= kMarchGrow;
    l.active = l.a < range_.hi();
  }
  void keep(Lane& l) {
    const double m = 0.5 * (l.a + l.b);
    if (l.b - l.a <= l.tol || m <= l.a || m >= l.b) {
      l.out->found = true;
      l.out->a = l.a;
      l.out->b = l.b;
      l.out->box = l.box;
      l.active = false;
      return;
    }
    l.w = m - l.a;
    l.run = 0;
  }

  /// Evaluates the boxes `box_of(lane)` of the lanes which[0..k), each counted as one evaluation
  /// of its beam, with `many(boxes, k, results, partials)` (the context's batch calls: one pass
  /// for two or more where it has the batch, the same intervals as one at a time). Hands each
  /// lane its result and partial-domain flag: `done(lane, result, partial)`.
  template <class Result, class BoxOf, class Many, class Done>
  void evaluate(const int* which, int k, BoxOf box_of, Many many, Done done) {
    if (k == 0) return;
    IBox boxes[kMost];
    Result r[kMost];
    bool partial[kMost];
    for (int j = 0; j < k; ++j) {
      ++lanes_[which[j]].out->evals;
      boxes[j] = box_of(lanes_[which[j]]);
    }
    many(boxes, k, r, partial);
    for (int j = 0; j < k; ++j) done(lanes_[which[j]], r[j], partial[j]);
  }
  /// F over the lanes' pieces: their natural enclosures (into f, the flags into partial).
  void naturals(const int* which, int k) {
    evaluate<Interval>(
        which, k, [](const Lane& l) -> const IBox& { return l.box; },
        [&](const IBox* b, int n, Interval* r, bool* p) { ctx_.eval_batch(b, n, r, p); },
        [](Lane& l, const Interval& f, bool partial) {
          l.f = f;
          l.partial = partial;
        });
  }
  /// F over the points of the lanes' mean-value forms (into fc).
  void points(const int* which, int k) {
    evaluate<Interval>(
        which, k, [](const Lane& l) -> const IBox& { return l.mvf.c; },
        [&](const IBox* b, int n, Interval* r, bool* p) { ctx_.eval_batch(b, n, r, p); },
        [](Lane& l, const Interval& f, bool) { l.fc = f; });
  }
  /// F and its gradient over the lanes' pieces into g, the partial-domain flag into .*partial.
  void grads(const int* which, int k, bool Lane::*partial) {
    evaluate<IGrad>(
        which, k, [](const Lane& l) -> const IBox& { return l.box; },
        [&](const IBox* b, int n, IGrad* r, bool* p) { ctx_.eval_grad_batch(b, n, r, p); },
        [partial](Lane& l, const IGrad& g, bool p) {
          l.g = g;
          l.*partial = p;
        });
  }

  RenderContext& ctx_;
  Interval range_;
  Lane lanes_[kMost];
  int n_ = 0;
};

/// The near slice of a full-coverage proof for a beam whose first kept piece starts at `a` and
/// is `w` wide: at t_near, or up to 2w before it. No ray meets the surface in the excluded pieces
/// in front of t_near, so a sign proved at t_s <= t_near still brackets the first hit of every ray
/// in [t_near, t_far]; close to the surface intervals cannot tell the sign. Sets `t_s` and
/// returns slice_sign() there.
int near_slice(RenderContext& ctx, const IBox& dirs, Interval range, double a, double w,
               double* t_s) {
  int s_near = 0;
  for (int k = 0; k < 4; ++k) {
    *t_s = k == 0 ? a : std::max(range.lo(), a - std::ldexp(w, k - 1));
    s_near = slice_sign(ctx, dirs, *t_s);
    if (s_near == 1 || s_near == -1 || *t_s <= range.lo()) break;
  }
  return s_near;
}

/// Tightens a far slice `tf` with the sign -s_near by bisection towards `t_fail` (the last depth
/// found without it), while the gap is wider than `w`: a shorter [t_near, t_far] gives a smaller
/// hit box (a sharper estimator) and a shorter search for the children.
double refine_far(RenderContext& ctx, const IBox& dirs, int s_near, double t_fail, double tf,
                  double w) {
  for (int r = 0; r < kFarRefine && tf - t_fail > w; ++r) {
    const double tm = 0.5 * (t_fail + tf);
    if (far_slice_sign(ctx, dirs, tm, -s_near) == -s_near) {
      tf = tm;
    } else {
      t_fail = tm;
    }
  }
  return tf;
}

/// Makes `out` Full over [t_near, tf] when the box of [t_s, tf] lies inside the bounds and f is
/// continuous on it (the slices at t_s and tf have the proved signs s_near and -s_near). Returns
/// why full coverage was or was not certified.
const char* certify_full(RenderContext& ctx, double t_s, double tf, int s_near, BeamSearch* out) {
  const Vec3& eye = ctx.setup.frame.eye;
  const IBox seg = segment_box(eye, out->dirs, Interval(t_s, tf));
  if (!box_inside(seg, ctx.bounds())) return "corner rays leave the bounds before t_far";
  bool partial = false;
  if (ctx.setup.may_partial) ctx.eval(seg, &partial);
  if (partial) return "f may be undefined or discontinuous between t_near and t_far";
  out->result = BeamResult::kFull;
  out->t_far = tf;
  out->t_s = t_s;
  out->sign = s_near;
  out->hit_box = segment_box(eye, out->dirs, Interval(out->t_near, tf));
  return "sign change proved between the slices at t_near and t_far";
}

/// Full coverage of the Partial beam `out` whose first kept piece is `w` wide: opposite proved
/// signs on the slices at t_near and at some t_far >= t_near, with the box of [t_near, t_far]
/// inside the bounds and f continuous on it. Makes `out` Full when proved; returns why full
/// coverage was or was not certified.
const char* prove_full_coverage(RenderContext& ctx, Interval range, double w, BeamSearch* out) {
  const double a = out->t_near;
  double t_s = a;
  const int s_near = near_slice(ctx, out->dirs, range, a, w, &t_s);
  if (s_near != 1 && s_near != -1) return "no proved sign on the slice at t_near";
  // Candidates t_near + w 2^k, the last one clamped to the end of the range. The depths whose
  // slice lies inside the bounds form an interval, so the search stops at the first slice
  // outside.
  double t_fail = a;  // the last candidate without the opposite sign
  for (int k = 0; k < kFarTries; ++k) {
    const double tf = std::min(a + std::ldexp(w, k), range.hi());
    const int s_far = far_slice_sign(ctx, out->dirs, tf, -s_near);
    if (s_far == kOutside) return "the slices leave the bounds before a sign change";
    if (s_far == -s_near)
      return certify_full(ctx, t_s, refine_far(ctx, out->dirs, s_near, t_fail, tf, w), s_near, out);
    if (tf >= range.hi()) break;
    t_fail = tf;
  }
  return "no slice with the opposite sign found";
}

}  // namespace

void first_pieces(RenderContext& ctx, const PixelRect* rects, int n, Interval range, bool traced,
                  FirstPiece* out, MeanValueBudget* budgets) {
  IAA_CHECK(n >= 1 && n <= DepthSearch::kMost);
  DepthSearch search(ctx, range);
  for (int i = 0; i < n; ++i) {
    const PixelRect& r = rects[i];
    search.add(ctx.setup.frame.dir_box(r), std::max(r.width(), r.height()), &out[i],
               traced ? &out[i].pieces : nullptr, budgets ? &budgets[i] : &ctx.mv);
  }
  if (!range.is_empty()) search.run();
}

BeamSearch eval_ray_set(RenderContext& ctx, const PixelRect& rect, Interval range,
                        const BeamSearch* parent, BeamTrace* trace, bool prove_full,
                        FirstPiece* first) {
  BeamSearch out;
  out.dirs = ctx.setup.frame.dir_box(rect);
  if (trace) trace->searched = range;
  if (range.is_empty()) return out;
  FirstPiece own;
  if (first) {
    if (trace) trace->pieces = std::move(first->pieces);
  } else {
    DepthSearch search(ctx, range);
    search.add(out.dirs, std::max(rect.width(), rect.height()), &own,
               trace ? &trace->pieces : nullptr, &ctx.mv);
    search.run();
    first = &own;
  }
  if (!first->found) {
    out.result = BeamResult::kMiss;
    if (trace) {
      trace->result = out.result;
      trace->full_reason = "every depth piece excluded 0";
    }
    return out;
  }
  const double a = first->a;
  out.hit_box = first->box;
  out.t_near = a;
  out.t_far = range.hi();
  out.result = BeamResult::kPartial;

  if (parent && parent->result == BeamResult::kFull && parent->t_s <= a && a <= parent->t_far) {
    // Inherited proof: this beam's slices lie inside the parent's, where the signs are proved.
    // t_far stays the parent's: tighten_far() shortens it only where the estimator needs it
    // (a bisection step here on every child costs more than it saves).
    out.result = BeamResult::kFull;
    out.t_s = parent->t_s;
    out.sign = parent->sign;
    out.t_far = parent->t_far;
    out.hit_box = segment_box(ctx.setup.frame.eye, out.dirs, Interval(a, out.t_far));
    return traced(out, "inside a Full parent: its sign change proof covers this beam", trace);
  }
  if (!prove_full)
    return traced(out,
                  "full coverage not tried: another part of the pixel is already certified covered",
                  trace);
  return traced(out, prove_full_coverage(ctx, range, first->b - a, &out), trace);
}

BeamSearch inherit_full(const RenderContext& ctx, const PixelRect& rect, const BeamSearch& parent,
                        BeamTrace* trace) {
  IAA_CHECK(parent.result == BeamResult::kFull);
  BeamSearch out = parent;
  out.dirs = ctx.setup.frame.dir_box(rect);
  out.hit_box = segment_box(ctx.setup.frame.eye, out.dirs, Interval(out.t_near, out.t_far));
  if (trace) trace->searched = Interval::empty();  // nothing was searched
  return traced(out, "inside a Full parent: its proof covers this beam, no search", trace);
}

bool tighten_far(RenderContext& ctx, BeamSearch* s, double step) {
  if (s->result != BeamResult::kFull || !(step > 0)) return false;
  // Candidates t_near + step 2^k from the front: the first slice with the opposite sign is the
  // nearest such depth to within a factor 2 (a bisection of [t_near, t_far] would be misled by
  // a thin feature, behind which the slices have the near sign again).
  double t_fail = s->t_near, tf = 0;
  bool found = false;
  for (int k = 0; k < kFarTries; ++k) {
    tf = s->t_near + std::ldexp(step, k);
    if (!(tf < s->t_far)) break;
    if (far_slice_sign(ctx, s->dirs, tf, -s->sign) == -s->sign) {
      found = true;
      break;
    }
    t_fail = tf;
  }
  if (!found) return false;
  for (int r = 0; r < kFarRefine && tf - t_fail > step; ++r) {
    const double tm = 0.5 * (t_fail + tf);
    if (far_slice_sign(ctx, s->dirs, tm, -s->sign) == -s->sign) {
      tf = tm;
    } else {
      t_fail = tm;
    }
  }
  s->t_far = tf;
  s->hit_box = segment_box(ctx.setup.frame.eye, s->dirs, Interval(s->t_near, tf));
  return true;
}

namespace {

/// What the estimator needs of a beam's direction box, computed once per beam: the box, the
/// enclosure of 1 / |d|, and the cone around the box's centre that holds every direction.
struct DirCone {
  IBox dirs;
  Interval inv_len;
  Vec3 centre;
  ConeAngle half_angle;

  explicit DirCone(const IBox& d) : dirs(d), centre(box_centre(d)), half_angle(cone_half_angle(d)) {
    Domain dom = Domain::kFull;
    inv_len = Interval(1.0) / sqrt(square(d.x) + square(d.y) + square(d.z), &dom);
  }
};

/// The estimator's interval of n . d over one box, from its interval gradient `g`.
Interval unit_dot(const IGrad& g, const DirCone& dc) {
  const Interval n2 = square(g.g[0]) + square(g.g[1]) + square(g.g[2]);
  if (!(n2.lo() > 0.0) || !n2.is_finite()) return Interval::whole();
  // The componentwise interval form: grad F . d / (|grad F| |d|).
  Domain dom = Domain::kFull;
  const Interval inv_n = Interval(1.0) / sqrt(n2, &dom);
  const IBox& dirs = dc.dirs;
  const Interval quotient =
      (g.g[0] * dirs.x + g.g[1] * dirs.y + g.g[2] * dirs.z) * inv_n * dc.inv_len;
  const IBox gb(g.g[0], g.g[1], g.g[2]);
  // Both the normals and the directions are enclosed in cones around their boxes' centres; the
  // angle between a normal and a direction then lies within the sum of the half-angles of the
  // angle between the centres. This encloses the same set of dot products as the componentwise
  // interval quotient, much more tightly (that one multiplies the width by the ratio of the
  // largest to the smallest |grad F| on the box). Both enclose the same set, so their
  // intersection does too. A cone of 90 degrees or more proves nothing: the quotient alone.
  const ConeAngle ag = cone_half_angle(gb), ad = dc.half_angle;
  if (!(ag.cos > 0) || !(ad.cos > 0)) return quotient;
  const Vec3 cg = box_centre(gb), cd = dc.centre;
  const double c0 = std::clamp(dot(cg, cd) / (length(cg) * length(cd)), -1.0, 1.0);
  // With th the angle between the centres and s = ag + ad (below 180 degrees), the dot products
  // lie in [cos(min(180, th + s)), cos(max(0, th - s))]: by the angle-sum formulas, without
  // inverse trigonometric functions (cos is decreasing on [0, 180]: th <= s iff cos th >= cos s,
  // th + s >= 180 iff cos th <= -cos s).
  const double cs = ag.cos * ad.cos - ag.sin * ad.sin, ss = ag.sin * ad.cos + ag.cos * ad.sin;
  const double s0 = std::sqrt((1.0 - c0) * (1.0 + c0));
  // The slack covers the rounding of the few double operations above (a decision, not a claim).
  constexpr double kSlack = 1e-9;
  const Interval cone(c0 <= -cs ? -1.0 : std::max(-1.0, c0 * cs - s0 * ss - kSlack),
                      c0 >= cs ? 1.0 : std::min(1.0, c0 * cs + s0 * ss + kSlack));
  // Both enclose the same set: keep what both allow.
  const Interval both = intersect(quotient, cone);
  return both.is_empty() ? quotient : both;
}

}  // namespace

Interval beam_estimator(RenderContext& ctx, const BeamSearch& s, int pieces, double stop_above) {
  // Only the normals at the first hits matter, and those lie where the surface may be: the hit
  // segment is cut into depth pieces, a piece whose F excludes 0 holds no hit and is left out,
  // and the estimator is the hull over the others. Smaller boxes also give sharper gradients
  // (the box of a long slanted segment is much wider than the segment). The pieces are halves
  // first, then the halves of those that may hold a hit and are needed, down to `pieces`: the
  // hull over coarser pieces often decides already, and the halves of a piece that excludes 0
  // are never evaluated.
  const DirCone dc(s.dirs);
  if (pieces <= 1) {
    bool partial = false;
    const IGrad g = ctx.eval_grad(s.hit_box, &partial);
    return partial ? Interval::whole() : unit_dot(g, dc);
  }
  constexpr int kMaxPieces = 64;
  struct Piece {
    double t0, t1;
  };
  Piece cur[kMaxPieces], next[kMaxPieces];
  int n = 0;
  // Appends the halves of p to cur (p itself when it has no double strictly inside).
  const auto push_halves = [&](const Piece& p) {
    const double mid = 0.5 * (p.t0 + p.t1);
    if (mid > p.t0 && mid < p.t1) {
      cur[n++] = {p.t0, mid};
      cur[n++] = {mid, p.t1};
    } else {
      cur[n++] = p;
    }
  };
  push_halves({s.t_near, s.t_far});
  const int most = std::min(pieces, kMaxPieces);
  // The pieces of a level are evaluated in groups, front to back: up to the batch's lanes in one
  // pass where the context has the gradient batch (the intervals one at a time gives, but for the
  // signs of zero bounds of partials on tapes with min or max, which unit_dot does not tell
  // apart), else one by one (RenderContext::eval_grad_batch). A group may evaluate a few pieces
  // past the point where the level's decision is made; they are counted and their results dropped,
  // so the estimate is the one of the pieces in order.
  constexpr int kGroup = SpecializingEval::kBatch;
  IGrad g[kGroup];
  bool partial[kGroup];
  for (int width = 2;; width *= 2) {
    // Evaluate this level front to back until the hull is too wide; what is left (and the kept
    // pieces) is halved for the next level.
    Interval out = Interval::empty();
    int m = 0;
    bool decided_wide = false;
    const bool finer = 2 * width <= most;
    for (int k0 = 0; k0 < n; k0 += kGroup) {
      const int count = std::min(kGroup, n - k0);
      if (!decided_wide) {
        IBox boxes[kGroup];
        for (int j = 0; j < count; ++j) {
          boxes[j] =
              segment_box(ctx.setup.frame.eye, s.dirs, Interval(cur[k0 + j].t0, cur[k0 + j].t1));
        }
        ctx.eval_grad_batch(boxes, count, g, partial);
      }
      for (int j = 0; j < count; ++j) {
        const Piece p = cur[k0 + j];
        if (decided_wide) {
          next[m++] = p;  // not needed at this level
          continue;
        }
        if (partial[j]) return Interval::whole();
        if (!g[j].v.contains_zero()) continue;
        const Interval u = unit_dot(g[j], dc);
        out = out.is_empty() ? u : hull(out, u);
        next[m++] = p;
        // The hull only grows: the decision at this level is made.
        if (out.width() > stop_above) {
          if (!finer) return out;
          decided_wide = true;
        }
      }
    }
    if (!decided_wide) return out.is_empty() ? Interval::whole() : out;
    // Halve the pieces that are left.
    n = 0;
    for (int k = 0; k < m; ++k) push_halves(next[k]);
  }
}

}  // namespace iaa
