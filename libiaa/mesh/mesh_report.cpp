// Mesh statistics; see mesh_report.h.
#include "mesh/mesh_report.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "core/interval.h"
#include "expr/eval_point.h"

namespace iaa {

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Locational code (leading 1, then x y z bits per level) of the cell at `depth` holding index.
std::uint64_t code_of(int depth, std::uint64_t ix, std::uint64_t iy, std::uint64_t iz) {
  std::uint64_t c = 1;
  for (int l = depth - 1; l >= 0; --l) {
    c = (c << 3) | (((ix >> l) & 1) << 2) | (((iy >> l) & 1) << 1) | ((iz >> l) & 1);
  }
  return c;
}

}  // namespace

void check_mesh(const TriangleSoup& mesh, const std::string& what) {
  if (mesh.triangles.empty()) throw Error(what + ": the mesh has no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& p = mesh.vertices[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error(what + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.vertices.size()) {
        throw Error(what + ": triangle " + std::to_string(t) + " refers to vertex " +
                    std::to_string(v) + " of " + std::to_string(mesh.vertices.size()));
      }
    }
  }
}

MeshReport analyze_mesh(const TriangleSoup& mesh, const Tape* tape, const Enclosure* enclosure,
                        CoordinatePrecision precision) {
  MeshReport r;
  const std::size_t nv = mesh.vertices.size();
  r.triangles = mesh.triangles.size();

  // Edges: (min, max, direction) for each triangle side, sorted so equal edges are adjacent.
  struct HalfEdge {
    std::uint32_t a, b;
    bool forward;
    bool operator<(const HalfEdge& o) const { return a != o.a ? a < o.a : b < o.b; }
  };
  std::vector<HalfEdge> he;
  he.reserve(3 * mesh.triangles.size());
  std::vector<bool> used(nv, false);
  std::vector<std::uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++r.degenerate_triangles;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      used[a] = true;
      if (a == b) continue;
      he.push_back({std::min(a, b), std::max(a, b), a < b});
      const std::uint32_t ra = find_root(parent, a), rb = find_root(parent, b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  // Components, numbered in the order of their smallest vertex: a union's root is the smaller
  // of the two, so a component's root is its smallest vertex.
  std::vector<std::uint32_t> component(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!used[v]) {
      ++r.unused_vertices;
      continue;
    }
    const std::uint32_t root = find_root(parent, static_cast<std::uint32_t>(v));
    if (root == v) {
      component[v] = static_cast<std::uint32_t>(r.component_topology.size());
      r.component_topology.emplace_back();
    } else {
      component[v] = component[root];
    }
    ++r.component_topology[component[v]].vertices;
  }
  for (const auto& t : mesh.triangles) ++r.component_topology[component[t[0]]].triangles;
  std::sort(he.begin(), he.end());
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i;
    while (j < he.size() && he[j].a == he[i].a && he[j].b == he[i].b) ++j;
    const std::size_t n = j - i;
    ComponentTopology& c = r.component_topology[component[he[i].a]];
    ++c.edges;
    if (n == 1) ++c.boundary_edges;
    if (n >= 3) ++c.nonmanifold_edges;
    if (n == 2 && he[i].forward == he[i + 1].forward) ++c.inconsistent_edges;
    i = j;
  }
  for (ComponentTopology& c : r.component_topology) {
    c.euler = std::int64_t(c.vertices) - std::int64_t(c.edges) + std::int64_t(c.triangles);
    const bool closed_oriented =
        c.boundary_edges == 0 && c.nonmanifold_edges == 0 && c.inconsistent_edges == 0;
    c.genus = closed_oriented && c.euler % 2 == 0 && c.euler <= 2 ? (2 - c.euler) / 2 : -1;
    r.vertices += c.vertices;
    r.edges += c.edges;
    r.boundary_edges += c.boundary_edges;
    r.nonmanifold_edges += c.nonmanifold_edges;
    r.inconsistent_edges += c.inconsistent_edges;
  }
  r.components = r.component_topology.size();
  r.euler = std::int64_t(r.vertices) - std::int64_t(r.edges) + std::int64_t(r.triangles);

  // Area and signed volume in round-to-nearest, whatever the caller's rounding mode.
  NearestScope nearest;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    r.area += 0.5 * length(cross(b - a, c - a));
    r.volume += dot(a, cross(b, c)) / 6.0;
  }
  if (tape) {
    PointEval pe(*tape);
    for (std::size_t v = 0; v < nv; ++v) {
      if (!used[v]) continue;
      const double f = pe.eval(mesh.vertices[v]);
      if (!std::isfinite(f)) {
        ++r.undefined_vertices;
      } else {
        r.max_abs_f = std::max(r.max_abs_f, std::fabs(f));
      }
    }
  }
  if (enclosure) {
    std::vector<std::uint64_t> leaves;
    std::vector<bool> depth_used(64, false);
    leaves.reserve(enclosure->cells.size());
    for (const Cell& c : enclosure->cells) {
      leaves.push_back(code_of(c.depth, c.index[0], c.index[1], c.index[2]));
      depth_used[c.depth] = true;
    }
    std::sort(leaves.begin(), leaves.end());
    const Box3& B = enclosure->bounds;
    std::int64_t outside = 0;
    for (std::size_t v = 0; v < nv; ++v) {
      if (!used[v]) continue;
      const Vec3 p = mesh.vertices[v];
      bool inside = false;
      for (int d = 0; d < 64 && !inside; ++d) {
        if (!depth_used[std::size_t(d)]) continue;
        const double n = std::ldexp(1.0, d);
        std::int64_t lo[3], hi[3];
        bool in_bounds = true;
        for (int a = 0; a < 3; ++a) {
          const double size = B.hi[a] - B.lo[a];
          // See CoordinatePrecision: arithmetic slack, plus the float rounding of the stored
          // coordinate when the mesh came from a float file.
          double tol = 1e-9 * size;
          if (precision == CoordinatePrecision::kFloat)
            tol += std::ldexp(std::fabs(p[a]), -24) + std::ldexp(1.0, -150);
          const double u0 = (p[a] - tol - B.lo[a]) / size * n,
                       u1 = (p[a] + tol - B.lo[a]) / size * n;
          lo[a] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor(u0)));
          hi[a] = std::min<std::int64_t>(static_cast<std::int64_t>(n) - 1,
                                         static_cast<std::int64_t>(std::floor(u1)));
          if (!(u1 >= 0 && u0 <= n) || lo[a] > hi[a]) in_bounds = false;
        }
        if (!in_bounds) continue;
        for (std::int64_t x = lo[0]; x <= hi[0] && !inside; ++x) {
          for (std::int64_t y = lo[1]; y <= hi[1] && !inside; ++y) {
            for (std::int64_t z = lo[2]; z <= hi[2] && !inside; ++z) {
              inside = std::binary_search(
                  leaves.begin(), leaves.end(),
                  code_of(d, std::uint64_t(x), std::uint64_t(y), std::uint64_t(z)));
            }
          }
        }
      }
      if (!inside) ++outside;
    }
    r.outside_enclosure = outside;
  }
  return r;
}

}  // namespace iaa
