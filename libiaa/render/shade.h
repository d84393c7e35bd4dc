// Phong shading from the gradient, with point lights and optional shadow rays that are tested
// with the guaranteed 1D search (a shadow is cast wherever the surface may lie on the way).
#pragma once

#include <cstdint>

#include "core/vec.h"
#include "render/context.h"

namespace iaa {

/// Shadow-ray results of the shading points of one pixel, reused by nearby points of it. The IAA
/// leaves of a pixel are shaded at points a fraction of a pixel apart; one guaranteed shadow
/// search per cluster of such points (within `radius` of the point that was tested, normals
/// within ~18 degrees) gives shadows at pixel resolution instead of per leaf, at a fraction of
/// the cost. One fresh cache per pixel (the IAA kernel's pixel owns it): the result then does not
/// depend on threads or tiles.
struct ShadowCache {
  static constexpr int kSize = 8;
  struct Entry {
    Vec3 p, n;
    std::uint32_t tested = 0;  ///< lights whose shadow ray was searched from p
    std::uint32_t lit = 0;     ///< of those, the ones found unoccluded
  };
  Entry entries[kSize];
  /// Per light (the first 32), where the shadow ray of an entry that found it occluded first
  /// may meet the surface (its parameter in [0, 1] from the entry's point to the light).
  double occluder[kSize][32];
  int count = 0;
  double radius = 0;  ///< reuse distance (world units)
};

/// A Full IAA part being shaded, so that a shadow edge inside it is shown at the share of its
/// points that see each light instead of all lit or all dark. `patch` encloses the part's
/// surface points; their shadow rays beyond a few patch diameters are tested together, as a cone
/// to the light (a few interval evaluations): when every one of them is proved to see the light
/// there, or proved to be occluded, the shading point's result stands; only when the cone test
/// cannot tell are `samples` of the part given their own shadow rays (docs/render.md).
class ShadowPart {
 public:
  static constexpr int kMaxSamples = 16;
  IBox patch;
  int side = 2;  ///< samples per side when the part is sampled in full (side^2 <= kMaxSamples)
  /// Fills `points` with the side^2 points of the part's surface at the centres of a grid of
  /// side x side over the part; returns how many.
  virtual int samples(int side, Vec3* points) = 0;

 protected:
  ~ShadowPart() = default;
};

/// Colour (linear RGB) of the surface at `p` with gradient `grad`, seen along `view_dir`.
/// The normal is turned toward the eye (surfaces are two-sided). Needs a RoundingScope.
/// With `cache`, shadow results of a nearby point of the same pixel are reused (ShadowCache).
/// With `part`, each light is weighted by the share of the part's points that see it
/// (ShadowPart).
Vec3 shade(RenderContext& ctx, const Vec3& p, const Vec3& grad, const Vec3& view_dir,
           Vec3* normal_out = nullptr, ShadowCache* cache = nullptr, ShadowPart* part = nullptr);

/// The scene's background colour.
inline Vec3 background(const RenderContext& ctx) {
  return ctx.setup.scene->background;
}

}  // namespace iaa
