// The guaranteed 1D search along one ray (docs/design.md, "Rendering"): bisection of the
// depth range with interval F, discarding pieces with 0 not in F, the first remaining piece
// narrowed by interval Newton where F' excludes 0. A ray's root is never skipped.
#pragma once

#include "core/interval.h"
#include "core/vec.h"
#include "render/context.h"

namespace iaa {

/// The first root along a ray, as far as intervals can tell.
struct RayHit {
  bool hit = false;        ///< some piece of width <= tol could not be excluded
  bool certified = false;  ///< a root is proved in `t` (sign change or interval Newton)
  Interval t;              ///< enclosure of the first possible root (when hit)
};

/// Searches origin + t * dir for t in `range`, front to back, inside the scene bounds. `dir` is
/// an enclosure of the exact direction (a degenerate box for a double direction). Pieces are
/// narrowed to width `tol`; interval Newton is tried on pieces no wider than `newton_from`. With
/// `first` > 0 the range is first cut into pieces of width first, first, 2 first, 4 first, ...
/// from its front (as segment_may_hit's), else bisected from the whole.
/// With `certify` false, a hit found by bisection is not tried for a proved sign change
/// (`certified` then only reports interval Newton's proofs): for callers that only need where the
/// first possible root is, such as the shading point of an IAA part. Needs a RoundingScope.
RayHit search_ray(RenderContext& ctx, const Vec3& origin, const IBox& dir, Interval range,
                  double tol, double newton_from, bool certify = true, double first = 0);

/// The first possible root along a shading ray (an IAA part's central ray), uncertified: where f
/// is a polynomial of degree at most RayPolynomial::kMaxDegree, by bisection of the ray's
/// restriction in Bernstein form (expr/ray_poly.h), one polynomial per ray and no pass over the
/// tape per piece; else search_ray(..., certify = false). Both keep every piece whose enclosure
/// holds 0, so neither steps over a root; the Bernstein hull is tighter, so a ray that passes
/// just beside the surface is more often found to miss it. Needs a RoundingScope.
RayHit search_shading_ray(RenderContext& ctx, const Vec3& origin, const IBox& dir, Interval range,
                          double tol, double newton_from, double first = 0);

/// True when some point of the segment origin + s * dir, s in range, may lie on the surface
/// (a shadow ray). Stops at the first piece of width <= tol that still contains 0. With `first`
/// > 0 the range is first cut into pieces of width first, first, 2 first, 4 first, ... from its
/// front (for a segment that starts close to the surface, such as a shadow ray); else it is
/// bisected from the whole. With `at`, a true result sets it to the front of that piece. With
/// `narrowest` (and `from`), it gets the width of the narrowest piece starting at `from` or
/// beyond that may hold the surface (unchanged when none): how close the segment passes.
bool segment_may_hit(RenderContext& ctx, const Vec3& origin, const IBox& dir, Interval range,
                     double tol, double first = 0, double* at = nullptr,
                     double* narrowest = nullptr, double from = 0);

}  // namespace iaa
