// Cubical marching squares over the enclosure's leaves; see octree_mesher.h for the method and
// its guarantees. The grid is the finest level L of the enclosure: every leaf corner is an integer
// point in [0, 2^L]^3. Points are kept in three sorted arrays, one per axis, whose keys put the
// coordinate along that axis in the lowest bits, so the points on any grid line are contiguous and
// ordered: the corners of all leaves that touch an edge are found with two binary searches, and
// an elementary grid edge is named by its axis and position in that array.
#include "mesh/octree_mesher.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "core/error.h"
#include "expr/eval_interval.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "mesh/radix_sort.h"

namespace iaa {

void OctreeMeshSettings::validate() const {
  enclose.validate();
  if (enclose.depth + enclose.refine_possible > kMaxLevel) {
    throw SettingError("octree mesh: depth + refine (" + std::to_string(enclose.depth) + " + " +
                       std::to_string(enclose.refine_possible) + ") must be at most " +
                       std::to_string(kMaxLevel));
  }
  if (edge_steps < 0 || edge_steps > 60) {
    throw SettingError("octree mesh: edge_steps must be in 0..60, got " +
                       std::to_string(edge_steps));
  }
  if (centre_steps < 0 || centre_steps > 20) {
    throw SettingError("octree mesh: centre_steps must be in 0..20, got " +
                       std::to_string(centre_steps));
  }
  if (!(flat_tolerance >= 0 && flat_tolerance <= 1)) {
    throw SettingError("octree mesh: flat_tolerance must be in 0..1 (of the leaf's edge), got " +
                       std::to_string(flat_tolerance));
  }
}

namespace {

using U64 = std::uint64_t;
constexpr int kBits = 21;
constexpr U64 kMask = (U64{1} << kBits) - 1;
constexpr U64 kCentreFlag = U64{1} << 63;
constexpr std::size_t kChunk = 512;

using IPoint = std::array<U64, 3>;

// Key of a grid point for the array of `axis`: the two other coordinates, then the one along axis.
inline U64 line_key(int axis, const IPoint& p) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  return (p[b] << (2 * kBits)) | (p[c] << kBits) | p[axis];
}
inline IPoint decode_key(int axis, U64 key) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  IPoint p{};
  p[axis] = key & kMask;
  p[c] = (key >> kBits) & kMask;
  p[b] = key >> (2 * kBits);
  return p;
}

// Locational code of an octree node: a leading 1, then 3 bits (x, y, z) per level.
inline U64 node_code(int depth, const std::array<std::uint32_t, 3>& idx) {
  U64 c = 1;
  for (int l = depth - 1; l >= 0; --l) {
    c = (c << 3) | (U64((idx[0] >> l) & 1) << 2) | (U64((idx[1] >> l) & 1) << 1) |
        U64((idx[2] >> l) & 1);
  }
  return c;
}

/// A sort key with a payload (the point's position in another array).
struct Keyed {
  U64 key;
  std::uint32_t value;
};
inline U64 key_of(U64 k) {
  return k;
}
inline U64 key_of(const Keyed& k) {
  return k.key;
}

/// Sorts v by key, ascending (radix_sort.h: the result does not depend on the thread count).
template <class T>
void sort_keys(std::vector<T>& v) {
  detail::radix_sort(v.data(), v.size(), [](const T& e) { return key_of(e); });
}

/// Open-addressing map from a 63-bit key to a 32-bit value, filled in parallel (distinct keys,
/// compare-and-swap on the key), then read-only. Lookups are what the extraction does per leaf
/// corner: one probe sequence instead of a binary search over millions of points.
class KeyTable {
 public:
  void build(std::size_t n, const std::function<U64(std::size_t)>& key) {
    std::size_t size = 16;
    while (size < 2 * n) size *= 2;
    mask_ = size - 1;
    keys_ = std::vector<std::atomic<U64>>(size);
    values_.assign(size, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, size, 1 << 14), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i)
        keys_[i].store(kEmpty, std::memory_order_relaxed);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
      for (std::size_t j = r.begin(); j < r.end(); ++j) {
        const U64 k = key(j);
        for (std::size_t i = hash(k);; i = (i + 1) & mask_) {
          U64 expected = kEmpty;
          if (keys_[i].compare_exchange_strong(expected, k, std::memory_order_relaxed)) {
            values_[i] = static_cast<std::uint32_t>(j);
            break;
          }
        }
      }
    });
  }
  /// The value of key k, or kMissing.
  std::uint32_t find(U64 k) const {
    for (std::size_t i = hash(k);; i = (i + 1) & mask_) {
      const U64 s = keys_[i].load(std::memory_order_relaxed);
      if (s == k) return values_[i];
      if (s == kEmpty) return kMissing;
    }
  }
  static constexpr std::uint32_t kMissing = 0xffffffffu;

 private:
  static constexpr U64 kEmpty = ~U64{0};
  std::size_t hash(U64 k) const {
    k *= 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(k ^ (k >> 29)) & mask_;
  }
  std::size_t mask_ = 0;
  std::vector<std::atomic<U64>> keys_;
  std::vector<std::uint32_t> values_;
};

struct Grid {
  int level = 0;
  Box3 bounds;
  // Per axis: sorted entries (line_key << 1) | negative.
  std::array<std::vector<U64>, 3> lines;
  std::vector<U64> internal;  // sorted codes of nodes that have leaves below them
  KeyTable point_table;       // line_key(2, p) -> position of p in lines[2]
  KeyTable internal_table;    // code -> 0 for the codes of `internal`
  // Position in lines[0] and lines[1] of the point at position i of lines[2].
  std::array<std::vector<std::uint32_t>, 2> pos_in;

  Vec3 position(const IPoint& p) const {  // call inside a NearestScope
    const double n = std::ldexp(1.0, level);
    Vec3 r;
    for (int a = 0; a < 3; ++a) {
      const U64 i = p[a];
      r[a] = i == (U64{1} << level)
                 ? bounds.hi[a]
                 : bounds.lo[a] + (bounds.hi[a] - bounds.lo[a]) * (static_cast<double>(i) / n);
    }
    return r;
  }
  // Position of p in the array of axis; p must be a grid point.
  std::size_t find(int axis, const IPoint& p) const {
    const std::uint32_t zi = point_table.find(line_key(2, p));
    IAA_CHECK(zi != KeyTable::kMissing);
    return axis == 2 ? zi : pos_in[static_cast<std::size_t>(axis)][zi];
  }
  bool negative(int axis, std::size_t pos) const {
    return lines[static_cast<std::size_t>(axis)][pos] & 1;
  }
  bool is_internal(U64 code) const { return internal_table.find(code) != KeyTable::kMissing; }
};

// A crossing seen while walking a polygon: the grid edge it lies on, and whether the walk enters
// the negative region there.
struct Crossing {
  U64 edge;
  bool enters_negative;
};

struct Centre {
  std::uint32_t leaf;
  std::uint32_t first, count;  // into the block's loop_refs
  /// A loop of 3 or 4 is triangulated flat (its triangles at this index of the block's tris) and
  /// gets the centre only where the surface bulges away from them; longer loops always get it.
  static constexpr std::uint32_t kAlways = 0xffffffffu;
  std::uint32_t flat = kAlways;
};

// Output of one block of leaves.
struct Block {
  std::vector<std::array<U64, 3>> tris;  // refs: edge ids, or kCentreFlag | local centre index
  std::vector<std::uint32_t> quads;      // tris[i], tris[i + 1] split a 4-loop along p0-p2
  // Filled when vertices are placed: each centre's position, and its vertex number (kNoVertex
  // for the centre of a loop that stays flat; kPending until the used centres are numbered).
  static constexpr std::uint32_t kNoVertex = 0xffffffffu, kPending = 0xfffffffeu;
  std::vector<Vec3> centre_pos;
  std::vector<std::uint32_t> centre_vertex;
  std::vector<Centre> centres;
  std::vector<U64> loop_refs;
  std::vector<std::uint32_t> unmeshed;  // leaves with no loop
  std::uint64_t open_chains = 0;
};

inline U64 edge_id(int axis, std::size_t pos) {
  return (U64(axis) << 40) | U64(pos);
}

class Extractor {
 public:
  Extractor(const Grid& g, const Enclosure& e) : g_(g), e_(e) {}

  void leaf(std::uint32_t li, Block& out) {
    const Cell& c = e_.cells[li];
    const int k = c.depth;
    const U64 s = U64{1} << (g_.level - k);
    const IPoint o{U64(c.index[0]) * s, U64(c.index[1]) * s, U64(c.index[2]) * s};
    origin_ = o;
    size_ = s;
    // The positions of the 8 corners in the three arrays, looked up all at once: independent
    // table reads whose cache misses overlap, where looking them up as the walk needs them would
    // wait for each in turn.
    std::uint32_t zi[8];
    for (int k = 0; k < 8; ++k) {
      const IPoint p{o[0] + ((k & 1) ? s : 0), o[1] + ((k & 2) ? s : 0), o[2] + ((k & 4) ? s : 0)};
      zi[k] = g_.point_table.find(line_key(2, p));
      IAA_CHECK(zi[k] != KeyTable::kMissing);
    }
    for (int k = 0; k < 8; ++k) {
      cached_[std::size_t(3 * k)] = g_.pos_in[0][zi[k]];
      cached_[std::size_t(3 * k + 1)] = g_.pos_in[1][zi[k]];
      cached_[std::size_t(3 * k + 2)] = zi[k];
    }
    segs_.clear();
    for (int a = 0; a < 3; ++a) {
      for (int side = 0; side < 2; ++side) {
        squares_.clear();
        const std::int64_t ni = std::int64_t(c.index[a]) + (side ? 1 : -1);
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        if (ni >= 0 && ni < (std::int64_t{1} << k)) {
          auto idx = c.index;
          idx[a] = static_cast<std::uint32_t>(ni);
          collect_squares(node_code(k, idx), a, side, o[u], o[v], s);
        } else {
          squares_.push_back({o[u], o[v], s});
        }
        const U64 w = o[a] + (side ? s : 0);
        for (const auto& q : squares_) polygon(a, side, w, q[0], q[1], q[2]);
      }
    }
    if (segs_.empty()) {
      out.unmeshed.push_back(li);
      return;
    }
    link(li, out);
  }

 private:
  // Sub-squares of a leaf face: the faces of the finer leaves on the other side.
  void collect_squares(U64 code, int a, int side, U64 u0, U64 v0, U64 size) {
    if (size == 1 || !g_.is_internal(code)) {
      squares_.push_back({u0, v0, size});
      return;
    }
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    const U64 h = size / 2;
    for (int bu = 0; bu < 2; ++bu) {
      for (int bv = 0; bv < 2; ++bv) {
        int bits[3];
        bits[a] = side ? 0 : 1;  // the half of the neighbour that touches our face
        bits[u] = bu;
        bits[v] = bv;
        const U64 child = (code << 3) | U64(bits[0] << 2 | bits[1] << 1 | bits[2]);
        collect_squares(child, a, side, u0 + U64(bu) * h, v0 + U64(bv) * h, h);
      }
    }
  }

  // Position of p in the array of axis t; the leaf's own corners are looked up once per leaf.
  std::size_t find(int t, const IPoint& p) {
    int k = 0;
    for (int a = 0; a < 3; ++a) {
      if (p[a] == origin_[a] + size_) {
        k |= 1 << a;
      } else if (p[a] != origin_[a]) {
        return g_.find(t, p);
      }
    }
    return cached_[std::size_t(3 * k + t)];
  }

  // Walks one side of a polygon from corner A to corner B (they differ along axis t).
  void walk(int t, const IPoint& A, const IPoint& B) {
    const std::size_t pa = find(t, A), pb = find(t, B);
    if (pa < pb) {
      for (std::size_t j = pa; j < pb; ++j) {
        const bool n0 = g_.negative(t, j), n1 = g_.negative(t, j + 1);
        if (n0 != n1) cross_.push_back({edge_id(t, j), n1});
      }
    } else {
      for (std::size_t j = pa; j > pb; --j) {
        const bool n0 = g_.negative(t, j), n1 = g_.negative(t, j - 1);
        if (n0 != n1) cross_.push_back({edge_id(t, j - 1), n1});
      }
    }
  }

  // One polygon of the leaf boundary, walked counter-clockwise around the outward normal; its
  // crossings are paired around each negative arc into segments oriented from the crossing that
  // enters the negative region to the one that leaves it.
  void polygon(int a, int side, U64 w, U64 u0, U64 v0, U64 q) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    auto pt = [&](U64 pu, U64 pv) {
      IPoint p{};
      p[a] = w;
      p[u] = pu;
      p[v] = pv;
      return p;
    };
    IPoint corner[4];
    if (side) {
      corner[0] = pt(u0, v0), corner[1] = pt(u0 + q, v0), corner[2] = pt(u0 + q, v0 + q),
      corner[3] = pt(u0, v0 + q);
    } else {
      corner[0] = pt(u0, v0), corner[1] = pt(u0, v0 + q), corner[2] = pt(u0 + q, v0 + q),
      corner[3] = pt(u0 + q, v0);
    }
    cross_.clear();
    for (int i = 0; i < 4; ++i) {
      const IPoint& A = corner[i];
      const IPoint& B = corner[(i + 1) % 4];
      walk(A[u] != B[u] ? u : v, A, B);
    }
    const std::size_t m = cross_.size();
    if (m == 0) return;
    IAA_CHECK(m % 2 == 0);
    std::size_t i0 = 0;
    while (!cross_[i0].enters_negative) ++i0;
    for (std::size_t i = 0; i < m; i += 2) {
      const Crossing& s = cross_[(i0 + i) % m];
      const Crossing& e = cross_[(i0 + i + 1) % m];
      IAA_CHECK(s.enters_negative && !e.enters_negative);
      segs_.push_back({s.edge, e.edge});
    }
  }

  // Links the leaf's segments into closed loops and triangulates each.
  void link(std::uint32_t li, Block& out) {
    std::sort(segs_.begin(), segs_.end());
    used_.assign(segs_.size(), false);
    for (std::size_t i0 = 0; i0 < segs_.size(); ++i0) {
      if (used_[i0]) continue;
      loop_.clear();
      std::size_t i = i0;
      bool closed = false;
      while (true) {
        used_[i] = true;
        loop_.push_back(segs_[i].first);
        const U64 next = segs_[i].second;
        if (next == segs_[i0].first) {
          closed = true;
          break;
        }
        const auto it = std::lower_bound(segs_.begin(), segs_.end(), std::pair<U64, U64>{next, 0});
        if (it == segs_.end() || it->first != next) break;
        i = static_cast<std::size_t>(it - segs_.begin());
        if (used_[i]) break;
      }
      if (!closed) {
        ++out.open_chains;
        continue;
      }
      const std::size_t n = loop_.size();
      if (n < 3) continue;  // a pinch: the neighbours' triangles meet along this segment directly
      const U64 centre = kCentreFlag | out.centres.size();
      out.centres.push_back(
          {li, static_cast<std::uint32_t>(out.loop_refs.size()), static_cast<std::uint32_t>(n)});
      for (std::size_t j = 0; j < n; ++j) out.loop_refs.push_back(loop_[j]);
      if (n <= 4) {  // flat: one triangle, or two (the shorter diagonal is chosen once placed)
        out.centres.back().flat = static_cast<std::uint32_t>(out.tris.size());
        if (n == 4) out.quads.push_back(static_cast<std::uint32_t>(out.tris.size()));
        out.tris.push_back({loop_[0], loop_[1], loop_[2]});
        if (n == 4) out.tris.push_back({loop_[0], loop_[2], loop_[3]});
        continue;
      }
      for (std::size_t j = 0; j < n; ++j)
        out.tris.push_back({centre, loop_[j], loop_[(j + 1) % n]});
    }
  }

  const Grid& g_;
  const Enclosure& e_;
  IPoint origin_{};
  U64 size_ = 0;
  std::array<std::size_t, 24> cached_{};
  std::vector<std::array<U64, 3>> squares_;
  std::vector<Crossing> cross_;
  std::vector<std::pair<U64, U64>> segs_;
  std::vector<bool> used_;
  std::vector<U64> loop_;
};

/// Regula falsi stops once an iterate moves less than this fraction of the edge: the mesh file
/// holds float coordinates, whose rounding moves a vertex by more (2^-24 of a coordinate is at
/// least 1e-5 of an edge at the default resolutions), so further steps would not change it.
constexpr double kEdgeTolerance = 1e-7;

// Places a crossing on its grid edge: regula falsi (Illinois) keeping the bracket.
Vec3 place_on_edge(PointEval& pe, Vec3 p0, Vec3 p1, int steps) {
  double f0 = pe.eval(p0), f1 = pe.eval(p1);
  if (!std::isfinite(f0) || !std::isfinite(f1) || (f0 < 0) == (f1 < 0) || f0 == 0 || f1 == 0) {
    if (f0 == 0 && std::isfinite(f1)) return p0;
    if (f1 == 0 && std::isfinite(f0)) return p1;
    return 0.5 * (p0 + p1);
  }
  double t0 = 0, t1 = 1;
  int last = 0;
  double best_t = f0 / (f0 - f1), best_f = INFINITY;
  double prev_t = best_t;
  for (int i = 0; i < steps; ++i) {
    double t = t0 + (t1 - t0) * f0 / (f0 - f1);
    if (!(t > t0 && t < t1)) t = 0.5 * (t0 + t1);
    const double f = pe.eval(p0 + t * (p1 - p0));
    if (!std::isfinite(f)) break;
    if (std::fabs(f) < best_f) best_f = std::fabs(f), best_t = t;
    if (f == 0) break;
    if (i > 0 && std::fabs(t - prev_t) < kEdgeTolerance) break;
    prev_t = t;
    if ((f < 0) == (f0 < 0)) {
      t0 = t, f0 = f;
      if (last == -1) f1 *= 0.5;
      last = -1;
    } else {
      t1 = t, f1 = f;
      if (last == 1) f0 *= 0.5;
      last = 1;
    }
  }
  if (steps == 0) best_t = std::clamp(best_t, 0.0, 1.0);
  const Vec3 lo = p0, d = p1 - p0;
  return lo + best_t * d;
}

}  // namespace

OctreeMesh extract_mesh(const Tape& tape, const Enclosure& enc, const OctreeMeshSettings& settings,
                        const Exec& exec) {
  OctreeMesh result;
  OctreeMeshStats& st = result.stats;
  const std::size_t n_leaves = enc.cells.size();
  st.leaves = n_leaves;
  st.evaluations = enc.evaluations;
  int level = 0;
  for (const Cell& c : enc.cells) {
    level = std::max(level, int(c.depth));
    (c.cls == CellClass::kCrossing ? st.crossing_leaves : st.possible_leaves) += 1;
  }
  if (level > OctreeMeshSettings::kMaxLevel) {
    throw SettingError("octree mesh: the enclosure's finest depth " + std::to_string(level) +
                       " exceeds the mesher's limit " +
                       std::to_string(OctreeMeshSettings::kMaxLevel));
  }
  st.finest_level = level;
  if (n_leaves == 0) return result;

  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  auto t0 = Clock::now();
  Grid g;
  g.level = level;
  g.bounds = enc.bounds;

  exec.run([&] {
    // Internal nodes: every proper ancestor of a leaf.
    std::vector<U64>& in = g.internal;
    for (const Cell& c : enc.cells) {
      U64 code = node_code(c.depth, c.index) >> 3;
      for (int d = c.depth - 1; d >= 0; --d, code >>= 3) in.push_back(code);
    }
    sort_keys(in);
    in.erase(std::unique(in.begin(), in.end()), in.end());
    g.internal_table.build(in.size(), [&](std::size_t j) { return in[j]; });

    // Grid points: the corners of every leaf, and of every child of an internal node at least as
    // deep as the shallowest leaf (empty children included: a leaf's face is cut into the faces
    // of the children of the same-depth node across it), sorted and unique (z-lines order = axis
    // 2 keys). Codes grow with depth, so those internal nodes are a suffix of `in`.
    // Corner keys carry the corner's proved sign in 2 low bits where the key leaves room (a key
    // has 21 bits per coordinate; at level <= 19 its top 2 bits are 0).
    const int sign_shift = level <= 19 ? 2 : 0;
    int min_depth = level;
    for (const Cell& c : enc.cells) min_depth = std::min(min_depth, int(c.depth));
    const std::size_t first = static_cast<std::size_t>(
        std::lower_bound(in.begin(), in.end(), U64{1} << (3 * min_depth)) - in.begin());
    const std::size_t n_split = in.size() - first;
    std::vector<U64> keys(8 * n_leaves + 27 * n_split);
    tbb::parallel_for(std::size_t{0}, n_split, [&](std::size_t i) {
      U64 code = in[first + i];
      int d = 0;
      while ((code >> (3 * (d + 1))) != 0) ++d;
      IPoint idx{0, 0, 0};
      for (int l = 0; l < d; ++l) {
        const U64 bits = (code >> (3 * l)) & 7;
        idx[0] |= ((bits >> 2) & 1) << l;
        idx[1] |= ((bits >> 1) & 1) << l;
        idx[2] |= (bits & 1) << l;
      }
      const U64 h = U64{1} << (level - d - 1);  // half the node's size
      for (int k = 0; k < 27; ++k) {
        const IPoint p{(2 * idx[0] + U64(k % 3)) * h, (2 * idx[1] + U64((k / 3) % 3)) * h,
                       (2 * idx[2] + U64(k / 9)) * h};
        keys[8 * n_leaves + 27 * i + std::size_t(k)] = line_key(2, p) << sign_shift;
      }
    });
    tbb::parallel_for(std::size_t{0}, n_leaves, [&](std::size_t i) {
      const Cell& c = enc.cells[i];
      const U64 s = U64{1} << (level - c.depth);
      for (int k = 0; k < 8; ++k) {
        const IPoint p{(U64(c.index[0]) + (k & 1)) * s, (U64(c.index[1]) + ((k >> 1) & 1)) * s,
                       (U64(c.index[2]) + ((k >> 2) & 1)) * s};
        const U64 known = sign_shift ? (c.corner_signs >> (2 * k)) & 3 : 0;
        keys[8 * i + std::size_t(k)] = (line_key(2, p) << sign_shift) | known;
      }
    });
    sort_keys(keys);
    // Unique points; a sign proved for a point by any leaf (they cannot disagree: both proofs
    // hold) is kept for it. known[i]: bit 0 f < 0 proved, bit 1 f > 0 proved.
    std::vector<std::uint8_t> known;
    {
      std::size_t np = 0;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        const U64 k = keys[i] >> sign_shift;
        const std::uint8_t bits = std::uint8_t(keys[i] & 3);
        if (np > 0 && keys[np - 1] == k) {
          known[np - 1] |= sign_shift ? bits : 0;
        } else {
          keys[np++] = k;
          known.push_back(sign_shift ? bits : 0);
        }
      }
      keys.resize(np);
    }
    const std::size_t np = keys.size();
    st.sample_points = np;

    // Certified signs: f at a point must be proved negative to count as negative (by a leaf of
    // the enclosure, else by the interval value on the point's degenerate box); anything
    // undecided (f = 0 up to rounding, undefined) counts as non-negative.
    {
      ProgressPhase phase(exec.progress, "mesh: signs", np);
      std::vector<U64>& z = g.lines[2];
      z.resize(np);
      std::atomic<std::uint64_t> uncertain{0};
      std::atomic<std::uint64_t> evaluated{0};
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, 4096), [&](const auto& r) {
        if (phase.cancelled()) throw Error("mesh: cancelled");
        IntervalEval ie(tape);
        std::vector<std::size_t> todo;  // points whose sign the enclosure did not prove
        std::vector<Vec3> pos;
        {
          NearestScope nearest;
          for (std::size_t i = r.begin(); i < r.end(); ++i) {
            z[i] = (keys[i] << 1) | U64(known[i] & 1);
            if (known[i]) continue;
            todo.push_back(i);
            pos.push_back(g.position(decode_key(2, keys[i])));
          }
        }
        std::uint64_t unc = 0;
        RoundingScope scope;
        for (std::size_t j = 0; j < todo.size(); ++j) {
          const Vec3& p = pos[j];
          const Interval v = ie.eval(IBox(Interval(p.x), Interval(p.y), Interval(p.z)));
          const bool neg = !ie.partial_domain() && v.certainly_negative();
          if (ie.partial_domain() || (!v.certainly_negative() && !v.certainly_positive())) ++unc;
          z[todo[j]] |= U64(neg);
        }
        uncertain += unc;
        evaluated += todo.size();
        phase.advance(r.size());
      });
      st.uncertain_points = uncertain;
      st.evaluations += evaluated;
      st.known_points = np - evaluated;
    }
    g.point_table.build(np, [&](std::size_t i) { return keys[i]; });
    for (int a = 0; a < 2; ++a) {
      // Sorted with each point's z position as payload, so that its position in this array
      // needs no lookup.
      std::vector<Keyed> kv(np);
      tbb::parallel_for(std::size_t{0}, np, [&](std::size_t i) {
        const U64 e = g.lines[2][i];
        kv[i] = {(line_key(a, decode_key(2, e >> 1)) << 1) | (e & 1),
                 static_cast<std::uint32_t>(i)};
      });
      sort_keys(kv);
      std::vector<U64>& v = g.lines[std::size_t(a)];
      v.resize(np);
      std::vector<std::uint32_t>& pos = g.pos_in[std::size_t(a)];
      pos.resize(np);
      tbb::parallel_for(std::size_t{0}, np, [&](std::size_t j) {
        v[j] = kv[j].key;
        pos[kv[j].value] = static_cast<std::uint32_t>(j);
      });
    }
    keys.clear();
    keys.shrink_to_fit();
  });

  st.seconds_signs = since(t0);
  t0 = Clock::now();
  // Loops and triangles, per block of leaves (blocks in leaf order: deterministic output).
  const std::size_t n_blocks = (n_leaves + kChunk - 1) / kChunk;
  std::vector<Block> blocks(n_blocks);
  {
    ProgressPhase phase(exec.progress, "mesh: extract", n_leaves);
    exec.run([&] {
      tbb::parallel_for(std::size_t{0}, n_blocks, [&](std::size_t b) {
        if (phase.cancelled()) throw Error("mesh: cancelled");
        Extractor ex(g, enc);
        const std::size_t end = std::min(n_leaves, (b + 1) * kChunk);
        for (std::size_t i = b * kChunk; i < end; ++i)
          ex.leaf(static_cast<std::uint32_t>(i), blocks[b]);
        phase.advance(end - b * kChunk);
      });
    });
  }

  st.seconds_extract = since(t0);
  t0 = Clock::now();
  // Vertices: every crossing edge used, in sorted order (axis, then position: marked in a byte
  // per grid edge, then collected in order), then the used loop centres in block order.
  std::array<std::vector<std::uint8_t>, 3> used_edge;
  for (int a = 0; a < 3; ++a) used_edge[std::size_t(a)].assign(g.lines[std::size_t(a)].size(), 0);
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, n_blocks, [&](std::size_t b) {
      for (const auto& t : blocks[b].tris) {
        for (U64 r : t) {
          if (!(r & kCentreFlag)) {
            std::atomic_ref<std::uint8_t>(used_edge[std::size_t(r >> 40)][r & ((U64{1} << 40) - 1)])
                .store(1, std::memory_order_relaxed);
          }
        }
      }
    });
  });
  std::vector<U64> edges;
  for (int a = 0; a < 3; ++a) {
    const auto& u = used_edge[std::size_t(a)];
    for (std::size_t j = 0; j < u.size(); ++j) {
      if (u[j]) edges.push_back(edge_id(a, j));
    }
  }
  used_edge = {};
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const Block& bl = blocks[b];
    st.open_chains += bl.open_chains;
    for (std::uint32_t li : bl.unmeshed) {
      const Cell& c = enc.cells[li];
      if (c.cls == CellClass::kPossible) {
        ++st.unmeshed_possible;
        result.unmeshed.push_back(c);
      } else {
        ++st.unmeshed_crossing;
      }
    }
  }
  st.meshed_leaves = n_leaves - st.unmeshed_possible - st.unmeshed_crossing;
  const std::size_t n_edge_vertices = edges.size();
  const Vec3 extent = enc.bounds.hi - enc.bounds.lo;
  const double min_extent = std::min({extent.x, extent.y, extent.z});
  std::size_t n_centres = 0;
  for (const Block& bl : blocks) n_centres += bl.centres.size();
  TriangleSoup& soup = result.soup;
  soup.vertices.resize(n_edge_vertices);
  {
    ProgressPhase phase(exec.progress, "mesh: vertices", n_edge_vertices + n_centres);
    exec.run([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_edge_vertices, 1024),
                        [&](const auto& r) {
                          NearestScope nearest;
                          PointEval pe(tape);
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                            const int axis = int(edges[i] >> 40);
                            const std::size_t pos = edges[i] & ((U64{1} << 40) - 1);
                            const auto& line = g.lines[std::size_t(axis)];
                            const Vec3 p0 = g.position(decode_key(axis, line[pos] >> 1));
                            const Vec3 p1 = g.position(decode_key(axis, line[pos + 1] >> 1));
                            soup.vertices[i] = place_on_edge(pe, p0, p1, settings.edge_steps);
                          }
                          phase.advance(r.size());
                        });
      // Vertex number of a crossing edge, by its axis and position: a direct table.
      std::array<std::vector<std::uint32_t>, 3> number;
      for (int a = 0; a < 3; ++a) number[std::size_t(a)].resize(g.lines[std::size_t(a)].size());
      tbb::parallel_for(std::size_t{0}, n_edge_vertices, [&](std::size_t i) {
        number[std::size_t(edges[i] >> 40)][edges[i] & ((U64{1} << 40) - 1)] =
            static_cast<std::uint32_t>(i);
      });
      auto vertex_of = [&](U64 r) -> std::size_t {
        return number[std::size_t(r >> 40)][r & ((U64{1} << 40) - 1)];
      };
      // Vertex number of crossing j (mod the loop's length) of a loop.
      auto loop_vertex = [&](const Block& bl, const Centre& c, std::uint32_t j) {
        return static_cast<std::uint32_t>(vertex_of(bl.loop_refs[c.first + j % c.count]));
      };
      tbb::parallel_for(std::size_t{0}, n_blocks, [&](std::size_t b) {
        NearestScope nearest;
        PointGradEval pg(tape);
        Block& bl = blocks[b];
        bl.centre_pos.resize(bl.centres.size());
        bl.centre_vertex.assign(bl.centres.size(), Block::kPending);
        for (std::size_t ci = 0; ci < bl.centres.size(); ++ci) {
          const Centre& c = bl.centres[ci];
          // The loop's centroid, and twice its vector area (relative to its first vertex, so
          // that it does not cancel far from the origin).
          const Vec3 v0 = soup.vertices[loop_vertex(bl, c, 0)];
          Vec3 p = v0, area{};
          for (std::uint32_t j = 1; j < c.count; ++j) {
            const Vec3 v = soup.vertices[loop_vertex(bl, c, j)];
            p = p + v;
            if (j + 1 < c.count) {
              area = area + cross(v - v0, soup.vertices[loop_vertex(bl, c, j + 1)] - v0);
            }
          }
          p = p / double(c.count);
          const Vec3 centroid = p;
          // The tolerance of a flat loop, from the leaf's shortest edge (to rounding).
          const double tol =
              settings.flat_tolerance * std::ldexp(min_extent, -int(enc.cells[c.leaf].depth));
          PGrad f = pg.eval(p);
          if (c.flat != Centre::kAlways && std::fabs(f.v) <= 0.5 * tol * std::sqrt(dot(f.g, f.g))) {
            // The first Newton step (usually the longest) would move less than half the
            // tolerance: the loop stays flat without pulling its centre.
            bl.centre_vertex[ci] = Block::kNoVertex;
            continue;
          }
          // Pull the centre onto the surface with Newton steps, staying inside its leaf.
          const Box3 box = enc.box(enc.cells[c.leaf]);
          for (int s = 0; s < settings.centre_steps && std::isfinite(f.v) && f.v != 0; ++s) {
            const double g2 = dot(f.g, f.g);
            if (!(g2 > 0) || !std::isfinite(g2)) break;
            Vec3 q = p - (f.v / g2) * f.g;
            for (int a = 0; a < 3; ++a) q[a] = std::clamp(q[a], box.lo[a], box.hi[a]);
            const PGrad fq = pg.eval(q);
            if (!(std::fabs(fq.v) < std::fabs(f.v))) break;
            p = q, f = fq;
          }
          bl.centre_pos[ci] = p;
          if (c.flat != Centre::kAlways) {
            // The flat loop stays flat unless the surface at the centre lies farther than
            // flat_tolerance (of the leaf's shortest edge) from the loop's mean plane, and every
            // triangle of the fan faces the way the loop does (Newton steps, clamped to the
            // leaf, can take the centre outside the loop's prism, where the fan would fold).
            const double a2 = dot(area, area);
            const double off = dot(p - centroid, area);
            bool bent = a2 > 0 && off * off > tol * tol * a2;
            for (std::uint32_t j = 0; bent && j < c.count; ++j) {
              const Vec3 v = soup.vertices[loop_vertex(bl, c, j)];
              const Vec3 w = soup.vertices[loop_vertex(bl, c, j + 1)];
              bent = dot(cross(v - p, w - p), area) > 0;
            }
            if (!bent) bl.centre_vertex[ci] = Block::kNoVertex;
          }
        }
        phase.advance(bl.centres.size());
      });
      // The used centres' vertices after the edge vertices, in block order.
      soup.vertices.resize(n_edge_vertices + n_centres);  // cut to the used ones below
      std::size_t next = n_edge_vertices;
      std::vector<std::size_t> tri_base(n_blocks + 1, 0);
      for (std::size_t b = 0; b < n_blocks; ++b) {
        Block& bl = blocks[b];
        std::size_t added = 0;  // a centred loop of n has n triangles where flat it had n - 2
        for (std::size_t ci = 0; ci < bl.centres.size(); ++ci) {
          if (bl.centre_vertex[ci] == Block::kNoVertex) continue;
          bl.centre_vertex[ci] = static_cast<std::uint32_t>(next);
          soup.vertices[next++] = bl.centre_pos[ci];
          if (bl.centres[ci].flat != Centre::kAlways) added += 2;
        }
        std::vector<Vec3>().swap(bl.centre_pos);
        st.bent_loops += added / 2;
        tri_base[b + 1] = tri_base[b] + bl.tris.size() + added;
      }
      soup.vertices.resize(next);
      // Triangles with final vertex numbers: the block's triangles in order, a centred flat
      // loop's fan (instead of its flat triangles) after them.
      soup.triangles.resize(tri_base[n_blocks]);
      tbb::parallel_for(std::size_t{0}, n_blocks, [&](std::size_t b) {
        const Block& bl = blocks[b];
        // The flat triangles that a fan replaces, and where each kept triangle went.
        std::vector<std::uint8_t> replaced(bl.tris.size(), 0);
        for (std::size_t ci = 0; ci < bl.centres.size(); ++ci) {
          const Centre& c = bl.centres[ci];
          if (bl.centre_vertex[ci] == Block::kNoVertex || c.flat == Centre::kAlways) continue;
          for (std::uint32_t t = 0; t + 2 < c.count; ++t) replaced[c.flat + t] = 1;
        }
        std::vector<std::uint32_t> placed(bl.tris.size());
        std::size_t out = tri_base[b];
        for (std::size_t t = 0; t < bl.tris.size(); ++t) {
          if (replaced[t]) continue;
          std::array<std::uint32_t, 3> tri{};
          for (int k = 0; k < 3; ++k) {
            const U64 r = bl.tris[t][std::size_t(k)];
            tri[std::size_t(k)] = (r & kCentreFlag) ? bl.centre_vertex[r & ~kCentreFlag]
                                                    : static_cast<std::uint32_t>(vertex_of(r));
          }
          placed[t] = static_cast<std::uint32_t>(out - tri_base[b]);
          soup.triangles[out++] = tri;
        }
        for (std::size_t ci = 0; ci < bl.centres.size(); ++ci) {
          const Centre& c = bl.centres[ci];
          if (bl.centre_vertex[ci] == Block::kNoVertex || c.flat == Centre::kAlways) continue;
          for (std::uint32_t j = 0; j < c.count; ++j) {
            soup.triangles[out++] = {bl.centre_vertex[ci], loop_vertex(bl, c, j),
                                     loop_vertex(bl, c, j + 1)};
          }
        }
        for (std::uint32_t q : bl.quads) {
          if (replaced[q]) continue;
          auto& t0 = soup.triangles[tri_base[b] + placed[q]];
          auto& t1 = soup.triangles[tri_base[b] + placed[q] + 1];
          const std::uint32_t p0 = t0[0], p1 = t0[1], p2 = t0[2], p3 = t1[2];
          const Vec3 d02 = soup.vertices[p2] - soup.vertices[p0];
          const Vec3 d13 = soup.vertices[p3] - soup.vertices[p1];
          if (dot(d13, d13) < dot(d02, d02)) {
            t0 = {p1, p2, p3};
            t1 = {p1, p3, p0};
          }
        }
      });
    });
  }
  st.seconds_vertices = since(t0);
  return result;
}

OctreeMesh mesh_octree(const Tape& tape, const OctreeMeshSettings& settings, const Exec& exec) {
  settings.validate();
  EncloseSettings es = settings.enclose;
  es.all_corner_signs = true;  // the grid's signs, most of them proved by the enclosure already
  const Enclosure enc = enclose(tape, es, exec);
  return extract_mesh(tape, enc, settings, exec);
}

}  // namespace iaa
