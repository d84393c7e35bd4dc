#include "scene/camera.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace iaa {

namespace {
bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
}  // namespace

void validate_camera(const Camera& c) {
  if (!finite(c.eye) || !finite(c.look_at) || !finite(c.up)) {
    throw Error("camera: eye, look_at and up must be finite numbers");
  }
  if (!(c.fov_deg > 0.0 && c.fov_deg < 180.0)) {
    throw Error("camera: fov must be in (0, 180) degrees, got " + std::to_string(c.fov_deg));
  }
  const Vec3 view = c.look_at - c.eye;
  const double lv = length(view);
  if (!(lv > 0.0))
    throw Error("camera: eye and look_at are the same point; the view has no direction");
  const double lu = length(c.up);
  if (!(lu > 0.0)) throw Error("camera: up is the zero vector");
  const double s = length(cross(view, c.up)) / (lv * lu);
  if (!(s > 1e-9)) {
    throw Error("camera: up is parallel to the view direction (look_at - eye); choose another up");
  }
}

CameraFrame::CameraFrame(const Camera& c, int width, int height) {
  validate_camera(c);
  eye = c.eye;
  forward = normalize(c.look_at - c.eye);
  right = normalize(cross(forward, c.up));
  up = cross(right, forward);
  scale = 2.0 * std::tan(c.fov_deg * M_PI / 360.0) / height;
  half_w = 0.5 * width;
  half_h = 0.5 * height;
}

IBox CameraFrame::dir_box(const PixelRect& r) const {
  const Interval s(scale);
  const Interval a = (Interval(r.u0, r.u1) - Interval(half_w)) * s;
  const Interval b = (Interval(half_h) - Interval(r.v0, r.v1)) * s;
  IBox d;
  for (int i = 0; i < 3; ++i)
    d[i] = Interval(forward[i]) + a * Interval(right[i]) + b * Interval(up[i]);
  return d;
}

Interval depth_range(const CameraFrame& f, const Box3& b) {
  // A point p = eye + t d(u, v) of the bounds has dot(p - eye, forward) = t * dot(d, forward).
  // Enclose the first over the box and the second over the whole image (it is ~1 but not
  // exactly, in floating point), and divide, all outward rounded.
  RoundingScope scope;
  Interval depth(0.0);
  for (int i = 0; i < 3; ++i)
    depth += (Interval(b.lo[i], b.hi[i]) - Interval(f.eye[i])) * Interval(f.forward[i]);
  // dot(d, forward) = ff + a fr + b fu with a, b the image-plane offsets; written this way the
  // interval result stays tight (the three dot products are evaluated as intervals).
  const auto idot = [](const Vec3& p, const Vec3& q) {
    return Interval(p.x) * Interval(q.x) + Interval(p.y) * Interval(q.y) +
           Interval(p.z) * Interval(q.z);
  };
  const Interval s(f.scale);
  const Interval ia = (Interval(0.0, 2 * f.half_w) - Interval(f.half_w)) * s;
  const Interval ib = (Interval(f.half_h) - Interval(0.0, 2 * f.half_h)) * s;
  const Interval k =
      idot(f.forward, f.forward) + ia * idot(f.right, f.forward) + ib * idot(f.up, f.forward);
  IAA_CHECK(k.lo() > 0.0);
  if (depth.hi() <= 0.0) return Interval::empty();
  const double lo = depth.lo() <= 0.0 ? 0.0 : (Interval(depth.lo()) / Interval(k.hi())).lo();
  const double hi = (Interval(depth.hi()) / Interval(k.lo())).hi();
  return Interval(lo, hi);
}

}  // namespace iaa
