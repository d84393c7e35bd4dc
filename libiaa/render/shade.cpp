#include "render/shade.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/piece_stack.h"
#include "render/ray_search.h"
#include "scene/camera.h"

namespace iaa {
namespace {

/// Cosine of the largest angle between normals of points that share shadow results.
constexpr double kShadowReuseCos = 0.95;

/// Length in front of a ShadowPart's patch, in patch diameters, in which its points' shadow rays
/// are not tested as a cone (the cone's first slices hold the patch itself, which is surface):
/// there only the shading point's own shadow ray is searched. An occluder that close is mostly
/// the part's own surface curving toward a grazing light, where the diffuse term is small.
constexpr double kConeNear = 4.0;
/// Width (in patch diameters) below which a cone test's piece is not bisected but left.
constexpr double kConeTol = 1.0;
/// A lit shading point's part is tested as a cone only when its shadow ray's search had to
/// narrow a piece that may hold the surface to this many cone widths (beyond the near length).
constexpr double kConeGate = 2.0;
/// Most depth pieces a cone test leaves to its samples' own shadow rays.
constexpr int kConeLeft = 8;
/// Depth tolerance of a sample's shadow ray in a piece left by the cone test, in cone widths
/// (patch diameter over distance to the light): a share estimate needs no finer resolution.
constexpr double kSampleTol = 1.0 / 8;
/// Most interval evaluations of one cone test; past them the test cannot tell.
constexpr int kConeEvals = 64;
/// Steps (in cone widths) behind the shading point's occluder in which a slice of the cone is
/// looked for wholly on the far side of the surface.
constexpr int kConeSteps = 8;

/// True when the shadow ray from `o` (just off the surface) to the light may meet the surface;
/// `at` (when true) the parameter in [0, 1] of the first piece that may.
bool occluded(RenderContext& ctx, const Vec3& o, const PointLight& l, double* at = nullptr,
              double* narrowest = nullptr, double from = 0) {
  const IBox d(Interval(l.position.x) - Interval(o.x), Interval(l.position.y) - Interval(o.y),
               Interval(l.position.z) - Interval(o.z));
  const double len = length(l.position - o);
  const double tol = 0.125 * ctx.setup.shadow_eps / std::max(len, 1e-300);
  // The ray starts shadow_eps off the surface: pieces of 16 tolerances (twice that offset) and
  // doubling from there pass it with one evaluation each.
  return segment_may_hit(ctx, o, d, Interval(0.0, 1.0), tol, 16 * tol, at, narrowest, from);
}

/// The points q + t (l - q) of every shadow ray of the cone from q in `from` to the light l,
/// for t in `t`, outward rounded (needs a RoundingScope).
IBox cone_box(const IBox& from, const Vec3& l, const Interval& t) {
  const Interval s = Interval(1.0) - t;
  return IBox(s * from.x + t * Interval(l.x), s * from.y + t * Interval(l.y),
              s * from.z + t * Interval(l.z));
}

/// The cone of the shadow rays of a ShadowPart: its patch moved shadow_eps off the surface in
/// every direction, its diameter and its distance to the light.
struct Cone {
  IBox from;
  double diam = 0, len = 0;
};

Cone make_cone(const RenderContext& ctx, const IBox& patch, const Vec3& l) {
  Cone c;
  const double e = ctx.setup.shadow_eps;
  c.from = IBox(patch.x + Interval(-e, e), patch.y + Interval(-e, e), patch.z + Interval(-e, e));
  c.diam = length(Vec3{c.from.x.width(), c.from.y.width(), c.from.z.width()});
  const Vec3 mid{c.from.x.mid(), c.from.y.mid(), c.from.z.mid()};
  c.len = std::max(length(l - mid), 1e-300);
  return c;
}

/// The depth pieces beyond kConeNear patch diameters in which some shadow ray of the cone may
/// meet the surface: pieces of the cone's depth range (the first kConeNear diameters long, then
/// doubling, as in segment_may_hit), each excluded by one evaluation or bisected down to the
/// cone's width. Returns how many are left in `left` (0: every ray is proved to see the light
/// there), or -1 when more than kConeLeft are, or the test took more than kConeEvals.
int cone_unresolved(RenderContext& ctx, const Cone& c, const Vec3& l, Interval* left) {
  const double t0 = kConeNear * c.diam / c.len;
  if (!(t0 < 1)) return 0;  // the light is within the near length
  const double tol = kConeTol * c.diam / c.len;
  PieceStack st;
  double ends[41];
  int n = 0;
  ends[n++] = t0;
  double w = t0;
  while (n < 40 && ends[n - 1] + w < 1.0) {
    ends[n] = ends[n - 1] + w;
    ++n;
    w *= 2;
  }
  ends[n++] = 1.0;
  for (int k = n - 1; k > 0; --k) st.push(ends[k - 1], ends[k]);
  int evals = 0, count = 0;
  double a = 0, b = 0;
  while (st.pop(&a, &b)) {
    const IBox box = clip_box(cone_box(c.from, l, Interval(a, b)), ctx.bounds());
    if (box.is_empty()) continue;
    if (++evals > kConeEvals) return -1;
    const Interval f = ctx.eval(box);
    if (f.is_empty() || !f.contains_zero()) continue;
    const double m = 0.5 * (a + b);
    if (b - a <= tol || m <= a || m >= b || !st.has_room(2)) {
      if (count > 0 && left[count - 1].hi() == a) {  // next to the last one: one piece
        left[count - 1] = Interval(left[count - 1].lo(), b);
        continue;
      }
      if (count == kConeLeft) return -1;
      left[count++] = Interval(a, b);
      continue;
    }
    st.push(m, b);
    st.push(a, m);
  }
  return count;
}

/// True when every shadow ray of the cone is proved to cross the surface: a slice of the cone
/// (all its rays at one parameter) just in front of `at`, where the shading point's shadow ray
/// may first meet the surface, has one strict sign and a slice behind it the other, with f
/// continuous in between. A few evaluations.
bool cone_occluded(RenderContext& ctx, const Cone& c, const Vec3& l, double at) {
  const double step = std::max(c.diam / c.len, 1e-12);
  const Box3& bx = ctx.bounds();
  auto sign_of = [&](double t) {
    const IBox box = cone_box(c.from, l, Interval(t));
    if (!box_inside(box, bx)) return 0;
    const Interval f = ctx.eval(box);
    return f.certainly_positive() ? 1 : (f.certainly_negative() ? -1 : 0);
  };
  double ta = 0;
  int sa = 0;
  for (double k : {1.0, 2.0, 4.0}) {
    ta = at - k * step;
    if (!(ta > 0)) {
      return false;
    }
    sa = sign_of(ta);
    if (sa != 0) break;
  }
  if (sa == 0) {
    return false;
  }
  for (int k = 1; k <= kConeSteps; ++k) {
    const double tb = at + k * step;
    if (!(tb < 1)) return false;
    if (sign_of(tb) != -sa) continue;
    if (!ctx.setup.may_partial) return true;
    bool partial = false;
    const IBox seg = cone_box(c.from, l, Interval(ta, tb));
    if (!box_inside(seg, bx)) return false;
    ctx.eval(seg, &partial);
    return !partial;
  }
  return false;
}

/// True when the shadow ray from the surface point q (normal n) may meet the surface. With
/// `count` >= 0, the ray is searched only in the `left` pieces (where the cone test of its part
/// could not prove that it sees the light; the shading point's ray was searched in front of
/// them). Else it is first searched about `at` (>= 0: where the shading point's ray may meet
/// the surface), where a piece that may hold the surface settles it at once, then in full.
bool sample_occluded(RenderContext& ctx, const Vec3& q, const Vec3& n, const PointLight& l,
                     const Interval* left, int count, double width, double at, double window) {
  const Vec3 o = q + ctx.setup.shadow_eps * n;
  const IBox d(Interval(l.position.x) - Interval(o.x), Interval(l.position.y) - Interval(o.y),
               Interval(l.position.z) - Interval(o.z));
  const double len = length(l.position - o);
  const double tol = 0.125 * ctx.setup.shadow_eps / std::max(len, 1e-300);
  if (count >= 0) {
    for (int k = 0; k < count; ++k)
      if (segment_may_hit(ctx, o, d, left[k], std::max(tol, kSampleTol * width))) return true;
    return false;
  }
  if (at >= 0) {
    const Interval near(std::max(0.0, at - window), std::min(1.0, at + window));
    if (segment_may_hit(ctx, o, d, near, tol)) return true;
  }
  return occluded(ctx, o, l);
}

/// Share of a ShadowPart's samples that see the light l, when the cone test could not tell:
/// a 2 x 2 grid first, and the part's full grid only when those disagree with the shading
/// point (`lit`; `at` where its shadow ray may meet the surface).
double sampled_share(RenderContext& ctx, ShadowPart& part, const Cone& c, const PointLight& l,
                     const Vec3& n, bool lit, double at, const Interval* left, int count) {
  Vec3 pts[ShadowPart::kMaxSamples];
  const double window = 4 * c.diam / c.len;
  int cnt = part.samples(2, pts), seen = 0;
  for (int k = 0; k < cnt; ++k)
    seen += !sample_occluded(ctx, pts[k], n, l, left, count, c.diam / c.len, at, window);
  if (seen == (lit ? cnt : 0)) return lit ? 1.0 : 0.0;
  if (part.side > 2) {
    cnt = part.samples(part.side, pts);
    seen = 0;
    for (int k = 0; k < cnt; ++k)
      seen += !sample_occluded(ctx, pts[k], n, l, left, count, c.diam / c.len, at, window);
  }
  return double(seen) / cnt;
}

}  // namespace

Vec3 shade(RenderContext& ctx, const Vec3& p, const Vec3& grad, const Vec3& view_dir,
           Vec3* normal_out, ShadowCache* cache, ShadowPart* part) {
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
    double share = 1.0;  // of the part's points that see the light
    const double ndl = dot(n, ldir);
    if (ndl <= 0) continue;
    if (shadows) {
      // Shadow ray from just off the surface to the light, inside the bounds only; from the
      // cluster's first point when the pixel already searched it.
      const std::uint32_t bit = std::uint32_t(1) << (li & 31);
      double* occ = entry ? &cache->occluder[entry - cache->entries][li & 31] : nullptr;
      double at = -1;  // where the shadow ray may meet the surface (occluded)
      bool lit;
      // Lit: the narrowest piece beyond kConeNear footprints (the cache's radius) in which
      // the shadow ray may have met the surface (infinite: none).
      double close = std::numeric_limits<double>::infinity();
      if (entry && (entry->tested & bit)) {
        lit = (entry->lit & bit) != 0;
        (lit ? close : at) = *occ;
      } else {
        const Vec3 from = entry ? entry->p : p;
        const Vec3 fn = entry ? entry->n : n;
        const double len = std::max(length(l.position - from), 1e-300);
        const double near = cache ? kConeNear * cache->radius / len : 0;
        lit = !occluded(ctx, from + ctx.setup.shadow_eps * fn, l, &at, &close, near);
        if (entry) {
          entry->tested |= bit;
          if (lit) entry->lit |= bit;
          *occ = lit ? close : at;
        }
      }
      share = lit ? 1.0 : 0.0;
      if (part) {
        // The shading point's result stands for the whole part when the cone of the part's
        // shadow rays is proved clear (lit) or proved occluded; else the part's samples are
        // searched each.
        const Cone cone = make_cone(ctx, part->patch, l.position);
        // Lit, the cone is tested only where the shadow ray passed within kConeGate cone
        // widths of the surface (beyond the near length); occluded, where the occluder is
        // beyond the near length and the cheap proof that it covers the cone fails.
        Interval left[kConeLeft];
        int count = 0;
        if (lit ? close <= kConeGate * cone.diam / cone.len
                : at >= 0 && at * cone.len >= kConeNear * cone.diam &&
                      !cone_occluded(ctx, cone, l.position, at))
          count = cone_unresolved(ctx, cone, l.position, left);
        const bool sure = count == 0;
        if (!sure) share = sampled_share(ctx, *part, cone, l, n, lit, at, left, count);
      }
      if (!(share > 0)) continue;
    }
    const Vec3 h = normalize(ldir + v);
    const double spec = std::pow(std::max(0.0, dot(n, h)), m.shininess);
    const Vec3 diff = (m.diffuse * ndl) * m.color;
    Vec3 add{l.color.x * (diff.x + m.specular * spec), l.color.y * (diff.y + m.specular * spec),
             l.color.z * (diff.z + m.specular * spec)};
    if (share != 1.0) add = share * add;
    c = c + add;
  }
  return c;
}

}  // namespace iaa
