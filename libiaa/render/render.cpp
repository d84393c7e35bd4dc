// The renderer: screen-block elimination, then one kernel per method for each pixel.
//
// Work is organised as a fixed quadtree of screen blocks aligned to the image origin (32, 16, 8,
// 4, 2 pixels, then the pixel). Every block is a beam: when EvalRaySet calls it a Miss, all its
// pixels are certified background at the cost of one search; otherwise its children search from
// its t_near (no ray of the block hits before it). The quadtree does not depend on Exec, so the
// result is the same for any thread count or tile size, and render_pixel() can walk the chain of
// blocks above one pixel and run exactly the code the full render ran.
#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "render/beam.h"
#include "scene/camera.h"
#include "render/context.h"
#include "render/ray_search.h"
#include "render/shade.h"

namespace iaa {

namespace {

/// Edge of the root screen blocks (the unit of parallel work) and of the smallest block above a
/// pixel.
constexpr int kRootBlock = 32;
constexpr int kMinBlock = 2;
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

bool may_be_partial(const Tape& tape) {
  for (const Instr& in : tape.instrs()) {
    switch (in.op) {
      case Op::kDiv:
      case Op::kPow:
      case Op::kSqrt:
      case Op::kLog:
      case Op::kTan:
        return true;
      default:
        break;
    }
  }
  return false;
}

Rgb to_rgb(const Vec3& c) {
  return {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
}

/// Depth range left for the children of a beam.
Interval child_range(const BeamSearch& s, const Interval& range) {
  return Interval(s.t_near, s.result == BeamResult::kFull ? s.t_far : range.hi());
}

/// Corner-ray results of the adaptive method, shared by the pixels of one root block.
struct AdaptiveCache {
  int gx0 = 0, gy0 = 0, n = 0;  ///< fine-grid origin and edge (in corner positions)
  std::vector<std::int8_t> done;
  std::vector<Vec3> color;
  std::vector<std::uint8_t> hit;
  AdaptiveCache(int gx, int gy, int edge) : gx0(gx), gy0(gy), n(edge) {
    done.assign(std::size_t(n) * n, 0);
    color.resize(std::size_t(n) * n);
    hit.assign(std::size_t(n) * n, 0);
  }
};

/// Shaded result of one point ray.
struct RaySample {
  Vec3 color;
  bool hit = false;
  bool certified = false;
};

class Renderer {
 public:
  explicit Renderer(RenderContext& ctx) : ctx_(ctx), su_(ctx.setup), st_(ctx.setup.settings) {}

  /// The kernel of one pixel, given the depth range left by the blocks above it.
  /// `root_range` is the range of its root block (the adaptive method's corner rays use it so
  /// that a corner ray's result does not depend on which pixel asks); `mv` the mean-value budget
  /// inherited from the block above.
  PixelResult pixel(int x, int y, Interval range, const BeamSearch* pfull, Interval root_range,
                    AdaptiveCache* cache, const MeanValueBudget& mv, PixelTrace* tr) {
    ctx_.mv = mv;
    const std::uint64_t e0 = ctx_.evals;
    PixelResult r;
    switch (st_.method) {
      case RenderMethod::kIaa:
        r = iaa_pixel(x, y, range, pfull, tr);
        break;
      case RenderMethod::kPoint:
      case RenderMethod::kGrid:
        r = grid_pixel(x, y, range, pfull, tr);
        break;
      case RenderMethod::kAdaptive:
        r = adaptive_pixel(x, y, range, pfull, root_range, cache, tr);
        break;
    }
    r.evals = static_cast<std::uint32_t>(ctx_.evals - e0);
    if (tr) tr->color = {r.color.r, r.color.g, r.color.b};
    return r;
  }

  /// Runs EvalRaySet on a screen block, starting with the mean-value budget `mv` (the record of
  /// the block above); records it when tracing.
  BeamSearch block(const PixelRect& rect, int level, Interval range, const BeamSearch* parent_full,
                   const MeanValueBudget& mv, PixelTrace* tr, int parent) {
    BeamTrace bt;
    const std::uint64_t e0 = ctx_.evals;
    ctx_.mv = mv;
    const BeamSearch s = eval_ray_set(ctx_, rect, range, parent_full, tr ? &bt : nullptr);
    if (tr) {
      bt.rect = rect;
      bt.level = level;
      bt.parent = parent;
      bt.decision =
          s.result == BeamResult::kMiss ? BeamDecision::kBackground : BeamDecision::kDescend;
      bt.evals = ctx_.evals - e0;
      tr->beams.push_back(std::move(bt));
    }
    return s;
  }

 private:
  // ---- IAA -------------------------------------------------------------------------------
  struct IaaAccum {
    Vec3 color;
    double coverage = 0;
    std::uint32_t leaves = 0;
    bool any_full = false, any_partial = false;
  };

  PixelResult iaa_pixel(int x, int y, Interval range, const BeamSearch* pfull, PixelTrace* tr) {
    IaaAccum acc;
    shadow_cache_.clear(0);
    const int parent = tr && !tr->beams.empty() ? static_cast<int>(tr->beams.size()) - 1 : -1;
    iaa_beam(PixelRect{double(x), double(y), double(x + 1), double(y + 1)}, 0, range, pfull, acc,
             tr, parent);
    PixelResult r;
    r.color = to_rgb(acc.color);
    r.leaves = acc.leaves;
    r.coverage = static_cast<float>(acc.coverage);
    r.certificate =
        acc.any_full ? PixelCertificate::kCovered
                     : (acc.any_partial ? PixelCertificate::kUncertain : PixelCertificate::kEmpty);
    return r;
  }

  void iaa_beam(const PixelRect& rect, int level, Interval range, const BeamSearch* parent_full,
                IaaAccum& acc, PixelTrace* tr, int parent) {
    BeamTrace bt;
    BeamTrace* t = tr ? &bt : nullptr;
    const std::uint64_t e0 = ctx_.evals;
    const double area = rect.area();
    // At the last level a proof of full coverage only decides the pixel's certificate (and how
    // the part's shading point is found): once another part of the pixel is certified covered
    // it is not tried.
    const bool last = level >= st_.max_level;
    BeamSearch s = parent_full && last
                       ? inherit_full(ctx_, rect, *parent_full, t)
                       : eval_ray_set(ctx_, rect, range, parent_full, t, !(last && acc.any_full));
    BeamDecision decision = BeamDecision::kBackground;
    if (s.result == BeamResult::kMiss) {
      acc.color = acc.color + area * background(ctx_);
    } else {
      bool shade_now = level >= st_.max_level;
      decision = BeamDecision::kShadeLeaf;
      if (!shade_now && s.result == BeamResult::kFull) {
        // The estimator over the whole hit box first (one gradient evaluation); when it is too
        // wide, a shorter hit segment (a few slice evaluations) and the estimator over its
        // pieces that may hold the surface, which is much cheaper than splitting the beam.
        Interval est = beam_estimator(ctx_, s, 1);
        if (est.width() > st_.estimator_threshold) {
          tighten_far(ctx_, &s,
                      st_.depth_tolerance * su_.frame.scale *
                          std::max(rect.width(), rect.height()) * s.t_near);
          est = beam_estimator(ctx_, s, kEstimatorPieces, st_.estimator_threshold);
        }
        if (t) t->estimator = est;
        if (est.width() <= st_.estimator_threshold) {
          shade_now = true;
          decision = BeamDecision::kShadeFull;
        }
      }
      if (shade_now) {
        double w = 1.0;
        // Two statements: shade_beam() sets w, and the order in which a call's arguments are
        // evaluated is unspecified (w_blend(shade_beam(..., &w), w) read w before it was set).
        const Vec3 shaded = shade_beam(rect, s, range, t, &w);
        const Vec3 c = w_blend(shaded, w);
        if (t) {
          t->color = c;
          t->weight = w;
        }
        acc.color = acc.color + area * c;
        acc.coverage += area * w;
        ++acc.leaves;
        if (s.result == BeamResult::kFull) {
          acc.any_full = true;
        } else {
          acc.any_partial = true;
        }
      } else {
        decision = BeamDecision::kSplit;
      }
    }
    int index = -1;
    if (tr) {
      bt.rect = rect;
      bt.level = level;
      bt.parent = parent;
      bt.decision = decision;
      bt.evals = ctx_.evals - e0;
      tr->beams.push_back(std::move(bt));
      index = static_cast<int>(tr->beams.size()) - 1;
    }
    if (decision != BeamDecision::kSplit) return;
    const Interval sub = child_range(s, range);
    const BeamSearch* pf = s.result == BeamResult::kFull ? &s : nullptr;
    const double um = 0.5 * (rect.u0 + rect.u1), vm = 0.5 * (rect.v0 + rect.v1);
    iaa_beam({rect.u0, rect.v0, um, vm}, level + 1, sub, pf, acc, tr, index);
    iaa_beam({um, rect.v0, rect.u1, vm}, level + 1, sub, pf, acc, tr, index);
    iaa_beam({rect.u0, vm, um, rect.v1}, level + 1, sub, pf, acc, tr, index);
    iaa_beam({um, vm, rect.u1, rect.v1}, level + 1, sub, pf, acc, tr, index);
  }

  /// Shades a beam part: at the exact hit of its central ray when there is one, else at the
  /// centre of the hit box with the mid-point normal of the interval gradient.
  Vec3 shade_beam(const PixelRect& rect, const BeamSearch& s, Interval range, BeamTrace* t,
                  double* weight) {
    const double uc = 0.5 * (rect.u0 + rect.u1), vc = 0.5 * (rect.v0 + rect.v1);
    const Vec3 d = su_.frame.dir(uc, vc);
    // Full: the central ray certainly hits in [t_near, t_far]. Partial: look for its hit only a
    // few beam widths behind t_near (a hit further back would be hidden by whatever the beam
    // touches first); beyond that the hit box's normal is used. This only chooses the shading
    // point: the certificate and the coverage do not depend on it.
    const double reach =
        kPartialShadeReach * su_.frame.scale * std::max(rect.width(), rect.height()) * s.t_near;
    const Interval sr(
        s.t_near, s.result == BeamResult::kFull ? s.t_far : std::min(range.hi(), s.t_near + reach));
    // The shading point needs a fraction of the part's footprint, not the baselines' 1e-9: near
    // grazing rays a fine tolerance costs thousands of evaluations for no visible difference.
    const double foot = su_.frame.scale * std::max(rect.width(), rect.height()) * sr.lo();
    const double shade_tol = std::max(su_.ray_tol, kShadeTolerance * foot);
    RayHit h;
    if (s.result == BeamResult::kFull) {
      h.hit = true;
      h.t = Interval(full_root(d, s, shade_tol));
    } else {
      h = search_ray(ctx_, su_.frame.eye, su_.frame.dir_box(uc, vc), sr, shade_tol,
                     su_.frame.scale * sr.hi() * 4, false);
    }
    *weight = 1.0;
    if (!h.hit && s.result == BeamResult::kPartial) {
      // A Partial part whose central ray misses the surface near t_near: that ray either sees a
      // surface further back (shade it there) or none at all. Then the part is most likely a
      // sliver of a silhouette or of a thin feature: it is shown with weight kPartialMissWeight
      // over the background, never dropped (its coverage stays > 0).
      if (sr.hi() < range.hi()) {
        h = search_ray(ctx_, su_.frame.eye, su_.frame.dir_box(uc, vc),
                       Interval(sr.hi(), range.hi()), shade_tol, su_.frame.scale * range.hi() * 4,
                       false);
      }
      if (!h.hit) *weight = kPartialMissWeight;
    }
    Vec3 p, g;
    if (h.hit) {
      p = su_.frame.eye + h.t.mid() * d;
      g = ctx_.se.eval_point_grad(p).g;
      if (!(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z)) || length(g) == 0) {
        g = interval_mid_gradient(segment_box(su_.frame.eye, su_.frame.dir_box(uc, vc), h.t));
      }
    } else {
      p = {s.hit_box.x.mid(), s.hit_box.y.mid(), s.hit_box.z.mid()};
      g = interval_mid_gradient(s.hit_box);
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

  /// The first hit of the central ray `d` of a Full part, to within `tol`: a march of point values
  /// to the first step with a sign change, then regula falsi (Illinois). The proof of the part
  /// brackets it: no ray of the part meets the surface in [t_s, t_near), f has the sign s.sign on
  /// the slice at t_s and the opposite one on the slice at t_far, and is continuous in between;
  /// so the central ray has a root in every bracket kept, and none before t_near. Only the shading
  /// point depends on it.
  double full_root(const Vec3& d, const BeamSearch& s, double tol) {
    const Vec3& eye = su_.frame.eye;
    // > 0 on the near side
    auto g = [&](double t) { return ctx_.se.eval_point(eye + t * d) * s.sign; };
    double a = s.t_near, b = s.t_far;
    double ga = g(a), gb = g(b);
    if (!(ga > 0)) {
      if (ga == 0) return a;
      a = s.t_s;  // rounding at t_near: the slice at t_s has the proved sign
      ga = g(a);
    }
    if (!(ga > 0) || !(gb < 0)) return 0.5 * (s.t_near + s.t_far);  // no usable point signs
    // The first crossing, not any: march in kRootMarch steps from the front to the first step
    // whose far end has the far sign (a feature thinner than a step can still hide a crossing:
    // shading only).
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

  /// A part's colour shown with weight `w` over the background.
  Vec3 w_blend(const Vec3& c, double w) const {
    return w == 1.0 ? c : w * c + (1.0 - w) * background(ctx_);
  }

  Vec3 interval_mid_gradient(const IBox& box) {
    const IGrad g = ctx_.eval_grad(box);
    Vec3 out;
    for (int i = 0; i < 3; ++i)
      out[i] = g.g[static_cast<std::size_t>(i)].is_finite() ? g.g[static_cast<std::size_t>(i)].mid()
                                                            : 0.0;
    return out;
  }

  // ---- point rays --------------------------------------------------------------------------
  RaySample ray(double u, double v, Interval range, PixelTrace* tr) {
    RaySample out;
    const RayHit h = search_ray(ctx_, su_.frame.eye, su_.frame.dir_box(u, v), range, su_.ray_tol,
                                su_.frame.scale * range.hi() * 4);
    out.hit = h.hit;
    out.certified = h.certified;
    Vec3 p, n;
    if (h.hit) {
      const Vec3 d = su_.frame.dir(u, v);
      p = su_.frame.eye + h.t.mid() * d;
      Vec3 g = ctx_.se.eval_point_grad(p).g;
      if (!(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z)) || length(g) == 0) {
        g = interval_mid_gradient(segment_box(su_.frame.eye, su_.frame.dir_box(u, v), h.t));
      }
      out.color = shade(ctx_, p, g, d, tr ? &n : nullptr);
    } else {
      out.color = background(ctx_);
    }
    if (tr) {
      RayTrace rt;
      rt.u = u;
      rt.v = v;
      rt.searched = range;
      rt.hit = h.hit;
      rt.certified = h.certified;
      rt.t_hit = h.t;
      rt.point = p;
      rt.normal = n;
      rt.color = out.color;
      tr->rays.push_back(rt);
    }
    return out;
  }

  /// The pixel's own beam first (every method does it: a Miss pixel costs one search).
  std::optional<Interval> pixel_beam(int x, int y, Interval range, const BeamSearch* pfull,
                                     PixelTrace* tr) {
    const int parent = tr && !tr->beams.empty() ? static_cast<int>(tr->beams.size()) - 1 : -1;
    const BeamSearch s = block(PixelRect{double(x), double(y), double(x + 1), double(y + 1)}, 0,
                               range, pfull, ctx_.mv, tr, parent);
    if (s.result == BeamResult::kMiss) return std::nullopt;
    return child_range(s, range);
  }

  PixelResult grid_pixel(int x, int y, Interval range, const BeamSearch* pfull, PixelTrace* tr) {
    PixelResult r;
    const auto sub = pixel_beam(x, y, range, pfull, tr);
    if (!sub) {
      r.color = to_rgb(background(ctx_));
      r.certificate = PixelCertificate::kEmpty;
      return r;
    }
    const int n = st_.method == RenderMethod::kPoint ? 1 : st_.grid_n;
    Vec3 sum;
    int hits = 0;
    bool certified = false;
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const RaySample s = ray(x + (i + 0.5) / n, y + (j + 0.5) / n, *sub, tr);
        sum = sum + s.color;
        hits += s.hit;
        certified |= s.certified;
      }
    }
    const double inv = 1.0 / (double(n) * n);
    r.color = to_rgb(inv * sum);
    r.leaves = static_cast<std::uint32_t>(n * n);
    r.coverage = static_cast<float>(hits * inv);
    r.certificate = certified ? PixelCertificate::kCovered : PixelCertificate::kUncertain;
    return r;
  }

  // ---- adaptive (Whitted) --------------------------------------------------------------------
  struct AdaptiveAccum {
    Vec3 color;
    double coverage = 0;
    std::uint32_t rays = 0;
    bool certified = false;
  };

  RaySample corner(int gx, int gy, Interval root_range, AdaptiveCache* cache, AdaptiveAccum& acc,
                   PixelTrace* tr) {
    const double g = double(1 << st_.max_level);
    std::size_t k = 0;
    if (cache) {
      k = std::size_t(gy - cache->gy0) * std::size_t(cache->n) + std::size_t(gx - cache->gx0);
      if (cache->done[k]) return {cache->color[k], cache->hit[k] != 0, cache->hit[k] == 2};
    }
    const RaySample s = ray(gx / g, gy / g, root_range, tr);
    ++acc.rays;
    if (cache) {
      cache->done[k] = 1;
      cache->color[k] = s.color;
      cache->hit[k] = s.hit ? (s.certified ? 2 : 1) : 0;
    }
    return s;
  }

  PixelResult adaptive_pixel(int x, int y, Interval range, const BeamSearch* pfull,
                             Interval root_range, AdaptiveCache* cache, PixelTrace* tr) {
    PixelResult r;
    if (!pixel_beam(x, y, range, pfull, tr)) {
      r.color = to_rgb(background(ctx_));
      r.certificate = PixelCertificate::kEmpty;
      return r;
    }
    AdaptiveAccum acc;
    const int g = 1 << st_.max_level;
    adaptive_square(x * g, y * g, g, 0, root_range, cache, acc, tr);
    r.color = to_rgb(acc.color);
    r.leaves = acc.rays;
    r.coverage = static_cast<float>(acc.coverage);
    r.certificate = acc.certified ? PixelCertificate::kCovered : PixelCertificate::kUncertain;
    return r;
  }

  void adaptive_square(int gx, int gy, int size, int level, Interval root_range,
                       AdaptiveCache* cache, AdaptiveAccum& acc, PixelTrace* tr) {
    const RaySample c[4] = {corner(gx, gy, root_range, cache, acc, tr),
                            corner(gx + size, gy, root_range, cache, acc, tr),
                            corner(gx, gy + size, root_range, cache, acc, tr),
                            corner(gx + size, gy + size, root_range, cache, acc, tr)};
    double diff = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        for (int ch = 0; ch < 3; ++ch)
          diff = std::max(diff, std::fabs(c[a].color[ch] - c[b].color[ch]));
      }
    }
    if (level < st_.max_level && diff > st_.adaptive_threshold) {
      const int h = size / 2;
      adaptive_square(gx, gy, h, level + 1, root_range, cache, acc, tr);
      adaptive_square(gx + h, gy, h, level + 1, root_range, cache, acc, tr);
      adaptive_square(gx, gy + h, h, level + 1, root_range, cache, acc, tr);
      adaptive_square(gx + h, gy + h, h, level + 1, root_range, cache, acc, tr);
      return;
    }
    const double area = 1.0 / double(1 << (2 * level));
    Vec3 mean;
    int hits = 0;
    for (const RaySample& s : c) {
      mean = mean + s.color;
      hits += s.hit;
      acc.certified |= s.certified;
    }
    acc.color = acc.color + (0.25 * area) * mean;
    acc.coverage += area * hits / 4.0;
  }

  RenderContext& ctx_;
  const RenderSetup& su_;
  const RenderSettings& st_;
  ShadowCache shadow_cache_;  ///< shadow results of the current IAA pixel
};

/// Window of the render: the settings' window or the whole image.
PixelWindow effective_window(const RenderSettings& s, int w, int h) {
  if (s.window.x0 == 0 && s.window.y0 == 0 && s.window.x1 == 0 && s.window.y1 == 0)
    return {0, 0, w, h};
  return s.window;
}

PixelRect block_rect(int bx, int by, int size, int w, int h) {
  return {double(bx), double(by), double(std::min(bx + size, w)), double(std::min(by + size, h))};
}

int block_level(int size) {
  int l = 0;
  while ((1 << l) < size) ++l;
  return -l;
}

/// Per-root-block output: the pixels live in the Film; the block evaluations are summed here.
struct BlockTask {
  RenderContext& ctx;
  Renderer& rn;
  Film& film;
  const PixelWindow& win;
  AdaptiveCache* cache;
  Interval root_range;
  std::uint64_t block_evals = 0;

  void store(int x, int y, const PixelResult& r) {
    const std::size_t i = film.index(x, y);
    film.color[i] = r.color;
    film.certificate[i] = r.certificate;
    film.leaves[i] = r.leaves;
    film.evals[i] = r.evals;
    film.coverage[i] = r.coverage;
  }
  void fill_background(int bx, int by, int size) {
    const Rgb bg = to_rgb(ctx.setup.scene->background);
    for (int y = std::max(by, win.y0); y < std::min(by + size, win.y1); ++y) {
      for (int x = std::max(bx, win.x0); x < std::min(bx + size, win.x1); ++x) {
        PixelResult r;
        r.color = bg;
        r.certificate = PixelCertificate::kEmpty;
        store(x, y, r);
      }
    }
  }
  bool intersects_window(int bx, int by, int size) const {
    return bx < win.x1 && bx + size > win.x0 && by < win.y1 && by + size > win.y0;
  }
  void run(int bx, int by, int size, Interval range, const BeamSearch* pfull,
           const MeanValueBudget& mv) {
    if (size < kMinBlock) {
      store(bx, by, rn.pixel(bx, by, range, pfull, root_range, cache, mv, nullptr));
      return;
    }
    const std::uint64_t e0 = ctx.evals;
    const BeamSearch s = rn.block(block_rect(bx, by, size, film.width, film.height),
                                  block_level(size), range, pfull, mv, nullptr, -1);
    const MeanValueBudget after = ctx.mv.inherited();
    block_evals += ctx.evals - e0;
    if (size == kRootBlock)
      root_range = s.result == BeamResult::kMiss ? range : child_range(s, range);
    if (s.result == BeamResult::kMiss) {
      fill_background(bx, by, size);
      return;
    }
    const Interval sub = child_range(s, range);
    const int h = size / 2;
    for (int k = 0; k < 4; ++k) {
      const int cx = bx + (k & 1) * h, cy = by + (k >> 1) * h;
      if (cx >= film.width || cy >= film.height || !intersects_window(cx, cy, h)) continue;
      run(cx, cy, h, sub, s.result == BeamResult::kFull ? &s : nullptr, after);
    }
  }
};

}  // namespace

RenderSetup::RenderSetup(const Scene& sc, const RenderSettings& st)
    : scene(&sc), settings(st), frame(sc.camera, sc.width, sc.height) {
  IAA_CHECK(sc.tape != nullptr);
  settings.validate();
  if (sc.width < 1 || sc.height < 1) throw SettingError("image size must be at least 1x1");
  if (!sc.bounds.valid()) throw Error("scene bounds are not a valid box");
  depth = depth_range(frame, sc.bounds);
  may_partial = may_be_partial(*sc.tape);
  diag = length(sc.bounds.size());
  ray_tol = 1e-9 * std::max(diag, depth.is_empty() ? 1.0 : depth.hi());
  shadow_eps = 1e-4 * diag;
}

Film render(const Scene& scene, const RenderSettings& settings, const Exec& exec) {
  const auto t0 = std::chrono::steady_clock::now();
  settings.validate_window(scene.width, scene.height);
  const RenderSetup setup(scene, settings);
  Film film(scene.width, scene.height);
  film.settings = settings;
  const PixelWindow win = effective_window(settings, scene.width, scene.height);
  film.window = win;

  // Root blocks that meet the window, in row-major order.
  std::vector<std::pair<int, int>> roots;
  for (int by = (win.y0 / kRootBlock) * kRootBlock; by < win.y1; by += kRootBlock) {
    for (int bx = (win.x0 / kRootBlock) * kRootBlock; bx < win.x1; bx += kRootBlock)
      roots.push_back({bx, by});
  }
  std::vector<std::uint64_t> block_evals(roots.size(), 0), pruned_evals(roots.size(), 0);
  ProgressPhase phase(exec.progress, "render", static_cast<std::uint64_t>(roots.size()));
  const int g = 1 << settings.max_level;

  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, roots.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& br) {
                        RoundingScope scope;  // once per task, not per operation
                        RenderContext ctx(setup);
                        Renderer rn(ctx);
                        std::optional<AdaptiveCache> cache;
                        for (std::size_t i = br.begin(); i != br.end(); ++i) {
                          if (phase.cancelled()) return;
                          const auto [bx, by] = roots[i];
                          AdaptiveCache* cp = nullptr;
                          if (settings.method == RenderMethod::kAdaptive) {
                            cache.emplace(bx * g, by * g, kRootBlock * g + 1);
                            cp = &*cache;
                          }
                          // Each root block starts without regions or specialized tapes, so
                          // that what it evaluates (and counts) does not depend on the blocks
                          // before it.
                          ctx.se.reset();
                          const std::uint64_t p0 = ctx.se.specialized_evals();
                          BlockTask task{ctx, rn, film, win, cp, setup.depth};
                          if (setup.depth.is_empty()) {
                            task.fill_background(bx, by, kRootBlock);
                          } else {
                            task.run(bx, by, kRootBlock, setup.depth, nullptr, MeanValueBudget{});
                          }
                          block_evals[i] = task.block_evals;
                          pruned_evals[i] = ctx.se.specialized_evals() - p0;
                          phase.advance(1);
                        }
                      });
  });

  // Totals, in a fixed order so that they do not depend on the threads.
  FilmStats& s = film.stats;
  for (std::uint64_t e : block_evals) s.block_evals += e;
  for (std::uint64_t e : pruned_evals) s.pruned_evals += e;
  s.evals = s.block_evals;
  for (int y = win.y0; y < win.y1; ++y) {
    for (int x = win.x0; x < win.x1; ++x) {
      const std::size_t i = film.index(x, y);
      ++s.pixels;
      s.evals += film.evals[i];
      s.leaves += film.leaves[i];
      s.covered_area += film.coverage[i];
      switch (film.certificate[i]) {
        case PixelCertificate::kEmpty:
          ++s.empty;
          break;
        case PixelCertificate::kCovered:
          ++s.covered;
          break;
        case PixelCertificate::kUncertain:
          ++s.uncertain;
          break;
        case PixelCertificate::kNotRendered:
          break;
      }
    }
  }
  film.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return film;
}

PixelResult render_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                         PixelTrace* trace) {
  if (x < 0 || y < 0 || x >= scene.width || y >= scene.height) {
    throw SettingError("pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                       std::to_string(scene.width) + "x" + std::to_string(scene.height) + " image");
  }
  const RenderSetup setup(scene, settings);
  RoundingScope scope;
  RenderContext ctx(setup);
  Renderer rn(ctx);
  if (trace) {
    trace->x = x;
    trace->y = y;
  }
  PixelResult out;
  out.color = to_rgb(scene.background);
  out.certificate = PixelCertificate::kEmpty;
  if (setup.depth.is_empty()) return out;
  // Walk the chain of screen blocks above the pixel, exactly as render() does.
  Interval range = setup.depth, root_range = setup.depth;
  int parent = -1;
  BeamSearch prev;  // the block above, passed on when it is Full (as render() does)
  bool have_prev = false;
  MeanValueBudget mv;  // the block above's, passed on (as render() does)
  for (int size = kRootBlock; size >= kMinBlock; size /= 2) {
    const int bx = (x / size) * size, by = (y / size) * size;
    const std::uint64_t e0 = ctx.evals;
    const BeamSearch s =
        rn.block(block_rect(bx, by, size, scene.width, scene.height), block_level(size), range,
                 have_prev ? &prev : nullptr, mv, trace, parent);
    mv = ctx.mv.inherited();
    out.block_evals += static_cast<std::uint32_t>(ctx.evals - e0);
    if (trace) parent = static_cast<int>(trace->beams.size()) - 1;
    if (size == kRootBlock)
      root_range = s.result == BeamResult::kMiss ? range : child_range(s, range);
    if (s.result == BeamResult::kMiss) {
      if (trace) trace->color = scene.background;
      return out;
    }
    range = child_range(s, range);
    prev = s;
    have_prev = s.result == BeamResult::kFull;
  }
  const std::uint32_t block_evals = out.block_evals;
  // The adaptive method's corner rays, shared within the pixel as render() shares them (render()
  // also shares them with the pixels around, so its ray and evaluation counts can be lower).
  std::optional<AdaptiveCache> cache;
  if (settings.method == RenderMethod::kAdaptive) {
    const int g = 1 << settings.max_level;
    cache.emplace(x * g, y * g, g + 1);
  }
  out = rn.pixel(x, y, range, have_prev ? &prev : nullptr, root_range, cache ? &*cache : nullptr,
                 mv, trace);
  out.block_evals = block_evals;
  return out;
}

}  // namespace iaa
