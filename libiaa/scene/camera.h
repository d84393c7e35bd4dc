// The pinhole camera: what a scene says (Camera), its validation, and the orthonormal frame that
// gives the ray direction through any point (u, v) of the image in continuous pixel coordinates
// (docs/design.md, "Conventions"). Also the boxes of beam segments that the renderer and the mesh
// ray caster evaluate on.
#pragma once

#include "core/interval.h"
#include "core/vec.h"

namespace iaa {

/// Pinhole camera, right-handed; vertical field of view in degrees.
struct Camera {
  /// Limits of the vertical field of view in degrees (docs/scene-format.md): above 0, so that the
  /// image plane has a size, and below 180.
  static constexpr double kMinFovDeg = 1e-3;
  static constexpr double kMaxFovDeg = 179.0;
  Vec3 eye{0, 0, 3};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_deg = 40.0;
};

/// A rectangle of continuous pixel coordinates [u0, u1] x [v0, v1] (u right, v down).
struct PixelRect {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  double width() const { return u1 - u0; }
  double height() const { return v1 - v0; }
  double area() const { return (u1 - u0) * (v1 - v0); }
};

/// Throws iaa::Error when the camera cannot form an image: eye == look_at, `up` parallel to the
/// view direction, a field of view outside (0, 180) degrees, or non-finite numbers.
void validate_camera(const Camera& camera);

/// Orthonormal camera frame. The direction through (u, v) is
///   d(u, v) = forward + (u - w/2) * s * right + (h/2 - v) * s * up,   s = 2 tan(fov/2) / h,
/// so that the depth t of eye + t * d along `forward` is t itself.
struct CameraFrame {
  Vec3 eye, forward, right, up;
  double scale = 0;  ///< s: pixel size at depth 1
  double half_w = 0, half_h = 0;

  /// Builds the frame; throws iaa::Error (validate_camera) for a degenerate camera.
  CameraFrame(const Camera& camera, int width, int height);

  /// Direction through (u, v), in double (for shading and point rays).
  Vec3 dir(double u, double v) const {
    const double a = (u - half_w) * scale, b = (half_h - v) * scale;
    return {forward.x + a * right.x + b * up.x, forward.y + a * right.y + b * up.y,
            forward.z + a * right.z + b * up.z};
  }
  /// Enclosure of the directions d(u, v) for all (u, v) in the rectangle (needs a
  /// RoundingScope). d is affine in (u, v), so its range is spanned by the four corners.
  IBox dir_box(const PixelRect& r) const;
  /// Enclosure of the exact direction through one point (needs a RoundingScope).
  IBox dir_box(double u, double v) const { return dir_box(PixelRect{u, v, u, v}); }
};

/// Depth range [t0, t1] along `forward` that contains every point of `bounds` in front of the
/// eye (t0 >= 0). Empty (t1 < t0) when the bounds lie behind the eye.
Interval depth_range(const CameraFrame& frame, const Box3& bounds);

/// Box of the points eye + t * d for t in `t` and d in `dirs`, outward rounded (needs a
/// RoundingScope). Because every coordinate is bilinear in (t, d), this is the box of the
/// segment's corners.
inline IBox segment_box(const Vec3& eye, const IBox& dirs, const Interval& t) {
  return IBox(Interval(eye.x) + t * dirs.x, Interval(eye.y) + t * dirs.y,
              Interval(eye.z) + t * dirs.z);
}

/// Intersection of a box with the scene bounds; empty when they do not meet.
inline IBox clip_box(const IBox& b, const Box3& bounds) {
  return IBox(intersect(b.x, Interval(bounds.lo.x, bounds.hi.x)),
              intersect(b.y, Interval(bounds.lo.y, bounds.hi.y)),
              intersect(b.z, Interval(bounds.lo.z, bounds.hi.z)));
}

/// True when the box lies inside the bounds.
inline bool box_inside(const IBox& b, const Box3& bounds) {
  return bounds.lo.x <= b.x.lo() && b.x.hi() <= bounds.hi.x && bounds.lo.y <= b.y.lo() &&
         b.y.hi() <= bounds.hi.y && bounds.lo.z <= b.z.lo() && b.z.hi() <= bounds.hi.z;
}

}  // namespace iaa
