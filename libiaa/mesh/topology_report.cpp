// Per-component topology; see topology_report.h.
#include "mesh/topology_report.h"

#include <algorithm>
#include <numeric>
#include <utility>

namespace iaa {

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

TopologyReport analyze_topology(const TriangleSoup& mesh) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<bool> used(nv, false);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      used[a] = true;
      if (a == b) continue;
      edges.emplace_back(std::min(a, b), std::max(a, b));
      const std::uint32_t ra = find_root(parent, a), rb = find_root(parent, b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  // Component number of each root, in order of the smallest vertex.
  std::vector<std::int64_t> id(nv, -1);
  TopologyReport r;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    const std::uint32_t root = find_root(parent, v);
    if (id[root] < 0) {
      id[root] = std::int64_t(r.components.size());
      r.components.emplace_back();
    }
    ++r.components[std::size_t(id[root])].vertices;
  }
  for (const auto& t : mesh.triangles) {
    ++r.components[std::size_t(id[find_root(parent, t[0])])].triangles;
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ComponentTopology& c = r.components[std::size_t(id[find_root(parent, edges[i].first)])];
    ++c.edges;
    if (j - i == 1) ++c.boundary_edges;
    if (j - i > 2) ++c.nonmanifold_edges;
    i = j;
  }
  for (ComponentTopology& c : r.components) {
    c.euler = std::int64_t(c.vertices) - std::int64_t(c.edges) + std::int64_t(c.triangles);
    const bool closed = c.boundary_edges == 0 && c.nonmanifold_edges == 0;
    c.genus = closed && c.euler % 2 == 0 && c.euler <= 2 ? (2 - c.euler) / 2 : -1;
  }
  return r;
}

}  // namespace iaa
