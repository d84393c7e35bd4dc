// The point-sampled kernels: one ray through the pixel's centre (point) or an n x n grid of rays
// (grid), each searched with the guaranteed 1D search after the pixel's own beam; and the point
// ray they share with the adaptive kernel.
#include "render/kernel.h"
#include "render/ray_search.h"
#include "scene/camera.h"

namespace iaa {

std::optional<Interval> pixel_beam(RenderContext& ctx, const PixelJob& job, PixelTrace* trace) {
  const PixelRect rect{double(job.x), double(job.y), double(job.x + 1), double(job.y + 1)};
  const BeamSearch s =
      search_block(ctx, rect, 0, job.range, job.full, job.mv, trace, last_beam(trace));
  if (s.result == BeamResult::kMiss) return std::nullopt;
  return child_range(s, job.range);
}

RaySample sample_ray(RenderContext& ctx, double u, double v, Interval range, PixelTrace* trace) {
  const CameraFrame& frame = ctx.setup.frame;
  const RayHit h = search_ray(ctx, frame.eye, frame.dir_box(u, v), range, ctx.setup.ray_tol,
                              frame.scale * range.hi() * 4);
  RaySample out;
  out.hit = h.hit;
  out.certified = h.certified;
  Vec3 p, n;
  if (h.hit) {
    const Vec3 d = frame.dir(u, v);
    p = frame.eye + h.t.mid() * d;
    out.color = shade(ctx, p, hit_gradient(ctx, p, u, v, h.t), d, trace ? &n : nullptr);
  } else {
    out.color = background(ctx);
  }
  if (trace) {
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
    trace->rays.push_back(rt);
  }
  return out;
}

PixelResult grid_pixel(RenderContext& ctx, const PixelJob& job, PixelTrace* trace) {
  const auto sub = pixel_beam(ctx, job, trace);
  if (!sub) return background_pixel(ctx);
  const RenderSettings& st = ctx.setup.settings;
  const int n = st.method == RenderMethod::kPoint ? 1 : st.grid_n;
  Vec3 sum;
  int hits = 0;
  bool certified = false;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const RaySample s =
          sample_ray(ctx, job.x + (i + 0.5) / n, job.y + (j + 0.5) / n, *sub, trace);
      sum = sum + s.color;
      hits += s.hit;
      certified |= s.certified;
    }
  }
  // Divide by n^2 rather than multiply by 1/n^2: the kernel runs under the RoundingScope's upward
  // rounding, where 9 * (1 / 9.0) is 1 + 2^-52. An exact integer ratio rounded up stays in [0, 1]
  // and is exactly 1 when every ray hits.
  const double rays = double(n) * n;
  PixelResult r;
  r.color = to_rgb((1.0 / rays) * sum);
  r.leaves = static_cast<std::uint32_t>(n * n);
  r.coverage = static_cast<float>(hits / rays);
  r.certificate = certified ? PixelCertificate::kCovered : PixelCertificate::kUncertain;
  return r;
}

}  // namespace iaa
