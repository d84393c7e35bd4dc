// EvalRaySet's certificates, as properties: a Miss beam holds no root of any of 100 random rays
// inside it; a Full beam's random rays all meet the surface inside [t_near, t_far].
#include "render/beam.h"

#include <gtest/gtest.h>

#include <random>

#include "render/ray_search.h"
#include "render/render_test_util.h"

namespace iaa {
namespace {

/// Dense point sampling of f along the ray: true when a strict sign change is seen.
bool sign_change_along(PointEval& pe, const Vec3& eye, const Vec3& d, double t0, double t1,
                       const Box3& b) {
  int last = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double t = t0 + (t1 - t0) * i / 2000.0;
    const Vec3 p = eye + t * d;
    if (!b.contains(p)) {
      last = 0;
      continue;
    }
    const double v = pe.eval(p);
    const int s = v > 0 ? 1 : (v < 0 ? -1 : 0);
    if (s != 0 && last != 0 && s != last) return true;
    if (s != 0) last = s;
  }
  return false;
}

TEST(EvalRaySet, MissBeamsHoldNoRootOfRandomRays) {
  std::mt19937 rng(12345);
  int misses = 0, fulls = 0;
  for (const char* name : {"teardrop", "chubs", "blobby", "tritrumpet"}) {
    const Scene s = test::bundled(name, 64);
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    PointEval pe(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int trial = 0; trial < 60; ++trial) {
      // Beams of many sizes, from 1/16 pixel to 8 pixels, anywhere on the image.
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 8) - 4);
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w);
      const PixelRect rect{u0, v0, u0 + w, v0 + w};
      const BeamSearch b = eval_ray_set(ctx, rect, setup.depth, nullptr, nullptr);
      for (int k = 0; k < 100; ++k) {
        const double u = rect.u0 + U(rng) * w, v = rect.v0 + U(rng) * w;
        const Vec3 d = setup.frame.dir(u, v);
        if (b.result == BeamResult::kMiss) {
          const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v), setup.depth,
                                      setup.ray_tol, 1.0);
          EXPECT_FALSE(h.certified) << name << " beam " << u0 << "," << v0 << " w " << w;
          EXPECT_FALSE(sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), setup.depth.hi(),
                                         s.bounds));
        } else {
          // No ray of the beam meets the surface before t_near.
          EXPECT_FALSE(
              sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), b.t_near, s.bounds));
          if (b.result == BeamResult::kFull) {
            const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v),
                                        Interval(b.t_near, b.t_far), setup.ray_tol, 1.0);
            EXPECT_TRUE(h.hit) << name;
          }
        }
      }
      misses += b.result == BeamResult::kMiss;
      fulls += b.result == BeamResult::kFull;
    }
  }
  EXPECT_GT(misses, 20);
  EXPECT_GT(fulls, 5);
}

}  // namespace
}  // namespace iaa
