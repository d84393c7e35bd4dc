// Phong shading from the gradient, with point lights and optional shadow rays that are tested
// with the guaranteed 1D search (a shadow is cast wherever the surface may lie on the way).
#pragma once

#include "core/vec.h"
#include "render/context.h"

namespace iaa {

/// Colour (linear RGB) of the surface at `p` with gradient `grad`, seen along `view_dir`.
/// The normal is turned toward the eye (surfaces are two-sided). Needs a RoundingScope.
Vec3 shade(RenderContext& ctx, const Vec3& p, const Vec3& grad, const Vec3& view_dir,
           Vec3* normal_out = nullptr);

/// The scene's background colour.
inline Vec3 background(const RenderContext& ctx) {
  return ctx.setup.scene->background;
}

}  // namespace iaa
