// The dispatch from a pixel to its method's kernel, and what the kernels share.
#include "render/kernel.h"

#include <cmath>
#include <utility>

#include "scene/camera.h"

namespace iaa {

PixelResult run_kernel(RenderContext& ctx, const PixelJob& job, AdaptiveCorners* corners,
                       PixelTrace* trace) {
  ctx.mv = job.mv;
  const std::uint64_t e0 = ctx.evals;
  PixelResult r;
  switch (ctx.setup.settings.method) {
    case RenderMethod::kIaa:
      r = iaa_pixel(ctx, job, trace);
      break;
    case RenderMethod::kPoint:
    case RenderMethod::kGrid:
      r = grid_pixel(ctx, job, trace);
      break;
    case RenderMethod::kAdaptive:
      r = adaptive_pixel(ctx, job, *corners, trace);
      break;
  }
  r.evals = static_cast<std::uint32_t>(ctx.evals - e0 + (job.first ? job.first->evals : 0));
  if (trace) trace->color = {r.color.r, r.color.g, r.color.b};
  return r;
}

int record_beam(PixelTrace& trace, BeamTrace&& bt, const PixelRect& rect, int level, int parent,
                BeamDecision decision, std::uint64_t evals) {
  bt.rect = rect;
  bt.level = level;
  bt.parent = parent;
  bt.decision = decision;
  bt.evals = evals;
  trace.beams.push_back(std::move(bt));
  return static_cast<int>(trace.beams.size()) - 1;
}

Vec3 interval_mid_gradient(RenderContext& ctx, const IBox& box) {
  const IGrad g = ctx.eval_grad(box);
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const Interval& c = g.g[static_cast<std::size_t>(i)];
    out[i] = c.is_finite() ? c.mid() : 0.0;
  }
  return out;
}

Vec3 hit_gradient(RenderContext& ctx, const Vec3& p, double u, double v, const Interval& t) {
  const Vec3 g = ctx.se.eval_point_grad(p).g;
  if (std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z) && length(g) != 0) return g;
  const CameraFrame& frame = ctx.setup.frame;
  return interval_mid_gradient(ctx, segment_box(frame.eye, frame.dir_box(u, v), t));
}

}  // namespace iaa
