// Seeing a mesh through the scene's camera: which pixels of the view show any of its triangles.
// Built on a CGAL AABB tree over the triangles; this header is CGAL-free and the functions exist
// when IAA_HAVE_CGAL is defined. The camera is the scene's (scene/camera.h), as the renderer uses
// it, so pixel (x, y) is the area [x, x+1] x [y, y+1], row 0 at the top, exactly as in a render.
#pragma once

#include <memory>
#include <vector>

#include "core/exec.h"
#include "mesh/triangle_soup.h"
#include "scene/scene.h"

namespace iaa {

/// An AABB tree over a mesh's triangles, queried by many threads at once.
class MeshRaycaster {
 public:
  /// Builds the tree; the mesh must be valid (check_mesh).
  explicit MeshRaycaster(const TriangleSoup& mesh);
  ~MeshRaycaster();
  MeshRaycaster(const MeshRaycaster&) = delete;
  MeshRaycaster& operator=(const MeshRaycaster&) = delete;

  /// True when the ray origin + t * dir, t >= 0, meets a triangle.
  bool hits(const Vec3& origin, const Vec3& dir) const;
  /// True when the pyramid with apex `apex` over the quadrilateral c0 c1 c2 c3 (convex, in order)
  /// meets a triangle: every ray of a pixel's beam at once, up to the base.
  bool pyramid_hits(const Vec3& apex, const Vec3& c0, const Vec3& c1, const Vec3& c2,
                    const Vec3& c3) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// What the mesh shows in each pixel of a view.
struct MeshView {
  int width = 0, height = 0;
  /// Fraction of the pixel's rays_per_side^2 regular rays that hit the mesh (the report's
  /// covered-area figure).
  std::vector<float> coverage;
  /// 1 when some ray through the pixel's area (its whole beam) meets a triangle: exact, so a
  /// triangle thinner than the gap between sample rays is still seen.
  std::vector<std::uint8_t> any;
};

/// Casts the mesh with the scene's camera at the scene's resolution. Throws iaa::Error for a bad
/// camera, SettingError for rays_per_side outside 1..16.
MeshView view_mesh(const TriangleSoup& mesh, const Scene& scene, int rays_per_side,
                   const Exec& exec = {});

}  // namespace iaa
