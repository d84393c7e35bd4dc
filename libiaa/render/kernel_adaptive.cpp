// The adaptive kernel (Whitted): the pixel is a square of point rays at its corners, split into
// four while the corner colours differ by more than adaptive_threshold, down to max_level. The
// corner rays lie on a fine grid and are shared through AdaptiveCorners.
#include <algorithm>
#include <cmath>

#include "render/kernel.h"

namespace iaa {

namespace {

/// One pixel's squares: the sums over the squares it was split into.
class AdaptivePixel {
 public:
  AdaptivePixel(RenderContext& ctx, AdaptiveCorners& corners, PixelTrace* tr)
      : ctx_(ctx), st_(ctx.setup.settings), corners_(corners), tr_(tr) {}

  PixelResult run(const PixelJob& job) {
    if (!pixel_beam(ctx_, job, tr_)) return background_pixel(ctx_);
    const int g = 1 << st_.max_level;
    square(job.x * g, job.y * g, g, 0);
    PixelResult r;
    r.color = to_rgb(color_);
    r.leaves = rays_;
    r.coverage = static_cast<float>(coverage_);
    r.certificate = certified_ ? PixelCertificate::kCovered : PixelCertificate::kUncertain;
    return r;
  }

 private:
  /// The corner ray at fine-grid position (gx, gy), searched once per root block.
  RaySample corner(int gx, int gy) {
    AdaptiveCorners& c = corners_;
    const std::size_t k = std::size_t(gy - c.gy0) * std::size_t(c.n) + std::size_t(gx - c.gx0);
    if (c.done[k]) return {c.color[k], c.hit[k] != 0, c.hit[k] == 2};
    const double g = double(1 << st_.max_level);
    const RaySample s = sample_ray(ctx_, gx / g, gy / g, c.range, tr_);
    ++rays_;
    c.done[k] = 1;
    c.color[k] = s.color;
    c.hit[k] = s.hit ? (s.certified ? 2 : 1) : 0;
    return s;
  }

  /// The square of fine-grid edge `size` at (gx, gy), at subdivision `level`: split, or added to
  /// the sums with the mean of its corners.
  void square(int gx, int gy, int size, int level) {
    const RaySample c[4] = {corner(gx, gy), corner(gx + size, gy), corner(gx, gy + size),
                            corner(gx + size, gy + size)};
    double diff = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        for (int ch = 0; ch < 3; ++ch)
          diff = std::max(diff, std::fabs(c[a].color[ch] - c[b].color[ch]));
      }
    }
    if (level < st_.max_level && diff > st_.adaptive_threshold) {
      const int h = size / 2;
      square(gx, gy, h, level + 1);
      square(gx + h, gy, h, level + 1);
      square(gx, gy + h, h, level + 1);
      square(gx + h, gy + h, h, level + 1);
      return;
    }
    const double area = 1.0 / double(1 << (2 * level));
    Vec3 mean;
    int hits = 0;
    for (const RaySample& s : c) {
      mean = mean + s.color;
      hits += s.hit;
      certified_ |= s.certified;
    }
    color_ = color_ + (0.25 * area) * mean;
    coverage_ += area * hits / 4.0;
  }

  RenderContext& ctx_;
  const RenderSettings& st_;
  AdaptiveCorners& corners_;
  PixelTrace* tr_;
  Vec3 color_;           ///< sum of the squares' mean colours times their areas
  double coverage_ = 0;  ///< sum of the squares' hit shares times their areas
  std::uint32_t rays_ = 0;
  bool certified_ = false;
};

}  // namespace

PixelResult adaptive_pixel(RenderContext& ctx, const PixelJob& job, AdaptiveCorners& corners,
                           PixelTrace* trace) {
  return AdaptivePixel(ctx, corners, trace).run(job);
}

}  // namespace iaa
