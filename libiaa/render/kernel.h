// The per-pixel kernels of the renderer, one per method, behind one interface: the screen blocks
// above a pixel (render.cpp) leave it a depth range, and the kernel turns the pixel into a
// PixelResult. kernel.cpp dispatches on the method once per pixel; kernel_iaa.cpp (IAA pixel
// subdivision), kernel_point.cpp (point and grid sampling) and kernel_adaptive.cpp (Whitted's
// adaptive corner rays) hold the kernels. Every kernel starts with the pixel's own beam, so that
// a pixel its beam proves empty costs one search for every method.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "render/beam.h"
#include "render/context.h"
#include "render/render.h"
#include "render/shade.h"
#include "render/trace.h"

namespace iaa {

/// What the screen blocks above a pixel leave to its kernel.
struct PixelJob {
  int x = 0, y = 0;
  Interval range;                    ///< depths left: no ray of the pixel meets the surface before
  const BeamSearch* full = nullptr;  ///< the block just above, when it is Full; else null
  MeanValueBudget mv;                ///< inherited from the block just above
  /// The IAA pixel beam's depth search, made ahead with its siblings' (first_pieces()), when
  /// not null: `mv` is then the budget after it. Its evaluations count as the pixel's.
  FirstPiece* first = nullptr;
};

/// The adaptive method's corner rays on a fine grid (2^max_level positions per pixel), shared by
/// the pixels of one root block and searched over that block's depth range, so that a corner
/// ray's result does not depend on which pixel asks.
struct AdaptiveCorners {
  int gx0 = 0, gy0 = 0, n = 0;  ///< fine-grid origin and edge (in corner positions)
  Interval range;               ///< depth range of the root block
  std::vector<std::int8_t> done;
  std::vector<Vec3> color;
  std::vector<std::uint8_t> hit;  ///< 0 miss, 1 hit, 2 certified hit
  AdaptiveCorners(int gx, int gy, int edge) : gx0(gx), gy0(gy), n(edge) {
    done.assign(std::size_t(n) * n, 0);
    color.resize(std::size_t(n) * n);
    hit.assign(std::size_t(n) * n, 0);
  }
};

/// Runs the kernel of the settings' method on one pixel and counts its evaluations. `corners`
/// is needed by the adaptive method only. Records into `trace` when it is not null (the beams
/// of the blocks above must already be in it).
PixelResult run_kernel(RenderContext& ctx, const PixelJob& job, AdaptiveCorners* corners,
                       PixelTrace* trace);

// ---- the kernels (run_kernel() sets ctx.mv and counts) --------------------------------------

/// IAA: the pixel's beam split into sub-beams until each is a Miss, a Full beam whose estimator
/// is within the threshold, or at max_level; each leaf is shaded once, weighted by its area.
PixelResult iaa_pixel(RenderContext& ctx, const PixelJob& job, PixelTrace* trace);
/// Point sampling (one ray at the centre) or an n x n grid of rays per pixel.
PixelResult grid_pixel(RenderContext& ctx, const PixelJob& job, PixelTrace* trace);
/// Adaptive: corner rays of squares split while their colours differ by more than the threshold.
PixelResult adaptive_pixel(RenderContext& ctx, const PixelJob& job, AdaptiveCorners& corners,
                           PixelTrace* trace);

// ---- shared by the screen blocks and the kernels ---------------------------------------------

/// A linear colour as the Film stores it.
inline Rgb to_rgb(const Vec3& c) {
  return {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
}

/// A pixel that shows only the background, certified empty.
inline PixelResult background_pixel(const RenderContext& ctx) {
  PixelResult r;
  r.color = to_rgb(background(ctx));
  r.certificate = PixelCertificate::kEmpty;
  return r;
}

/// Depth range left for the children of a beam that is not a Miss.
inline Interval child_range(const BeamSearch& s, const Interval& range) {
  return Interval(s.t_near, s.result == BeamResult::kFull ? s.t_far : range.hi());
}

/// Index of the last beam recorded in `trace` (the parent of the next one), or -1.
inline int last_beam(const PixelTrace* trace) {
  return trace && !trace->beams.empty() ? static_cast<int>(trace->beams.size()) - 1 : -1;
}

/// Appends `bt` to `trace` with where it sits and what was decided; returns its index.
int record_beam(PixelTrace& trace, BeamTrace&& bt, const PixelRect& rect, int level, int parent,
                BeamDecision decision, std::uint64_t evals);

/// Runs EvalRaySet on a screen block (or on a pixel's own beam, level 0), starting with the
/// mean-value budget `mv`; records it when tracing, as a child of the beam `parent`.
/// `first`: its depth search made ahead (first_pieces()), `mv` the budget after it.
BeamSearch search_block(RenderContext& ctx, const PixelRect& rect, int level, Interval range,
                        const BeamSearch* full, const MeanValueBudget& mv, PixelTrace* trace,
                        int parent, FirstPiece* first = nullptr);

/// The pixel's own beam (level 0), searched like a screen block: the depth range it leaves for
/// the pixel's rays, or nothing when it is a Miss (the pixel is background).
std::optional<Interval> pixel_beam(RenderContext& ctx, const PixelJob& job, PixelTrace* trace);

/// Shaded result of one point ray.
struct RaySample {
  Vec3 color;
  bool hit = false;
  bool certified = false;
};

/// Searches the point ray through (u, v) over the depths `range` and shades its hit (or gives
/// the background); records it when tracing.
RaySample sample_ray(RenderContext& ctx, double u, double v, Interval range, PixelTrace* trace);

/// The midpoint of the interval gradient over `box` (0 where a component is not finite).
Vec3 interval_mid_gradient(RenderContext& ctx, const IBox& box);

/// The gradient for shading at the point `p` found at depths `t` of the ray through (u, v): the
/// point gradient, or the interval gradient's midpoint over the ray's segment when the point
/// gradient is not finite or is zero.
Vec3 hit_gradient(RenderContext& ctx, const Vec3& p, double u, double v, const Interval& t);

}  // namespace iaa
