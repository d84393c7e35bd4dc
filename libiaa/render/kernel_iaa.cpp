// The IAA kernel: the pixel's beam split into four sub-beams until each is a Miss (background),
// a Full beam whose estimator is within the threshold, or at max_level; each such leaf is shaded
// once at a point of its surface and weighted by its area (docs/render.md, "How").
#include <algorithm>
#include <cmath>
#include <utility>

#include "render/kernel.h"
#include "render/ray_search.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// How far behind t_near (in beam widths) a Partial beam's central ray is searched for shading.
constexpr double kPartialShadeReach = 8.0;
/// The first piece of the search behind a Partial part's near reach, in reaches (measured against
/// bisection of that range and first pieces of 1/4, 1 and 2 reaches: at 300x300, that search's
/// evaluations blobby 0.64x, gyroid 0.76x, twist 0.81x; the same hits but one in 2000). A march
/// of the near search itself (first pieces of 1/32 to 1/4 of the reach) saved the twist's
/// evaluations (0.69x at 1/8) but cost blobby's (1.7x) and the gyroid's (1.1x): not kept.
constexpr double kFarMarch = 0.5;
/// Depth tolerance of the central ray of an IAA part, in footprints of the part (its lateral
/// width at the depth): where it is shaded, not whether it is covered.
constexpr double kShadeTolerance = 1.0 / 64;
/// Point rays per side of a Partial part (at the centres of its kCoverageRays^2 quarters, besides
/// its central ray) whose hits estimate the share of the part shown as surface.
constexpr int kCoverageRays = 2;
/// Least share of a Partial part shown as surface, when none of its rays finds the surface (one
/// ray of a 4x4 grid over the part): a part that may hold surface is never dropped.
constexpr double kPartialMinWeight = 1.0 / 16;
/// Least coverage of a pixel with a part that may hold surface, in last-level parts: a quarter
/// of one (1/64 of the pixel at max_level 2), the least any such pixel showed before Partial
/// parts were weighted by their rays, so that it stays visible.
constexpr double kPixelMinParts = 0.25;
/// Point-value steps over [t_near, t_far] in which the first crossing of a Full part's central
/// ray is looked for before regula falsi narrows it (full_root). The steps start at one
/// footprint of the part and double up to (t_far - t_near) / kRootMarch, or kRootStepMost
/// footprints when that is less; at most kRootMarchMost of them.
constexpr int kRootMarch = 8;
constexpr double kRootStepMost = 4;
constexpr int kRootMarchMost = 64;
/// March steps evaluated in one pass of the batched point evaluator (first_crossing): most
/// marches take 3 to 5 steps (the twist's and chubs' at 500x500).
constexpr int kMarchAhead = 4;
/// A Full part's bracket longer than this many footprints is searched with intervals instead
/// (full_root). Measured against 4, 16, 128, 256 and 1024 on the Klein bottle, the twist and
/// chubs at 250x250: 4 to 64 gave the same images, 64 the fewest evaluations (docs/render.md).
constexpr double kRootSearchFrom = 64;
/// Most point values along one coverage ray of a Partial part (steps of one footprint).
constexpr int kCoverageMarch = 64;
/// Samples per side of a Full part (at the centres of a grid over it) searched for shadows when
/// the cone test cannot tell whether a shadow edge crosses it (shade, ShadowPart): 4 at level
/// 0, halved per level, at least 2.
constexpr int kShadowSamples = 4;
/// Most depth pieces of a Full beam's hit segment over which the estimator is taken (halves first,
/// then halves of those that may hold a hit while the hull is too wide: beam_estimator).
constexpr int kEstimatorPieces = 8;

/// The first crossing of g (> 0 at a, < 0 at b) in [a, b]: a march of point values from the
/// front to the first step whose far end has the far sign, then regula falsi (Illinois) to
/// within `tol`. The steps are `first` wide at the front, then double, up to (b - a) /
/// kRootMarch or kRootStepMost x `first`: the first crossing is most often near a (the beam's
/// t_near), where a thin sliver in front of a farther surface (a lobe passing in front of
/// another) would hide in one long step; and a Full part inside a Full parent inherits the
/// parent's long [t_near, t_far], where steps of 1/8 of it skipped the thin fold of the Klein
/// bottle in front of its other sheet. A feature thinner than a step can still hide a crossing:
/// shading only.
template <class G, class GMany>
double first_crossing(const G& g, const GMany& g_many, double a, double b, double ga, double gb,
                      double tol, double first) {
  const double end = b;
  const double most = std::min((b - a) / kRootMarch, kRootStepMost * first);
  double step = std::min(first, most);
  double t = a;
  // The march's depths follow from t and step alone, so its values are taken up to kMarchAhead
  // at a time, in one call of g_many: the depths the march visits are those it would visit one
  // at a time (the same recurrence), and their values are the same; those past the first
  // crossing are computed for nothing.
  double ahead[kMarchAhead];
  int have = 0, used = 0;
  for (int k = 0; k < kRootMarchMost; ++k) {
    t += step;
    step = std::min(2 * step, most);
    if (!(t > a && t < end)) break;
    if (used == have) {
      double ts[kMarchAhead];
      ts[0] = t;
      have = 1;
      for (double tt = t, st = step; have < kMarchAhead && k + have < kRootMarchMost; ++have) {
        tt += st;
        st = std::min(2 * st, most);
        if (!(tt > ts[have - 1] && tt < end)) break;  // the march stops there (or before)
        ts[have] = tt;
      }
      if (have == 1) {
        ahead[0] = g(t);
      } else {
        g_many(ts, have, ahead);
      }
      used = 0;
    }
    const double gt = ahead[used++];
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
///
/// A bracket longer than kRootSearchFrom footprints (`first`) is searched with intervals along
/// the point ray d, front to back, as the baselines search their rays, so that no crossing pair
/// is stepped over. Such brackets come from a Full part inside a Full parent, which inherits the
/// parent's [t_near, t_far] without a search: there the march's steps of kRootStepMost
/// footprints stepped over the Klein bottle's thin fold in front of its other sheet (less than
/// half a footprint deep), and its kRootMarchMost steps could end before the first crossing,
/// leaving regula falsi to settle on any crossing of the rest (the far side of the twist's
/// other blade, behind the thin blade in front).
double full_root(RenderContext& ctx, const Vec3& d, const BeamSearch& s, double tol, double first) {
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
  if (s.t_far - a > kRootSearchFrom * first) {
    const IBox dir(Interval(d.x), Interval(d.y), Interval(d.z));
    // From t_near: no ray of the part meets the surface before it (a may be t_s).
    const RayHit h = search_shading_ray(ctx, eye, dir, Interval(s.t_near, s.t_far), tol,
                                        ctx.setup.frame.scale * s.t_far * 4);
    if (h.hit) return h.t.mid();
  }
  // The march's steps four at a time by the point batch (the whole tape's values: those of `se`'s
  // specialized tapes but where a dropped branch overflows; shading only, as the coverage rays').
  const auto g_many = [&](const double* ts, int n, double* out) {
    if (!ctx.batch_point4) {
      for (int j = 0; j < n; ++j) out[j] = g(ts[j]);
      return;
    }
    Vec3 p[kMarchAhead];
    for (int j = 0; j < n; ++j) p[j] = eye + ts[j] * d;
    ctx.batch_point4->eval(p, n, out);
    for (int j = 0; j < n; ++j) out[j] *= s.sign;
  };
  return first_crossing(g, g_many, a, s.t_far, ga, gb, tol, first);
}

/// The shadow samples of a Full part: the hits of the central rays of a grid of its sub-parts,
/// found as its shading point is (full_root).
class FullPartShadow final : public ShadowPart {
 public:
  FullPartShadow(RenderContext& ctx, const PixelRect& rect, const BeamSearch& s, int n, double tol,
                 double first)
      : ctx_(ctx), rect_(rect), s_(s), tol_(tol), first_(first) {
    patch = s.hit_box;
    side = n;
  }

  int samples(int side_, Vec3* points) override {
    const CameraFrame& fr = ctx_.setup.frame;
    int n = 0;
    for (int j = 0; j < side_; ++j) {
      for (int i = 0; i < side_; ++i) {
        const double u = rect_.u0 + (i + 0.5) / side_ * rect_.width();
        const double v = rect_.v0 + (j + 0.5) / side_ * rect_.height();
        const Vec3 d = fr.dir(u, v);
        points[n++] = fr.eye + full_root(ctx_, d, s_, tol_, first_) * d;
      }
    }
    return n;
  }

 private:
  RenderContext& ctx_;
  const PixelRect& rect_;
  const BeamSearch& s_;
  double tol_, first_;
};

/// One pixel's subdivision: the sums over its leaves and the shadow searches they share.
class IaaPixel {
 public:
  IaaPixel(RenderContext& ctx, PixelTrace* tr)
      : ctx_(ctx), su_(ctx.setup), st_(ctx.setup.settings), tr_(tr) {}

  PixelResult run(const PixelJob& job) {
    if (tr_) first_beam_ = tr_->beams.size();
    beam(PixelRect{double(job.x), double(job.y), double(job.x + 1), double(job.y + 1)}, 0,
         job.range, job.full, last_beam(tr_), job.first);
    raise_to_min_coverage();
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
  /// A pixel with a part that may hold surface shows at least kPixelMinParts last-level parts
  /// of coverage: when its Partial parts' rays found too little surface, their weights are
  /// scaled up together (no Full part then: one covers more than the minimum).
  void raise_to_min_coverage() {
    const double least = kPixelMinParts / double(1u << (2 * st_.max_level));
    if (!any_partial_ || any_full_ || !(coverage_ < least) || !(coverage_ > 0)) return;
    const double k = least / coverage_;
    const Vec3 bg = background(ctx_);
    // colour = sum of area (w shaded + (1 - w) bg) over the parts + the background parts'
    // = bg + sum of area w (shaded - bg) = bg + coverage (mean surface colour - bg).
    color_ = bg + k * (color_ - bg);
    coverage_ = least;
    if (!tr_) return;
    tr_->raised_coverage = k;
    for (std::size_t i = first_beam_; i < tr_->beams.size(); ++i) {
      BeamTrace& b = tr_->beams[i];
      if (b.decision != BeamDecision::kShadeLeaf || b.result == BeamResult::kFull) continue;
      const Vec3 part = b.color - bg;  // w (shaded - bg)
      b.color = bg + k * part;
      b.weight *= k;
    }
  }

  /// Searches the beam `rect`, shades it or splits it into four, and records it when tracing.
  void beam(const PixelRect& rect, int level, Interval range, const BeamSearch* parent_full,
            int parent, FirstPiece* first = nullptr) {
    BeamTrace bt;
    BeamTrace* t = tr_ ? &bt : nullptr;
    const std::uint64_t e0 = ctx_.evals;
    // At the last level a proof of full coverage only decides the pixel's certificate (and how
    // the part's shading point is found): once another part of the pixel is certified covered
    // it is not tried.
    const bool last = level >= st_.max_level;
    BeamSearch s;
    BeamDecision decision = BeamDecision::kSplit;
    if (parent_full && !last && !st_.shadows && inherited_leaf(rect, *parent_full, t, &s)) {
      decision = BeamDecision::kShadeFull;
      add_leaf(rect, s, range, t);
    } else {
      if (t) *t = BeamTrace{};  // what inherited_leaf() recorded is replaced by the search
      s = parent_full && last
              ? inherit_full(ctx_, rect, *parent_full, t)
              : eval_ray_set(ctx_, rect, range, parent_full, t, !(last && any_full_), first);
      decision = decide(rect, last, range, s, t);
    }
    // The depth search made ahead for this beam (with its siblings) counts as its own.
    const std::uint64_t evals = ctx_.evals - e0 + (first ? first->evals : 0);
    const int index =
        tr_ ? record_beam(*tr_, std::move(bt), rect, level, parent, decision, evals) : -1;
    if (decision != BeamDecision::kSplit) return;
    const Interval sub = child_range(s, range);
    const BeamSearch* pf = s.result == BeamResult::kFull ? &s : nullptr;
    const double um = 0.5 * (rect.u0 + rect.u1), vm = 0.5 * (rect.v0 + rect.v1);
    const PixelRect kids[4] = {{rect.u0, rect.v0, um, vm},
                               {um, rect.v0, rect.u1, vm},
                               {rect.u0, vm, um, rect.v1},
                               {um, vm, rect.u1, rect.v1}};
    // The children of a Partial beam all search `sub` from the front: side by side, four boxes
    // per pass of the batched evaluators (where the tape has them). A Full parent's children
    // mostly take its proof without a search of their own (inherited_leaf, inherit_full).
    FirstPiece firsts[4];
    const bool together = !pf && ctx_.batched;
    if (together) first_pieces(ctx_, kids, 4, sub, tr_ != nullptr, firsts);
    for (int k = 0; k < 4; ++k)
      beam(kids[k], level + 1, sub, pf, index, together ? &firsts[k] : nullptr);
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

  /// A beam inside a Full beam `parent` is Full over the parent's [t_near, t_far] without any
  /// search (inherit_full()): when the estimator over that hit box (one gradient evaluation) is
  /// already within the threshold, the beam is a leaf as it is, and its depth search, which
  /// would only move t_near closer to the surface, is not needed. Sets `s` and returns true then;
  /// else the caller searches the beam as usual (the one evaluation is the price of trying).
  /// Not with shadows: a Full part's hit box is also the patch its shadow cone is cast from
  /// (FullPartShadow), and a longer one leaves more shadow edges to sampling (the twist, the
  /// scene with shadows: the same evaluations, RMSE 0.00261 -> 0.00267).
  bool inherited_leaf(const PixelRect& rect, const BeamSearch& parent, BeamTrace* t,
                      BeamSearch* s) {
    *s = inherit_full(ctx_, rect, parent, t);
    const Interval est = beam_estimator(ctx_, *s, 1);
    if (t) t->estimator = est;
    return est.width() <= st_.estimator_threshold;
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
    // The share of a Partial part shown as the surface behind it (coverage rays that missed
    // near t_near and met the surface further back), at the mean colour of their hits. Surface
    // then shows on `wt` of the part: one division, so that all rays hitting is exactly 1 under
    // the upward rounding (w + the behind share could round to 1 + 2^-52).
    const double wt = behind_hits_ > 0 ? double(coverage_hits_ + behind_hits_) / coverage_rays_ : w;
    Vec3 c = w == 1.0 ? shaded : w * shaded + (1.0 - wt) * background(ctx_);
    if (behind_hits_ > 0) c = c + (1.0 / coverage_rays_) * behind_color_;
    if (t) {
      t->color = c;
      t->weight = wt;
    }
    const double area = rect.area();
    color_ = color_ + area * c;
    coverage_ += area * wt;
    ++leaves_;
    if (s.result == BeamResult::kFull) {
      any_full_ = true;
    } else {
      any_partial_ = true;
    }
  }

  /// Shades a beam part: at the exact hit of its central ray (or of its first coverage ray that
  /// finds the surface, when the central ray does not) when there is one, else at the centre of
  /// the hit box with the mid-point normal of the interval gradient. Sets `weight` to the share
  /// of the part shown as surface.
  Vec3 shade_beam(const PixelRect& rect, const BeamSearch& s, Interval range, BeamTrace* t,
                  double* weight) {
    PartHit ph;
    ph.u = 0.5 * (rect.u0 + rect.u1);
    ph.v = 0.5 * (rect.v0 + rect.v1);
    ph.d = su_.frame.dir(ph.u, ph.v);
    part_hit(rect, s, range, &ph, weight);
    Vec3 p, g;
    if (ph.h.hit) {
      p = su_.frame.eye + ph.h.t.mid() * ph.d;
      g = hit_gradient(ctx_, p, ph.u, ph.v, ph.h.t);
    } else {
      p = {s.hit_box.x.mid(), s.hit_box.y.mid(), s.hit_box.z.mid()};
      g = interval_mid_gradient(ctx_, s.hit_box);
    }
    Vec3 n;
    // Leaves of this pixel within a pixel's footprint of each other share shadow searches.
    shadow_cache_.radius = su_.frame.scale * s.t_near;
    Vec3 c;
    if (s.result == BeamResult::kFull && st_.shadows) {
      // The part is rect.width() pixels wide (1 at level 0, halved per level).
      const int side = std::max(2, static_cast<int>(kShadowSamples * rect.width() + 0.5));
      FullPartShadow part(ctx_, rect, s, side, ph.tol, ph.foot);
      c = shade(ctx_, p, g, ph.d, &n, &shadow_cache_, &part);
    } else {
      c = shade(ctx_, p, g, ph.d, &n, &shadow_cache_);
    }
    shade_behind(ph);
    if (t) {
      t->center_ray_hit = ph.central;
      t->coverage_ray_hit = ph.h.hit && !ph.central;
      t->coverage_rays = coverage_rays_;
      t->coverage_hits = coverage_hits_;
      t->behind_hits = behind_hits_;
      t->point = p;
      t->normal = n;
      t->color = c;
    }
    return c;
  }

  /// The ray that gives a part its shading point: through (u, v) in direction d, its hit h.
  struct PartHit {
    double u = 0, v = 0;
    Vec3 d;
    RayHit h;
    bool central = false;  ///< the central ray found the surface
    double tol = 0;        ///< depth tolerance of its hit
    double foot = 0;       ///< its footprint at its depth
  };

  /// The hit of the central ray of a part (ph holds it), which chooses its shading point, and
  /// the share of the part shown as surface (`weight`); the certificate does not depend on them.
  /// Full: the central ray certainly hits in [t_near, t_far], weight 1. Partial: its hit is
  /// looked for only a few beam widths behind t_near (a hit further back would be hidden by
  /// whatever the beam touches first), then behind that; the weight is the share of the part's
  /// rays that find the surface, the central ray and kCoverageRays^2 point-marched ones
  /// (coverage_ray), never below kPartialMinWeight: a part that may hold surface is never
  /// dropped. When only a coverage ray finds the surface, the part is shaded where it does.
  void part_hit(const PixelRect& rect, const BeamSearch& s, Interval range, PartHit* ph,
                double* weight) {
    const double side = std::max(rect.width(), rect.height());
    const double reach = kPartialShadeReach * su_.frame.scale * side * s.t_near;
    const Interval sr(
        s.t_near, s.result == BeamResult::kFull ? s.t_far : std::min(range.hi(), s.t_near + reach));
    // The shading point needs a fraction of the part's footprint, not the baselines' 1e-9: near
    // grazing rays a fine tolerance costs many evaluations for no visible difference.
    const double foot = su_.frame.scale * side * sr.lo();
    const double shade_tol = std::max(su_.ray_tol, kShadeTolerance * foot);
    ph->tol = shade_tol;
    ph->foot = foot;
    *weight = 1.0;
    coverage_rays_ = coverage_hits_ = behind_hits_ = n_missed_ = 0;
    behind_color_ = Vec3{};
    RayHit& h = ph->h;
    if (s.result == BeamResult::kFull) {
      h.hit = true;
      h.t = Interval(full_root(ctx_, ph->d, s, shade_tol, foot));
      ph->central = true;
      return;
    }
    const IBox dir = su_.frame.dir_box(ph->u, ph->v);
    h = search_shading_ray(ctx_, su_.frame.eye, dir, sr, shade_tol, su_.frame.scale * sr.hi() * 4);
    if (!h.hit && sr.hi() < range.hi()) {
      // Behind the near reach the range runs to the back of the bounds: marched from its front
      // in pieces from half the reach, doubling, as a shadow ray's (kFarMarch).
      h = search_shading_ray(ctx_, su_.frame.eye, dir, Interval(sr.hi(), range.hi()), shade_tol,
                             su_.frame.scale * range.hi() * 4, kFarMarch * (sr.hi() - sr.lo()));
    }
    ph->central = h.hit;
    // The coverage rays, at the centres of the part's quarters (kCoverageRays 2), marched over
    // the near reach, or to as far behind the central ray's hit when that lies further back.
    coverage_rays_ = 1 + kCoverageRays * kCoverageRays;
    coverage_hits_ = h.hit ? 1 : 0;
    const double end = h.hit ? std::max(sr.hi(), h.t.hi() + (sr.hi() - sr.lo())) : sr.hi();
    const Interval march(s.t_near, std::min(range.hi(), end));
    constexpr int kRays = kCoverageRays * kCoverageRays;
    Missed ray[kRays];
    Vec3 dirs[kRays];
    for (int j = 0; j < kCoverageRays; ++j) {
      for (int i = 0; i < kCoverageRays; ++i) {
        Missed& r = ray[j * kCoverageRays + i];
        r.u = rect.u0 + (i + 0.5) / kCoverageRays * rect.width();
        r.v = rect.v0 + (j + 0.5) / kCoverageRays * rect.height();
        r.d = dirs[j * kCoverageRays + i] = su_.frame.dir(r.u, r.v);
      }
    }
    Crossing x[kRays];
    bool found[kRays];
    coverage_rays(dirs, kRays, march, foot, x, found);
    for (int k = 0; k < kRays; ++k) {
      const Missed& r = ray[k];
      if (!found[k]) {
        missed_[n_missed_++] = r;
        continue;
      }
      ++coverage_hits_;
      if (h.hit) continue;
      // The first coverage ray that finds the surface gives the shading point.
      h.hit = true;
      h.t = Interval(crossing_depth(r.d, x[k], shade_tol));
      ph->u = r.u;
      ph->v = r.v;
      ph->d = r.d;
    }
    *weight = std::max(kPartialMinWeight, double(coverage_hits_) / coverage_rays_);
    // A coverage ray that passed beside the surface the part's rays found may meet another
    // surface behind it (the edge of a blade in front of another): shade_behind() looks there.
    // Only where some ray of the part found surface (a part that only the intervals'
    // overestimation keeps, beside a silhouette, is left as it is) and the depth range goes on
    // behind the march.
    if (coverage_hits_ == 0 || !(march.hi() < range.hi())) {
      n_missed_ = 0;
      return;
    }
    behind_ = Interval(march.hi(), range.hi());
  }

  /// The coverage rays of the part `ph` that missed near t_near (part_hit), marched on behind:
  /// each that meets surface there adds its colour at its hit to behind_color_ (with shadow rays
  /// through the pixel's cache, at the cache radius of its depth) and counts in behind_hits_.
  /// After the part's own shading point, which comes first in the cache.
  void shade_behind(const PartHit& ph) {
    const double radius = shadow_cache_.radius;
    Vec3 dirs[kCoverageRays * kCoverageRays];
    Crossing xs[kCoverageRays * kCoverageRays];
    bool found[kCoverageRays * kCoverageRays];
    for (int k = 0; k < n_missed_; ++k) dirs[k] = missed_[k].d;
    coverage_rays(dirs, n_missed_, behind_, ph.foot, xs, found);
    for (int k = 0; k < n_missed_; ++k) {
      const Missed& m = missed_[k];
      if (!found[k]) continue;
      const Interval tb(crossing_depth(m.d, xs[k], ph.tol));
      const Vec3 p = su_.frame.eye + tb.mid() * m.d;
      const Vec3 g = hit_gradient(ctx_, p, m.u, m.v, tb);
      shadow_cache_.radius = su_.frame.scale * tb.mid();
      behind_color_ = behind_color_ + shade(ctx_, p, g, m.d, nullptr, &shadow_cache_);
      ++behind_hits_;
    }
    shadow_cache_.radius = radius;
  }

  /// A bracket [a, b] of point values of opposite signs (fa == 0: a root at a).
  struct Crossing {
    double a = 0, b = 0, fa = 0, fb = 0;
  };

  /// For each point ray d[k] (k < n <= kCoverageRays^2) of a Partial part: found[k] when it meets
  /// the surface in `range` (the part's depths from t_near), inside the bounds, as far as a march
  /// of point values in steps of `step` can tell (one footprint of the part; at most
  /// kCoverageMarch steps, wider when the range is longer); x[k] gets the first bracket. No ray of
  /// the part meets the surface before t_near, so they all start on the same side. A crossing pair
  /// thinner than a step can hide, which only lowers the part's weight, never below the minimum.
  /// The rays march side by side, their points evaluated in one pass of the batched point
  /// evaluator where the context has it (the values one ray at a time gives).
  void coverage_rays(const Vec3* d, int n, Interval range, double step, Crossing* x, bool* found) {
    constexpr int kMost = kCoverageRays * kCoverageRays;
    struct March {
      double a = 0, b = 0, ta = 0, fa = 0;
      int steps = 0, k = 0;  // steps of the march; the next one (0: the start, at a)
      bool active = false;
    };
    const Vec3& eye = su_.frame.eye;
    const Box3& bx = ctx_.bounds();
    March m[kMost];
    for (int r = 0; r < n; ++r) {
      found[r] = false;
      double a = range.lo(), b = range.hi();
      bool inside = true;
      for (int i = 0; i < 3 && inside; ++i) {  // the ray's depths inside the bounds
        if (d[r][i] == 0) {
          inside = !(eye[i] < bx.lo[i] || eye[i] > bx.hi[i]);
          continue;
        }
        double t0 = (bx.lo[i] - eye[i]) / d[r][i], t1 = (bx.hi[i] - eye[i]) / d[r][i];
        if (t0 > t1) std::swap(t0, t1);
        a = std::max(a, t0);
        b = std::min(b, t1);
      }
      if (!inside || !(a < b) || !(step > 0)) continue;
      // Steps of `step`, or wider so that there are at most kCoverageMarch of them.
      m[r].steps = static_cast<int>(
          std::clamp(std::ceil((b - a) / step), 1.0, static_cast<double>(kCoverageMarch)));
      m[r].a = a;
      m[r].b = b;
      m[r].active = true;
    }
    // Each pass gives each marching ray an equal share of the batch's lanes, its next steps in
    // order (one step each without a batch); a ray's steps after its crossing are evaluated for
    // nothing, but a pass costs about what one point costs, and long marches take fewer passes.
    constexpr int kLanes = decltype(ctx_.batch_point)::value_type::kLanes;
    for (;;) {
      int active = 0;
      for (int r = 0; r < n; ++r) active += m[r].active ? 1 : 0;
      if (active == 0) return;
      const int share = ctx_.batch_point ? kLanes / active : 1;
      int ray[kLanes], nl = 0;
      Vec3 p[kLanes];
      double t[kLanes], f[kLanes];
      for (int r = 0; r < n; ++r) {
        const March& q = m[r];
        if (!q.active) continue;
        for (int k = q.k; k <= q.steps && k < q.k + share; ++k) {
          t[nl] = k == 0 ? q.a : (k == q.steps ? q.b : q.a + (q.b - q.a) * k / q.steps);
          p[nl] = eye + t[nl] * d[r];
          ray[nl++] = r;
        }
      }
      if (nl >= 2 && ctx_.batch_point) {
        ctx_.batch_point->eval(p, nl, f);
      } else {
        for (int l = 0; l < nl; ++l) f[l] = ctx_.se.eval_point(p[l]);
      }
      for (int l = 0; l < nl; ++l) {
        March& q = m[ray[l]];
        if (!q.active) continue;  // crossed at an earlier step of this pass
        const double tb = t[l], fb = f[l];
        if (q.k == 0) {
          if (fb == 0) {
            x[ray[l]] = {tb, tb, 0, 0};
            found[ray[l]] = true;
            q.active = false;
          }
        } else if (std::isfinite(q.fa) && std::isfinite(fb) &&
                   (fb == 0 || (q.fa < 0) != (fb < 0))) {
          x[ray[l]] = {q.ta, tb, q.fa, fb};
          found[ray[l]] = true;
          q.active = false;
        }
        q.ta = tb;
        q.fa = fb;
        if (++q.k > q.steps) q.active = false;
      }
    }
  }

  /// The depth of the crossing `x` of the point ray `d`, to within `tol` (first_crossing).
  double crossing_depth(const Vec3& d, const Crossing& x, double tol) {
    if (x.fa == 0) return x.a;
    if (x.fb == 0) return x.b;
    const double sg = x.fa > 0 ? 1.0 : -1.0;  // > 0 on the near side
    auto g = [&](double t) { return sg * ctx_.se.eval_point(su_.frame.eye + t * d); };
    const auto g_many = [&](const double* ts, int n, double* out) {
      for (int j = 0; j < n; ++j) out[j] = g(ts[j]);
    };
    return first_crossing(g, g_many, x.a, x.b, sg * x.fa, sg * x.fb, tol, x.b - x.a);
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
  int coverage_rays_ = 0, coverage_hits_ = 0;  ///< of the part being shaded
  /// A coverage ray of a Partial part that did not find the surface near t_near.
  struct Missed {
    double u = 0, v = 0;  ///< pixel coordinates of the ray
    Vec3 d;               ///< its direction
  };
  Missed missed_[kCoverageRays * kCoverageRays];  ///< of the part being shaded, to march on
  int n_missed_ = 0;
  Interval behind_;             ///< the depths behind the part's march, to the end of its range
  int behind_hits_ = 0;         ///< of its coverage rays that missed, those that met surface behind
  Vec3 behind_color_;           ///< the sum of the colours of their hits
  std::size_t first_beam_ = 0;  ///< this pixel's first beam in tr_ (tracing)
};

}  // namespace

PixelResult iaa_pixel(RenderContext& ctx, const PixelJob& job, PixelTrace* trace) {
  return IaaPixel(ctx, trace).run(job);
}

}  // namespace iaa
