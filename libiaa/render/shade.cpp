#include "render/shade.h"

#include <algorithm>
#include <cmath>

#include "render/ray_search.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// Cosine of the largest angle between normals of points that share shadow results.
constexpr double kShadowReuseCos = 0.95;

/// True when the shadow ray from `o` (just off the surface) to the light may meet the surface.
bool occluded(RenderContext& ctx, const Vec3& o, const PointLight& l) {
  const IBox d(Interval(l.position.x) - Interval(o.x), Interval(l.position.y) - Interval(o.y),
               Interval(l.position.z) - Interval(o.z));
  const double len = length(l.position - o);
  const double tol = 0.125 * ctx.setup.shadow_eps / std::max(len, 1e-300);
  // The ray starts shadow_eps off the surface: pieces of 16 tolerances (twice that offset) and
  // doubling from there pass it with one evaluation each.
  return segment_may_hit(ctx, o, d, Interval(0.0, 1.0), tol, 16 * tol);
}

}  // namespace

Vec3 shade(RenderContext& ctx, const Vec3& p, const Vec3& grad, const Vec3& view_dir,
           Vec3* normal_out, ShadowCache* cache) {
  const Scene& sc = *ctx.setup.scene;
  const Material& m = sc.material;
  const Vec3 v = normalize(-view_dir);
  Vec3 n = normalize(grad);
  if (!(length(n) > 0.5)) n = v;  // no usable gradient (a singular point): face the eye
  if (dot(n, v) < 0) n = -n;
  if (normal_out) *normal_out = n;
  Vec3 c = m.ambient * m.color;
  const bool shadows = ctx.setup.settings.shadows;
  // The cluster of this point in the pixel's shadow cache (null: search every shadow ray).
  ShadowCache::Entry* entry = nullptr;
  if (shadows && cache && sc.lights.size() <= 32) {
    for (int k = 0; k < cache->count && !entry; ++k) {
      ShadowCache::Entry& e = cache->entries[k];
      if (length(p - e.p) <= cache->radius && dot(n, e.n) >= kShadowReuseCos) entry = &e;
    }
    if (!entry && cache->count < ShadowCache::kSize) {
      entry = &cache->entries[cache->count++];
      *entry = ShadowCache::Entry{p, n, 0, 0};
    }
  }
  for (std::size_t li = 0; li < sc.lights.size(); ++li) {
    const PointLight& l = sc.lights[li];
    const Vec3 to_l = l.position - p;
    const Vec3 ldir = normalize(to_l);
    const double ndl = dot(n, ldir);
    if (ndl <= 0) continue;
    if (shadows) {
      // Shadow ray from just off the surface to the light, inside the bounds only; from the
      // cluster's first point when the pixel already searched it.
      const std::uint32_t bit = std::uint32_t(1) << (li & 31);
      bool lit;
      if (entry && (entry->tested & bit)) {
        lit = (entry->lit & bit) != 0;
      } else {
        const Vec3 from = entry ? entry->p : p;
        const Vec3 fn = entry ? entry->n : n;
        lit = !occluded(ctx, from + ctx.setup.shadow_eps * fn, l);
        if (entry) {
          entry->tested |= bit;
          if (lit) entry->lit |= bit;
        }
      }
      if (!lit) continue;
    }
    const Vec3 h = normalize(ldir + v);
    const double spec = std::pow(std::max(0.0, dot(n, h)), m.shininess);
    const Vec3 diff = (m.diffuse * ndl) * m.color;
    c = c + Vec3{l.color.x * (diff.x + m.specular * spec), l.color.y * (diff.y + m.specular * spec),
                 l.color.z * (diff.z + m.specular * spec)};
  }
  return c;
}

}  // namespace iaa
