// CGAL AABB-tree ray casting of a mesh; see mesh_raycast.h.
#include "mesh/mesh_raycast.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/interval.h"
#include "scene/camera.h"

namespace iaa {

namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 pt(const Vec3& p) {
  return {p.x, p.y, p.z};
}
}  // namespace

struct MeshRaycaster::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

MeshRaycaster::MeshRaycaster(const TriangleSoup& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Triangle tri(pt(mesh.vertices[t[0]]), pt(mesh.vertices[t[1]]), pt(mesh.vertices[t[2]]));
    if (!tri.is_degenerate()) impl_->triangles.push_back(tri);
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
}

MeshRaycaster::~MeshRaycaster() = default;

bool MeshRaycaster::hits(const Vec3& origin, const Vec3& dir) const {
  if (impl_->triangles.empty()) return false;
  return impl_->tree.do_intersect(K::Ray_3(pt(origin), K::Vector_3(dir.x, dir.y, dir.z)));
}

bool MeshRaycaster::pyramid_hits(const Vec3& apex, const Vec3& c0, const Vec3& c1, const Vec3& c2,
                                 const Vec3& c3) const {
  if (impl_->triangles.empty()) return false;
  return impl_->tree.do_intersect(K::Tetrahedron_3(pt(apex), pt(c0), pt(c1), pt(c2))) ||
         impl_->tree.do_intersect(K::Tetrahedron_3(pt(apex), pt(c0), pt(c2), pt(c3)));
}

MeshView view_mesh(const TriangleSoup& mesh, const Scene& scene, int n, const Exec& exec) {
  if (n < 1 || n > 16) {
    throw SettingError("rays per pixel side must be in 1..16, got " + std::to_string(n));
  }
  NearestScope nearest;
  const CameraFrame frame(scene.camera, scene.width, scene.height);
  MeshView view;
  view.width = scene.width;
  view.height = scene.height;
  view.coverage.assign(std::size_t(view.width) * std::size_t(view.height), 0.0f);
  view.any.assign(view.coverage.size(), 0);
  const MeshRaycaster caster(mesh);
  // The beams reach beyond the farthest point of the mesh.
  double far = 0;
  for (const Vec3& p : mesh.vertices) far = std::max(far, dot(p - frame.eye, frame.forward));
  far = 1.01 * far + 1e-9;
  ProgressPhase phase(exec.progress, "compare: cast mesh", std::uint64_t(view.height));
  exec.run([&] {
    tbb::parallel_for(0, view.height, [&](int y) {
      if (phase.cancelled()) throw Error("compare: cancelled");
      NearestScope nearest_here;  // TBB threads have their own FPU state
      for (int x = 0; x < view.width; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(view.width) + std::size_t(x);
        if (far <= 0) continue;
        auto corner = [&](double u, double v) { return frame.eye + far * frame.dir(u, v); };
        if (!caster.pyramid_hits(frame.eye, corner(x, y), corner(x + 1, y), corner(x + 1, y + 1),
                                 corner(x, y + 1))) {
          continue;
        }
        view.any[i] = 1;
        int hit = 0;
        for (int j = 0; j < n; ++j) {
          for (int k = 0; k < n; ++k) {
            hit += caster.hits(frame.eye, frame.dir(x + (k + 0.5) / n, y + (j + 0.5) / n));
          }
        }
        view.coverage[i] = float(hit) / float(n * n);
      }
      phase.advance(1);
    });
  });
  return view;
}

}  // namespace iaa
