// The IAA kernel: the pixel's beam split into four sub-beams until each is a Miss (background),
// a Full beam whose estimator is within the threshold, or at max_level; each such leaf is shaded
// once at a point of its surface and weighted by its area (docs/render.md, "How").
#include <algorithm>
#include <utility>

#include "render/kernel.h"
#include "render/ray_search.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// How far behind t_near (in beam widths) a Partial beam's central ray is searched for shading.
constexpr double kPartialShadeReach = 8.0;
/// Depth tolerance of the central ray of an IAA part, in footprints of the part (its lateral
/// width at the depth): where it is shaded, not whether it is covered.
constexpr double kShadeTolerance = 1.0 / 64;
/// Share of a Partial part's area shown as surface when its central ray finds no surface at all.
constexpr double kPartialMissWeight = 0.25;
/// Point-value steps over [t_near, t_far] in which the first crossing of a Full part's central
/// ray is looked for before regula falsi narrows it (full_root).
constexpr int kRootMarch = 8;
/// Most depth pieces of a Full beam's hit segment over which the estimator is taken (halves first,
/// then halves of those that may hold a hit while the hull is too wide: beam_estimator).
constexpr int kEstimatorPieces = 8;

/// The first crossing of g (> 0 at a, < 0 at b) in [a, b]: a march of kRootMarch point values
/// from the front to the first step whose far end has the far sign (a feature thinner than a
/// step can still hide a crossing: shading only), then regula falsi (Illinois) to within `tol`.
template <class G>
double first_crossing(const G& g, double a, double b, double ga, double gb, double tol) {
  const double step = (b - a) / kRootMarch;
  for (int k = 1; k < kRootMarch; ++k) {
    const double t = a + k * step;
    if (!(t > a && t < b)) break;
    const double gt = g(t);
    if (gt == 0) return t;
    if (gt < 0) {
      b = t;
      gb = gt;
      break;
    }
    if (gt > 0) {
      a = t;
      ga = gt;
    }
  }
  int stale = 0;  // which end kept its value last time: +1 a, -1 b
  double width = b - a;
  for (int it = 0; it < 64 && b - a > tol; ++it) {
    double t = a + (b - a) * (ga / (ga - gb));
    // Bisect when the bracket did not halve in two steps (regula falsi stalling).
    if ((it % 2 == 1 && b - a > 0.5 * width) || !(t > a && t < b)) t = 0.5 * (a + b);
    if (it % 2 == 1) width = b - a;
    const double gt = g(t);
    if (gt == 0) return t;
    if (gt > 0) {
      a = t;
      ga = gt;
      if (stale == -1) gb *= 0.5;
      stale = -1;
    } else {
      b = t;
      gb = gt;
      if (stale == 1) ga *= 0.5;
      stale = 1;
    }
  }
  return 0.5 * (a + b);
}

/// The first hit of the central ray `d` of a Full part, to within `tol`. The proof of the part
/// brackets it: no ray of the part meets the surface in [t_s, t_near), f has the sign s.sign on
/// the slice at t_s and the opposite one on the slice at t_far, and is continuous in between;
/// so the central ray has a root in every bracket kept, and none before t_near. Only the shading
/// point depends on it.
double full_root(RenderContext& ctx, const Vec3& d, const BeamSearch& s, double tol) {
  const Vec3& eye = ctx.setup.frame.eye;
  // > 0 on the near side
  auto g = [&](double t) { return ctx.se.eval_point(eye + t * d) * s.sign; };
  double a = s.t_near;
  double ga = g(a);
  const double gb = g(s.t_far);
  if (!(ga > 0)) {
    if (ga == 0) return a;
    a = s.t_s;  // rounding at t_near: the slice at t_s has the proved sign
    ga = g(a);
  }
  if (!(ga > 0) || !(gb < 0)) return 0.5 * (s.t_near + s.t_far);  // no usable point signs
  return first_crossing(g, a, s.t_far, ga, gb, tol);
}

/// One pixel's subdivision: the sums over its leaves and the shadow searches they share.
class IaaPixel {
 public:
  IaaPixel(RenderContext& ctx, PixelTrace* tr)
      : ctx_(ctx), su_(ctx.setup), st_(ctx.setup.settings), tr_(tr) {}

  PixelResult run(const PixelJob& job) {
    beam(PixelRect{double(job.x), double(job.y), double(job.x + 1), double(job.y + 1)}, 0,
         job.range, job.full, last_beam(tr_));
    PixelResult r;
    r.color = to_rgb(color_);
    r.leaves = leaves_;
    r.coverage = static_cast<float>(coverage_);
    r.certificate = any_full_      ? PixelCertificate::kCovered
                    : any_partial_ ? PixelCertificate::kUncertain
                                   : PixelCertificate::kEmpty;
    return r;
  }

 private:
  /// Searches the beam `rect`, shades it or splits it into four, and records it when tracing.
  void beam(const PixelRect& rect, int level, Interval range, const BeamSearch* parent_full,
            int parent) {
    BeamTrace bt;
    BeamTrace* t = tr_ ? &bt : nullptr;
    const std::uint64_t e0 = ctx_.evals;
    // At the last level a proof of full coverage only decides the pixel's certificate (and how
    // the part's shading point is found): once another part of the pixel is certified covered
    // it is not tried.
    const bool last = level >= st_.max_level;
    BeamSearch s = parent_full && last
                       ? inherit_full(ctx_, rect, *parent_full, t)
                       : eval_ray_set(ctx_, rect, range, parent_full, t, !(last && any_full_));
    const BeamDecision decision = decide(rect, last, range, s, t);
    const int index =
        tr_ ? record_beam(*tr_, std::move(bt), rect, level, parent, decision, ctx_.evals - e0) : -1;
    if (decision != BeamDecision::kSplit) return;
    const Interval sub = child_range(s, range);
    const BeamSearch* pf = s.result == BeamResult::kFull ? &s : nullptr;
    const double um = 0.5 * (rect.u0 + rect.u1), vm = 0.5 * (rect.v0 + rect.v1);
    beam({rect.u0, rect.v0, um, vm}, level + 1, sub, pf, index);
    beam({um, rect.v0, rect.u1, vm}, level + 1, sub, pf, index);
    beam({rect.u0, vm, um, rect.v1}, level + 1, sub, pf, index);
    beam({um, vm, rect.u1, rect.v1}, level + 1, sub, pf, index);
  }

  /// What becomes of a searched beam that is not split: background, or a shaded leaf added to
  /// the sums. A Full beam above the last level is a leaf when its estimator is narrow enough.
  BeamDecision decide(const PixelRect& rect, bool last, Interval range, BeamSearch& s,
                      BeamTrace* t) {
    if (s.result == BeamResult::kMiss) {
      color_ = color_ + rect.area() * background(ctx_);
      return BeamDecision::kBackground;
    }
    BeamDecision decision = BeamDecision::kShadeLeaf;
    if (!last) {
      if (s.result != BeamResult::kFull || !estimator_within(rect, s, t))
        return BeamDecision::kSplit;
      decision = BeamDecision::kShadeFull;
    }
    add_leaf(rect, s, range, t);
    return decision;
  }

  /// True when the estimator of the Full beam `s` is within the threshold. The estimator over
  /// the whole hit box first (one gradient evaluation); when it is too wide, a shorter hit
  /// segment (a few slice evaluations) and the estimator over its pieces that may hold the
  /// surface, which is much cheaper than splitting the beam.
  bool estimator_within(const PixelRect& rect, BeamSearch& s, BeamTrace* t) {
    Interval est = beam_estimator(ctx_, s, 1);
    if (est.width() > st_.estimator_threshold) {
      tighten_far(
          ctx_, &s,
          st_.depth_tolerance * su_.frame.scale * std::max(rect.width(), rect.height()) * s.t_near);
      est = beam_estimator(ctx_, s, kEstimatorPieces, st_.estimator_threshold);
    }
    if (t) t->estimator = est;
    return est.width() <= st_.estimator_threshold;
  }

  /// Shades the leaf `s` and adds it to the pixel's sums.
  void add_leaf(const PixelRect& rect, const BeamSearch& s, Interval range, BeamTrace* t) {
    double w = 1.0;
    // Two statements: shade_beam() sets w, and the order in which a call's arguments are
    // evaluated is unspecified.
    const Vec3 shaded = shade_beam(rect, s, range, t, &w);
    const Vec3 c = w == 1.0 ? shaded : w * shaded + (1.0 - w) * background(ctx_);
    if (t) {
      t->color = c;
      t->weight = w;
    }
    const double area = rect.area();
    color_ = color_ + area * c;
    coverage_ += area * w;
    ++leaves_;
    if (s.result == BeamResult::kFull) {
      any_full_ = true;
    } else {
      any_partial_ = true;
    }
  }

  /// Shades a beam part: at the exact hit of its central ray when there is one, else at the
  /// centre of the hit box with the mid-point normal of the interval gradient. Sets `weight` to
  /// the share of the part shown as surface.
  Vec3 shade_beam(const PixelRect& rect, const BeamSearch& s, Interval range, BeamTrace* t,
                  double* weight) {
    const double uc = 0.5 * (rect.u0 + rect.u1), vc = 0.5 * (rect.v0 + rect.v1);
    const Vec3 d = su_.frame.dir(uc, vc);
    const RayHit h = central_hit(rect, s, range, d, weight);
    Vec3 p, g;
    if (h.hit) {
      p = su_.frame.eye + h.t.mid() * d;
      g = hit_gradient(ctx_, p, uc, vc, h.t);
    } else {
      p = {s.hit_box.x.mid(), s.hit_box.y.mid(), s.hit_box.z.mid()};
      g = interval_mid_gradient(ctx_, s.hit_box);
    }
    Vec3 n;
    // Leaves of this pixel within a pixel's footprint of each other share shadow searches.
    shadow_cache_.radius = su_.frame.scale * s.t_near;
    const Vec3 c = shade(ctx_, p, g, d, &n, &shadow_cache_);
    if (t) {
      t->center_ray_hit = h.hit;
      t->point = p;
      t->normal = n;
      t->color = c;
    }
    return c;
  }

  /// The hit of the central ray `d` of a part, which only chooses its shading point: the
  /// certificate and the coverage do not depend on it. Full: the central ray certainly hits in
  /// [t_near, t_far]. Partial: its hit is looked for only a few beam widths behind t_near (a hit
  /// further back would be hidden by whatever the beam touches first), then behind that. A
  /// Partial part whose central ray finds no surface is most likely a sliver of a silhouette or
  /// of a thin feature: it is shown with weight kPartialMissWeight over the background, never
  /// dropped (its coverage stays > 0).
  RayHit central_hit(const PixelRect& rect, const BeamSearch& s, Interval range, const Vec3& d,
                     double* weight) {
    const double uc = 0.5 * (rect.u0 + rect.u1), vc = 0.5 * (rect.v0 + rect.v1);
    const double side = std::max(rect.width(), rect.height());
    const double reach = kPartialShadeReach * su_.frame.scale * side * s.t_near;
    const Interval sr(
        s.t_near, s.result == BeamResult::kFull ? s.t_far : std::min(range.hi(), s.t_near + reach));
    // The shading point needs a fraction of the part's footprint, not the baselines' 1e-9: near
    // grazing rays a fine tolerance costs many evaluations for no visible difference.
    const double foot = su_.frame.scale * side * sr.lo();
    const double shade_tol = std::max(su_.ray_tol, kShadeTolerance * foot);
    *weight = 1.0;
    RayHit h;
    if (s.result == BeamResult::kFull) {
      h.hit = true;
      h.t = Interval(full_root(ctx_, d, s, shade_tol));
      return h;
    }
    h = search_ray(ctx_, su_.frame.eye, su_.frame.dir_box(uc, vc), sr, shade_tol,
                   su_.frame.scale * sr.hi() * 4, false);
    if (h.hit) return h;
    if (sr.hi() < range.hi()) {
      h = search_ray(ctx_, su_.frame.eye, su_.frame.dir_box(uc, vc), Interval(sr.hi(), range.hi()),
                     shade_tol, su_.frame.scale * range.hi() * 4, false);
    }
    if (!h.hit) *weight = kPartialMissWeight;
    return h;
  }

  RenderContext& ctx_;
  const RenderSetup& su_;
  const RenderSettings& st_;
  PixelTrace* tr_;
  ShadowCache shadow_cache_;  ///< shadow results of this pixel's leaves (empty at the start)
  Vec3 color_;                ///< sum of the leaves' colours times their areas
  double coverage_ = 0;       ///< sum of the leaves' weights times their areas
  std::uint32_t leaves_ = 0;
  bool any_full_ = false, any_partial_ = false;
};

}  // namespace

PixelResult iaa_pixel(RenderContext& ctx, const PixelJob& job, PixelTrace* trace) {
  return IaaPixel(ctx, trace).run(job);
}

}  // namespace iaa
