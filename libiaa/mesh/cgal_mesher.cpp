// CGAL Mesh_3 over our point evaluator; see cgal_mesher.h. This is the only Mesh_3 translation
// unit (each costs ~60 s and ~4 GB to compile).
#include "mesh/cgal_mesher.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/make_mesh_3.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "core/error.h"
#include "core/interval.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"

namespace iaa {

void CgalMeshSettings::validate() const {
  if (!bounds.valid() ||
      !(bounds.lo.x < bounds.hi.x && bounds.lo.y < bounds.hi.y && bounds.lo.z < bounds.hi.z)) {
    throw SettingError("cgal mesh: the bounds must be a finite box with positive extent");
  }
  if (!(facet_angle >= 0 && facet_angle <= 30)) {
    throw SettingError("cgal mesh: facet angle must be in [0, 30] degrees, got " +
                       std::to_string(facet_angle));
  }
  if (!(facet_size > 0) || !std::isfinite(facet_size)) {
    throw SettingError("cgal mesh: facet size must be a positive length, got " +
                       std::to_string(facet_size));
  }
  if (!(facet_distance > 0) || !std::isfinite(facet_distance)) {
    throw SettingError("cgal mesh: facet distance must be a positive length, got " +
                       std::to_string(facet_distance));
  }
  if (!(relative_error >= 1e-12 && relative_error <= 1e-2)) {
    throw SettingError("cgal mesh: relative error must be in [1e-12, 1e-2], got " +
                       std::to_string(relative_error));
  }
}

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using FT = K::FT;
using Point = K::Point_3;
using Function = std::function<FT(const Point&)>;
using MeshDomain = CGAL::Labeled_mesh_domain_3<K>;
#ifdef CGAL_LINKED_WITH_TBB
using Concurrency = CGAL::Parallel_tag;
#else
using Concurrency = CGAL::Sequential_tag;
#endif
using Tr = CGAL::Mesh_triangulation_3<MeshDomain, CGAL::Default, Concurrency>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// Each call of mesh_cgal() has its own number: the per-thread evaluators below are rebuilt when it
// changes (a tape's address alone could be reused by a later tape).
std::atomic<std::uint64_t> g_next_run{1};

// f bounded by the box: negative exactly where f < 0 inside the bounds. Mesh_3 calls it from TBB
// workers, so each thread keeps its own evaluator (evaluators own scratch space).
struct BoundedFunction {
  const Tape* tape;
  Box3 box;
  std::uint64_t run;
  FT operator()(const Point& p) const {
    thread_local std::uint64_t cached = 0;
    thread_local std::unique_ptr<PointEval> pe;
    if (cached != run || !pe) {
      pe = std::make_unique<PointEval>(*tape);
      cached = run;
    }
    double out = 0;
    for (int a = 0; a < 3; ++a) out = std::max({out, box.lo[a] - p[a], p[a] - box.hi[a]});
    if (out > 0) return 1 + out;
    const double f = pe->eval(p.x(), p.y(), p.z());
    return std::isfinite(f) ? f : 1.0;  // undefined: outside the domain
  }
};

// Facet size as a field: the requested size on f = 0, but as large as the bounds on their own
// faces (where a surface Delaunay ball's centre lies on a bounds plane and f is not 0), so that
// Mesh_3 does not spend its time on the cut of the domain, which is thrown away afterwards.
struct SizeField {
  Box3 box;
  double size, coarse, tol;
  const Tape* tape;
  std::uint64_t run;
  template <class Index>
  FT operator()(const Point& p, int, const Index&) const {
    for (int a = 0; a < 3; ++a) {
      if (std::fabs(p[a] - box.lo[a]) < tol || std::fabs(p[a] - box.hi[a]) < tol) {
        return on_surface(p) ? size : coarse;
      }
    }
    return size;
  }
  bool on_surface(const Point& p) const;
};

// True when f vanishes at p up to the position error of Mesh_3's surface search.
bool near_zero(const Tape& tape, std::uint64_t run, const Vec3& p, double tol) {
  thread_local std::uint64_t cached = 0;
  thread_local std::unique_ptr<PointGradEval> pg;
  if (cached != run || !pg) {
    pg = std::make_unique<PointGradEval>(tape);
    cached = run;
  }
  const PGrad g = pg->eval(p);
  return std::isfinite(g.v) && std::fabs(g.v) <= length(g.g) * tol;
}

bool SizeField::on_surface(const Point& p) const {
  return near_zero(*tape, run, {p.x(), p.y(), p.z()}, 100 * tol);
}

}  // namespace

TriangleSoup mesh_cgal(const Tape& tape, const CgalMeshSettings& s, const Exec& exec,
                       CgalMeshStats* stats) {
  s.validate();
  NearestScope nearest;
  const std::uint64_t run = g_next_run++;
  const Box3& b = s.bounds;
  const Vec3 c = b.center(), half = 0.5 * b.size();
  const double r2 = 1.0001 * dot(half, half) + 1e-300;
  namespace params = CGAL::parameters;
  MeshDomain domain = MeshDomain::create_implicit_mesh_domain(
      Function(BoundedFunction{&tape, b, run}), K::Sphere_3(Point(c.x, c.y, c.z), r2),
      params::relative_error_bound = s.relative_error);
  // A surface mesh only: no cell criterion at all, so Mesh_3 does not refine the volume (cell
  // shape criteria cost time and leave the surface facets as they are; docs/mesh.md).
  const double diag = length(b.size());
  const double pos_tol = std::max(1e-9, 10 * s.relative_error) * diag;
  const SizeField size_field{b, s.facet_size, 0.25 * diag, pos_tol, &tape, run};
  Criteria criteria(params::facet_angle = s.facet_angle, params::facet_size = size_field,
                    params::facet_distance = s.facet_distance);
  C3t3 c3t3;
  // Mesh_3's parallel refinement locks the cells of a grid over the bounding box before it
  // changes the triangulation there; retries of failed locks cost more than the locks, so the
  // grid is finer than CGAL's default (the measurements are in docs/mesh.md, under `iaa bench
  // mesh`). The setting is CGAL's process-wide singleton, set once.
  static std::once_flag lock_grid_once;
  std::call_once(lock_grid_once,
                 [] { Concurrent_mesher_config::get().locking_grid_num_cells_per_axis = 100; });
  exec.run([&] {
    // Parallel Mesh_3 puts pseudo-infinite vertices at random points of a far sphere, drawn from
    // CGAL's default generator, which is seeded with the time of day (one per thread): meshes
    // then differed from run to run even on one thread (seen: 1 run in 60 of the teardrop at
    // 200x200 covered one more pixel). A fixed seed on the thread that meshes makes one thread's
    // mesh the same in every run on a machine (their number is per hardware thread, so machines
    // with other core counts mesh differently); with more threads their timing still decides.
    // The thread's own generator is put back afterwards.
    CGAL::Random& shared = CGAL::get_default_random();
    const CGAL::Random saved = shared;
    shared = CGAL::Random(0);
    try {
      c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, params::no_perturb(), params::no_exude());
    } catch (...) {
      shared = saved;
      throw;
    }
    shared = saved;
  });

  TriangleSoup soup;
  std::unordered_map<const void*, std::uint32_t> index;
  auto vertex = [&](Tr::Vertex_handle v) {
    const auto [it, fresh] = index.emplace(&*v, static_cast<std::uint32_t>(soup.vertices.size()));
    if (fresh) {
      const auto& p = v->point();
      soup.vertices.push_back(
          {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    return it->second;
  };
  std::uint64_t facets = 0, on_bounds = 0;
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    ++facets;
    Tr::Cell_handle cell = f->first;
    int i = f->second;
    // Orient away from the inside cell's opposite vertex: outwards of {f < 0}, towards larger f.
    if (!c3t3.is_in_complex(cell)) {
      const Tr::Cell_handle n = cell->neighbor(i);
      i = n->index(cell);
      cell = n;
    }
    std::array<Tr::Vertex_handle, 3> v{cell->vertex((i + 1) & 3), cell->vertex((i + 2) & 3),
                                       cell->vertex((i + 3) & 3)};
    std::array<Vec3, 3> p;
    for (int k = 0; k < 3; ++k) {
      const auto& q = v[std::size_t(k)]->point();
      p[std::size_t(k)] = {CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())};
    }
    // A facet of the domain's cut by the bounds has a vertex where f is not 0.
    bool bound_facet = false;
    for (int k = 0; k < 3 && !bound_facet; ++k)
      bound_facet = !near_zero(tape, run, p[std::size_t(k)], pos_tol);
    if (bound_facet) {
      ++on_bounds;
      continue;
    }
    const auto& o = cell->vertex(i)->point();
    const Vec3 opp{CGAL::to_double(o.x()), CGAL::to_double(o.y()), CGAL::to_double(o.z())};
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    if (dot(n, p[0] - opp) < 0) std::swap(v[1], v[2]);
    soup.triangles.push_back({vertex(v[0]), vertex(v[1]), vertex(v[2])});
  }
  if (stats) {
    stats->facets = facets;
    stats->bound_facets = on_bounds;
  }
  return soup;
}

}  // namespace iaa
