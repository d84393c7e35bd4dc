// Small 3-vectors and axis-aligned boxes of doubles and intervals.
#pragma once

#include <array>
#include <cmath>

#include "core/interval.h"

namespace iaa {

/// A point or direction in 3-space.
struct Vec3 {
  double x = 0, y = 0, z = 0;

  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
  friend Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
  friend Vec3 operator*(Vec3 a, double s) { return s * a; }
  friend Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
  friend bool operator==(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) {
  return std::sqrt(dot(a, a));
}
inline Vec3 normalize(Vec3 a) {
  const double l = length(a);
  return l > 0 ? a / l : a;
}

/// An axis-aligned box of doubles: [lo.x, hi.x] x [lo.y, hi.y] x [lo.z, hi.z].
struct Box3 {
  Vec3 lo, hi;

  bool valid() const {
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || !(lo[i] <= hi[i])) return false;
    }
    return true;
  }
  bool contains(Vec3 p) const {
    return lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y && lo.z <= p.z && p.z <= hi.z;
  }
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 size() const { return hi - lo; }
};

/// A box of intervals, one per axis: the argument of an interval evaluation.
struct IBox {
  Interval x, y, z;

  IBox() = default;
  IBox(Interval x_, Interval y_, Interval z_) : x(x_), y(y_), z(z_) {}
  explicit IBox(const Box3& b) : x(b.lo.x, b.hi.x), y(b.lo.y, b.hi.y), z(b.lo.z, b.hi.z) {}
  const Interval& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Interval& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  bool is_empty() const { return x.is_empty() || y.is_empty() || z.is_empty(); }
  /// Every side contains o's (an empty side of o counts as contained, as in Interval::contains).
  bool contains(const IBox& o) const {
    return x.contains(o.x) && y.contains(o.y) && z.contains(o.z);
  }
  bool contains(Vec3 p) const { return x.contains(p.x) && y.contains(p.y) && z.contains(p.z); }
};

}  // namespace iaa
