// The shading rays' search (search_shading_ray): on the polynomial scenes it runs on the ray's
// Bernstein form (expr/ray_poly.h), and it must never step over a root: wherever interval values
// at two depths prove opposite signs, it finds a hit no later than the second depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "render/ray_search.h"
#include "render/render_test_util.h"

namespace iaa {
namespace {

/// The sign of F at depth t of the ray, proved with intervals (0: not proved, or outside).
int proved_sign(RenderContext& ctx, const IBox& dir, double t) {
  const IBox p = segment_box(ctx.setup.frame.eye, dir, Interval(t));
  if (!box_inside(p, ctx.bounds())) return 0;
  const Interval f = ctx.eval(p);
  return f.certainly_positive() ? 1 : (f.certainly_negative() ? -1 : 0);
}

TEST(ShadingRaySearch, NeverStepsOverAProvedRoot) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int proved = 0, missed_clean = 0;
  for (const char* name : {"chubs", "teardrop", "tritrumpet", "barth_sextic"}) {
    const Scene s = test::bundled(name, 64);
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    ASSERT_TRUE(ctx.ray_poly.has_value()) << name << " is a polynomial scene";
    const Interval depth = setup.depth;
    for (int trial = 0; trial < 150; ++trial) {
      const double u = U(rng) * 64, v = U(rng) * 64;
      const IBox dir = setup.frame.dir_box(u, v);
      // A random part of the depth range, as the Partial parts' searches take.
      const double a = depth.lo() + U(rng) * 0.5 * depth.width();
      const double b = trial % 3 ? depth.hi() : a + U(rng) * (depth.hi() - a);
      const Interval range(a, b);
      const double tol = 1e-4 * range.width();
      const RayHit h = search_shading_ray(ctx, setup.frame.eye, dir, range, tol, 0.0);
      // Dense depths: the first pair of proved opposite signs brackets a root.
      int last = 0;
      double t_last = 0;
      bool found = false;
      for (int i = 0; i <= 600 && !found; ++i) {
        const double t = a + (b - a) * i / 600.0;
        const int sg = proved_sign(ctx, dir, t);
        if (sg != 0 && last != 0 && sg != last) {
          found = true;
          ++proved;
          ASSERT_TRUE(h.hit) << name << " pixel (" << u << ", " << v << "): root in [" << t_last
                             << ", " << t << "] stepped over";
          ASSERT_LE(h.t.lo(), t) << name << " pixel (" << u << ", " << v << ")";
        }
        if (sg != 0) {
          last = sg;
          t_last = t;
        }
      }
      if (!found && !h.hit) ++missed_clean;
    }
  }
  EXPECT_GT(proved, 100);
  EXPECT_GT(missed_clean, 50);
}

}  // namespace
}  // namespace iaa
