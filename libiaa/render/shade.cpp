#include "render/shade.h"

#include <cmath>

#include "render/camera.h"
#include "render/ray_search.h"

namespace iaa {

Vec3 shade(RenderContext& ctx, const Vec3& p, const Vec3& grad, const Vec3& view_dir,
           Vec3* normal_out) {
  const Scene& sc = *ctx.setup.scene;
  const Material& m = sc.material;
  const Vec3 v = normalize(-view_dir);
  Vec3 n = normalize(grad);
  if (!(length(n) > 0.5)) n = v;  // no usable gradient (a singular point): face the eye
  if (dot(n, v) < 0) n = -n;
  if (normal_out) *normal_out = n;
  Vec3 c = m.ambient * m.color;
  for (const PointLight& l : sc.lights) {
    const Vec3 to_l = l.position - p;
    const Vec3 ldir = normalize(to_l);
    const double ndl = dot(n, ldir);
    if (ndl <= 0) continue;
    if (ctx.setup.settings.shadows) {
      // Shadow ray from just off the surface to the light, inside the bounds only.
      const Vec3 o = p + ctx.setup.shadow_eps * n;
      const IBox d(Interval(l.position.x) - Interval(o.x), Interval(l.position.y) - Interval(o.y),
                   Interval(l.position.z) - Interval(o.z));
      const double len = length(to_l);
      const double tol = 0.125 * ctx.setup.shadow_eps / std::max(len, 1e-300);
      if (segment_may_hit(ctx, o, d, Interval(0.0, 1.0), tol)) continue;
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
