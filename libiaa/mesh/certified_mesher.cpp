// The certified mesher (certified_mesher.h; the argument is in docs/mesh.md).
//
// Phases: (1) each root cell is refined on its own until its leaves are empty or pass the local
// certificate (f monotone along a direction; in strict mode also the tangential gradient of its 6
// faces and the derivative along its 12 edges); (2) all leaf corners go into one hash table with
// their signs; each non-empty leaf cuts its faces into the pieces its neighbours make, pairs the
// crossings of each piece, chains them into loops and fans each loop; a leaf whose pieces, loops
// or fan fail the global rules is split and phase (1) runs on its children. (2) repeats, for the
// new leaves and the leaves touching them only, until no leaf is split.
#include "mesh/certified_mesher.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "core/arena.h"
#include "core/big_allocator.h"
#include "core/error.h"
#include "core/spread.h"
#include "enclose/octree.h"
#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_interval_hess.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "mesh/radix_sort.h"

namespace iaa {

void CertifiedMeshSettings::validate() const {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(bounds.lo[a]) || !std::isfinite(bounds.hi[a]) ||
        !(bounds.lo[a] < bounds.hi[a])) {
      throw SettingError("certified mesh: every bounds range must be finite with LO < HI");
    }
  }
  if (max_roots_per_axis < 1 || max_roots_per_axis > 64) {
    throw SettingError("certified mesh: roots per axis must be in 1..64, got " +
                       std::to_string(max_roots_per_axis));
  }
  const int root_bits = static_cast<int>(std::ceil(std::log2(max_roots_per_axis)));
  const int deepest = kGridBits - root_bits;
  if (max_depth < 1 || max_depth > deepest) {
    throw SettingError("certified mesh: max depth must be in 1.." + std::to_string(deepest) +
                       " (fine grid of 2^" + std::to_string(kGridBits) + " per axis over up to " +
                       std::to_string(max_roots_per_axis) + " root cells), got " +
                       std::to_string(max_depth));
  }
  if (min_depth < 0 || min_depth > max_depth) {
    throw SettingError("certified mesh: min depth must be in 0..max depth (" +
                       std::to_string(max_depth) + "), got " + std::to_string(min_depth));
  }
  if (max_boxes < 1) throw SettingError("certified mesh: max boxes must be at least 1");
  if (edge_steps < 0 || edge_steps > 60 || centre_steps < 0 || centre_steps > 20) {
    throw SettingError("certified mesh: edge steps must be in 0..60 and centre steps in 0..20");
  }
}

namespace {

using Key = std::uint64_t;
using Index3 = std::array<std::uint32_t, 3>;
constexpr int kKeyBits = 20;

Key make_key(const Index3& p) {
  return Key(p[0]) | (Key(p[1]) << kKeyBits) | (Key(p[2]) << (2 * kKeyBits));
}
Index3 key_point(Key k) {
  const Key m = (Key{1} << kKeyBits) - 1;
  return {std::uint32_t(k & m), std::uint32_t((k >> kKeyBits) & m),
          std::uint32_t(k >> (2 * kKeyBits))};
}

enum class Kind : std::uint8_t { kEmpty, kCertified, kUncertified };

/// A leaf: its lowest corner on the fine grid, its depth below the root cells, and what phase 1
/// proved. `sign` is the sign of f on an empty leaf (+1, -1; 0 where f may be undefined).
struct Leaf {
  Index3 at;
  std::uint8_t depth;
  Kind kind;
  std::int8_t sign;
  /// 1 when a split for fidelity alone was undone (it left uncertified children): the leaf is
  /// not split for fidelity again.
  std::uint8_t keep = 0;
};
/// Millions of leaves on fine surfaces: their buffers use huge pages (core/big_allocator.h).
using Leaves = BigVector<Leaf>;

/// The fine grid: root cells per axis 2^root_bits[a], each split max_depth times.
struct Grid {
  Box3 bounds;
  std::array<int, 3> root_bits{};
  int max_depth = 0;

  std::uint32_t size(int depth) const { return std::uint32_t{1} << (max_depth - depth); }
  /// Grid line i of axis a; needs a RoundingScope (grid_coordinate_upward), so that every caller
  /// gets the same double for the same line.
  double coord(int a, std::uint64_t i) const {
    return grid_coordinate_upward(bounds.lo[a], bounds.hi[a], i, root_bits[a] + max_depth);
  }
  Vec3 point(const Index3& p) const { return {coord(0, p[0]), coord(1, p[1]), coord(2, p[2])}; }
  Box3 box(const Index3& at, std::uint32_t s) const {
    return {point(at), point({at[0] + s, at[1] + s, at[2] + s})};
  }
};

/// What the whole-face evaluation of face_ok proved about the face's edges: f has no zero on the
/// face, or is strictly monotone along axis k of the face (bit k).
struct FaceProof {
  bool tested = false;
  bool zero_free = false;
  unsigned monotone = 0;
  /// The edges of this face along `axis` need no proof of their own.
  bool covers(int axis) const { return tested && (zero_free || (monotone >> axis & 1u)); }
};

/// The face and edge proofs of locally_certified by the grid position of the face or edge, per
/// thread. Up to four cells share an edge and two share a face, and a proof depends on the face
/// or edge alone (its box, which the grid position fixes), so a neighbour's proof is taken as it
/// is: the mesh and the certificates are the same with or without this cache, only the count of
/// interval evaluations is lower. Direct-mapped: cells come depth-first, so neighbours follow
/// each other closely.
class ProofCache {
 public:
  struct Entry {
    Key corner = ~Key{0};   ///< the lowest grid corner of the face or edge (never all ones)
    std::uint8_t what = 0;  ///< depth | axis << 5 | (1 for an edge) << 7
    std::int8_t ok = 0;     ///< 1 proved, -1 refuted
    FaceProof proof;        ///< a face's
  };
  explicit ProofCache(bool enabled) : enabled_(enabled) {}
  /// The entry of (corner, what) when the cache holds it, else null.
  const Entry* find(Key corner, std::uint8_t what) {
    const Entry& e = slot(corner, what);
    return enabled_ && e.corner == corner && e.what == what ? &e : nullptr;
  }
  /// Keeps (corner, what)'s proof, in place of what its slot held.
  void keep(const Entry& entry) {
    if (enabled_) slot(entry.corner, entry.what) = entry;
  }
  static std::uint8_t what(int depth, int axis, bool edge) {
    return std::uint8_t(depth | axis << 5 | int(edge) << 7);
  }

 private:
  /// The slot where (corner, what) is or would go.
  Entry& slot(Key corner, std::uint8_t what) {
    const std::uint64_t h = (corner ^ (std::uint64_t(what) << 56)) * 0x9E3779B97F4A7C15ull;
    return entries_[h >> (64 - kBits)];
  }
  static constexpr int kBits = 12;
  bool enabled_;
  std::vector<Entry> entries_ = std::vector<Entry>(enabled_ ? std::size_t{1} << kBits : 1);
};

/// Per-thread evaluators.
struct Evaluators {
  Evaluators(const Tape& t, bool proof_cache)
      : proofs(proof_cache), f(t), batch(t), g(t), batch_g(t), p(t), pg(t), h(t) {
    partials.reserve(6);  // the evaluators keep their addresses
    for (int wanted = 1; wanted < 7; ++wanted) partials.emplace_back(t, detail::VarMask(wanted));
    const auto ins = t.instrs();
    for (int i = t.first_op(); i < t.size(); ++i) {
      const Op op = ins[std::size_t(i)].op;
      if (op == Op::kMin || op == Op::kMax) kinks.push_back(std::size_t(i));
    }
    quarters.reserve(3);
    halves.reserve(3);
    for (int a = 0; a < 3; ++a) {
      quarters.emplace_back(t, detail::VarMask(7 & ~(1 << a)));
      halves.emplace_back(t, detail::VarMask(1 << a));
    }
  }
  ProofCache proofs;
  IntervalEval f;
  /// The 8 children of a split cell: their values, and f at their centres (Refiner::refine()).
  BatchIntervalEval batch;
  IntervalGradEval g;
  /// The gradients of a cell's 8 children: tighten(), and the children that evaluate their own
  /// (Refiner::evaluate_children). The same doubles as `g`, box by box (no min/max choices are
  /// recorded, and the mesher specializes no tape).
  BatchIntervalGradEval batch_g;
  /// For faces and edges: index wanted - 1 computes only the partials along the axes in
  /// `wanted` (the axes a face or an edge extends along, the only ones their proofs read).
  std::vector<IntervalGradEval> partials;
  /// The 4 quarters of a piece of a face normal to axis a (quarters[a]) and the 2 halves of a
  /// piece of an edge along axis a (halves[a]), each in one batch, with the partials `partials`
  /// computes for them: the same doubles.
  std::vector<BatchIntervalGradEvalK<4>> quarters;
  std::vector<BatchIntervalGradEvalK<2>> halves;
  bool flat_partial = false;  ///< the last eval_flat_natural met domain trouble
  PointEval p;
  PointGradEval pg;
  /// The Hessian over a cell, for the centred form of its gradient (Refiner::centre_gradient).
  IntervalHessEval h;
  /// The tape's min and max instructions: where a cell does not decide one, f has a crease in it
  /// and its Hessian is unbounded (Refiner::centre_gradient).
  std::vector<std::size_t> kinks;
  std::uint64_t evaluations = 0;
  /// Leaves made by this thread and not yet added to the shared count (which they would make a
  /// contended cache line if added one by one).
  std::uint64_t pending_leaves = 0;
};
using ThreadEvaluators = tbb::enumerable_thread_specific<std::unique_ptr<Evaluators>>;

/// 0 is outside v: the box it encloses f over holds no point of the surface. Strict at both
/// ends: a box where f <= 0 may still touch f = 0 (a surface that never changes sign, such as
/// -(x^2 + y^2 + z^2 - 1)^2), and such a box is not empty but possible.
bool zero_free(const Interval& v) {
  return v.hi() < 0.0 || v.lo() > 0.0;
}

/// Coordinate a of the centre of b, the point the mean-value form expands around.
double centre(const IBox& b, int a) {
  return b[a].lo() == b[a].hi() ? b[a].lo()
                                : std::clamp(0.5 * (b[a].lo() + b[a].hi()), b[a].lo(), b[a].hi());
}

/// The value of f over `b` bounded twice, by the natural interval `g.v` and by the mean-value form
/// f(c) + G(b).(b - c) around b's centre c, intersected. The mean-value form's overestimation
/// shrinks with the square of the box's size, the natural interval's only linearly: near a
/// tangency between the surface and a grid plane only the former can prove a face free of zeros.
/// At kinks (min, max, abs) G holds every generalized gradient, for which the mean-value theorem
/// of Lipschitz functions (Lebourg) holds.
/// f(c) + G.(b - c) for the centre c of b and its value `fc` there.
Interval expand(const IBox& b, Interval fc, const std::array<Interval, 3>& g) {
  for (int a = 0; a < 3; ++a) {
    if (b[a].lo() != b[a].hi()) fc = fc + g[std::size_t(a)] * (b[a] - Interval(centre(b, a)));
  }
  return fc;
}

/// f at the centre of b, or nothing where f may be undefined there.
std::optional<Interval> centre_value(Evaluators& e, const IBox& b) {
  IBox point;
  for (int a = 0; a < 3; ++a) point[a] = Interval(centre(b, a));
  ++e.evaluations;
  const Interval v = e.f.eval(point);
  if (e.f.partial_domain()) return std::nullopt;
  return v;
}

Interval mean_value(Evaluators& e, const IBox& b, const IGrad& g) {
  const std::optional<Interval> fc = centre_value(e, b);
  return fc ? intersect(expand(b, *fc, g.g), g.v) : g.v;
}

/// Box b made degenerate along the axes in `flat` (bit a: axis a at lo).
IBox flat_box(const Box3& b, int flat) {
  IBox ib(b);
  for (int a = 0; a < 3; ++a) {
    if (flat & (1 << a)) ib[a] = Interval(b.lo[a]);
  }
  return ib;
}

/// The gradient evaluation of a box degenerate along the axes in `flat`, its value the natural
/// interval only (see tightened()). Only the partials along the other axes are computed (the
/// others are [0,0]): the proofs of faces and edges read no other, and the mean-value form over
/// the box needs none along its flat axes. `e.flat_partial` gets whether it met domain trouble.
IGrad eval_flat_natural(Evaluators& e, const Box3& b, int flat) {
  ++e.evaluations;
  IntervalGradEval& g = e.partials[std::size_t((7 & ~flat) - 1)];
  const IGrad r = g.eval(flat_box(b, flat));
  e.flat_partial = g.partial_domain();
  return r;
}

/// The value of `g` (eval_flat_natural of b, flat, without domain trouble) bounded by the
/// mean-value form as well, where the natural interval alone does not exclude 0.
Interval tightened(Evaluators& e, const Box3& b, int flat, const IGrad& g) {
  return zero_free(g.v) ? g.v : mean_value(e, flat_box(b, flat), g);
}

/// The gradient evaluation of a box degenerate along the axes in `flat`, with its value bounded
/// by the mean-value form as well.
IGrad eval_flat(Evaluators& e, const Box3& b, int flat) {
  IGrad g = eval_flat_natural(e, b, flat);
  if (e.flat_partial) return g;
  g.v = tightened(e, b, flat, g);
  return g;
}

/// A piece's eval_flat_natural, made in a batch with its siblings' before it is used (and counted
/// when it is), and whether it met domain trouble.
struct Evaluated {
  IGrad g;
  bool partial = false;
};

/// The natural evaluation of a proof's piece: `pre`, counted now, when it was batched; else
/// eval_flat_natural. False where it met domain trouble.
bool piece_grad(Evaluators& e, const Box3& piece, int flat, const Evaluated* pre, IGrad& g) {
  if (!pre) {
    g = eval_flat_natural(e, piece, flat);
    return !e.flat_partial;
  }
  ++e.evaluations;
  g = pre->g;
  return !pre->partial;
}

/// How many times a face or an edge whose whole-box test fails is halved along each of its axes
/// to prove it piece by piece (face_ok, edge_ok).
constexpr int kProofSplits = 2;

/// The pieces of a face or an edge that a proof left to be joined up: pieces of the finest split
/// on which f has no zero but may have a critical point (a vanishing derivative along an edge)
/// and that touch no side of the face (hold no end of the edge), and every piece found free of
/// zeros, through which they may reach one. Closed boxes, flat along the axes the face or edge is
/// flat along (`flat`, as for eval_flat).
///
/// Whether a piece is free of zeros matters only for joining when some piece is loose, and the
/// mean-value form that often decides it costs an evaluation of f: a piece whose natural interval
/// does not decide and whose zeros nothing else needs is added as *pending*, with its gradient
/// evaluation, and its mean-value form is evaluated by resolve() only when a loose piece must be
/// joined (most faces and edges have none). Which pieces are zero-free, and so what is proved, is
/// the same as when every piece's form is evaluated at once.
struct ProofPieces {
  /// Every piece of every level may be zero-free: 1 + 4 + ... + 4^kProofSplits of a face (an
  /// edge has fewer).
  static constexpr int kMax = ((4 << (2 * kProofSplits)) - 1) / 3;
  explicit ProofPieces(int flat_axes) : flat(flat_axes) {}
  int flat;
  std::array<Box3, kMax> box;
  std::array<bool, kMax> loose{};    ///< a piece that must reach the boundary
  std::array<bool, kMax> pending{};  ///< zero-free not decided yet (grad holds its evaluation)
  std::array<bool, kMax> absent{};   ///< resolved: not zero-free after all
  std::array<IGrad, kMax> grad;
  int n = 0;
  void add(const Box3& b, bool is_loose) {
    box[std::size_t(n)] = b;
    loose[std::size_t(n)] = is_loose;
    ++n;
  }
  /// Adds piece b, with its evaluation g, if it is zero-free (pending when undecided; `final`:
  /// g's value is tightened already, and decides).
  void add_maybe(const Box3& b, const IGrad& g, bool final) {
    if (final && !zero_free(g.v)) return;
    if (!zero_free(g.v)) {
      grad[std::size_t(n)] = g;
      pending[std::size_t(n)] = true;
    }
    add(b, false);
  }
  /// Decides the pending pieces: zero-free by the mean-value form, or absent.
  void resolve(Evaluators& e) {
    for (int i = 0; i < n; ++i) {
      const auto k = std::size_t(i);
      if (!pending[k]) continue;
      pending[k] = false;
      absent[k] = !zero_free(tightened(e, box[k], flat, grad[k]));
    }
  }
  bool any_loose() const {
    for (int i = 0; i < n; ++i) {
      if (loose[std::size_t(i)]) return true;
    }
    return false;
  }
  /// Every loose piece lies in one connected union of zero-free pieces with a piece that touches
  /// `whole`'s boundary (a side of the face, an end of the edge; along axes where `whole` is
  /// flat every piece is flat too and touches nothing new).
  bool joined(const Box3& whole) const {
    std::array<bool, kMax> reached{};
    std::array<int, kMax> stack{};
    int top = 0;
    auto on_boundary = [&](const Box3& b) {
      for (int a = 0; a < 3; ++a) {
        if (whole.lo[a] == whole.hi[a]) continue;
        if (b.lo[a] == whole.lo[a] || b.hi[a] == whole.hi[a]) return true;
      }
      return false;
    };
    auto touch = [](const Box3& p, const Box3& q) {
      for (int a = 0; a < 3; ++a) {
        if (p.lo[a] > q.hi[a] || q.lo[a] > p.hi[a]) return false;
      }
      return true;
    };
    for (int i = 0; i < n; ++i) {
      if (!absent[std::size_t(i)] && on_boundary(box[std::size_t(i)]))
        reached[std::size_t(i)] = true, stack[std::size_t(top++)] = i;
    }
    while (top > 0) {
      const int i = stack[std::size_t(--top)];
      for (int j = 0; j < n; ++j) {
        if (!reached[std::size_t(j)] && !absent[std::size_t(j)] &&
            touch(box[std::size_t(i)], box[std::size_t(j)])) {
          reached[std::size_t(j)] = true;
          stack[std::size_t(top++)] = j;
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      if (loose[std::size_t(i)] && !reached[std::size_t(i)]) return false;
    }
    return true;
  }
};

/// No double crossing on this piece of an edge: f is strictly monotone along it, or has no zero
/// on it and the piece holds an end of the edge (`ends`, bit 0 the lower end, bit 1 the upper), or
/// (loose, checked by ProofPieces::joined) has no zero and is joined to an end of the edge by
/// zero-free pieces. A double crossing surrounds a point where f's derivative along the edge
/// vanishes; the zero-free pieces joined to the piece holding that point would all lie between
/// the two crossings, away from both ends. Strict monotonicity holds pointwise, so pieces that
/// pass, covering the edge, prove it whole. False when a piece of the finest split is neither
/// monotone nor zero-free.
/// `known`: the whole edge's evaluation, its value tightened already (eval_flat); the pieces' are
/// tightened only where their zeros decide (ProofPieces).
/// `pre`: the piece's natural evaluation, batched with its sibling's.
bool edge_pieces(Evaluators& e, const Box3& piece, int axis, unsigned ends, int splits,
                 ProofPieces& zero_free_pieces, const IGrad* known = nullptr,
                 const Evaluated* pre = nullptr) {
  const int flat = 7 & ~(1 << axis);
  IGrad g;
  if (known) {
    g = *known;  // made without domain trouble
  } else if (!piece_grad(e, piece, flat, pre, g)) {
    return false;
  }
  if (!g.g[std::size_t(axis)].contains_zero()) {
    zero_free_pieces.add_maybe(piece, g, known);
    return true;
  }
  if (ends == 0 && splits > 0) {
    zero_free_pieces.add_maybe(piece, g, known);
  } else {
    const bool no_zero = zero_free(known ? g.v : tightened(e, piece, flat, g));
    if (no_zero) zero_free_pieces.add(piece, false);
    if (ends && no_zero) return true;
    if (splits == 0) {
      if (!no_zero) return false;
      zero_free_pieces.loose[std::size_t(zero_free_pieces.n - 1)] = true;
      return true;
    }
  }
  const double mid = 0.5 * (piece.lo[axis] + piece.hi[axis]);
  Box3 lo = piece, hi = piece;
  lo.hi[axis] = hi.lo[axis] = mid;
  const std::array<IBox, 2> boxes{flat_box(lo, flat), flat_box(hi, flat)};
  std::array<IGrad, 2> out;
  auto& batch = e.halves[std::size_t(axis)];
  batch.eval(boxes.data(), 2, out.data());
  const Evaluated half[2] = {{out[0], batch.partial_domain(0)}, {out[1], batch.partial_domain(1)}};
  return edge_pieces(e, lo, axis, ends & 1u, splits - 1, zero_free_pieces, nullptr, &half[0]) &&
         edge_pieces(e, hi, axis, ends & 2u, splits - 1, zero_free_pieces, nullptr, &half[1]);
}

/// f has no zero on the edge box, or is monotone along it: its derivative along `axis` keeps one
/// sign. Weak monotonicity is accepted (a derivative interval [0, d] or [-d, 0]) because grid
/// planes often are planes of symmetry, where the derivative vanishes at an edge's end; f - delta
/// then has at most one zero on the edge for all but countably many delta (docs/mesh.md). Else
/// the edge is proved in pieces (edge_pieces).
bool edge_ok(Evaluators& e, const Box3& edge, int axis) {
  const int flat = 7 & ~(1 << axis);
  IGrad g = eval_flat_natural(e, edge, flat);
  if (e.flat_partial) return false;
  const Interval& d = g.g[std::size_t(axis)];
  // Monotone needs no value: the mean-value form is evaluated only where it is not.
  if (d.lo() >= 0.0 || d.hi() <= 0.0) return true;
  g.v = tightened(e, edge, flat, g);
  if (zero_free(g.v)) return true;
  ProofPieces pieces(flat);
  // The whole edge is the first piece, already evaluated.
  if (!edge_pieces(e, edge, axis, 3u, kProofSplits, pieces, &g)) return false;
  if (!pieces.any_loose()) return true;
  pieces.resolve(e);
  return pieces.joined(edge);
}

/// No closed curve of the surface inside this piece of a face normal to axis a: f restricted to
/// the face has no critical point on the piece (its tangential gradient never vanishes), or f has
/// no zero on the piece and the piece touches the face's boundary (`sides`: bits 0, 1 the face's
/// lower and upper side along the next axis, bits 2, 3 along the one after), or (loose, checked by
/// ProofPieces::joined) f has no zero on the piece and zero-free pieces join it to the face's
/// boundary. A closed curve C in the face bounds a disc D in it, and f restricted to D has an
/// extremum p inside; the zero-free pieces joined to the piece holding p form a connected set
/// without zeros, so they stay inside D, which meets the face's boundary nowhere but on C. So
/// pieces that pass, covering the face, leave no place for p. False when a piece of the finest
/// split is neither free of critical points nor of zeros.
/// `pre`: the piece's natural evaluation, batched with its siblings'.
bool face_pieces(Evaluators& e, const Box3& piece, int a, unsigned sides, int splits,
                 ProofPieces& zero_free_pieces, const IGrad* known = nullptr,
                 const Evaluated* pre = nullptr) {
  const std::size_t u = std::size_t((a + 1) % 3), v = std::size_t((a + 2) % 3);
  IGrad g;
  if (known) {
    g = *known;  // made without domain trouble
  } else if (!piece_grad(e, piece, 1 << a, pre, g)) {
    return false;
  }
  if ((square(g.g[u]) + square(g.g[v])).lo() > 0.0) {
    zero_free_pieces.add_maybe(piece, g, known);
    return true;
  }
  if (sides == 0 && splits > 0) {
    zero_free_pieces.add_maybe(piece, g, known);
  } else {
    const bool no_zero = zero_free(known ? g.v : tightened(e, piece, 1 << a, g));
    if (no_zero) zero_free_pieces.add(piece, false);
    if (sides && no_zero) return true;
    if (splits == 0) {
      if (!no_zero) return false;
      zero_free_pieces.loose[std::size_t(zero_free_pieces.n - 1)] = true;
      return true;
    }
  }
  const double mu = 0.5 * (piece.lo[u] + piece.hi[u]), mv = 0.5 * (piece.lo[v] + piece.hi[v]);
  std::array<Box3, 4> q;
  std::array<IBox, 4> boxes;
  for (unsigned k = 0; k < 4; ++k) {
    q[k] = piece;
    (k & 1 ? q[k].lo[u] : q[k].hi[u]) = mu;
    (k & 2 ? q[k].lo[v] : q[k].hi[v]) = mv;
    boxes[k] = flat_box(q[k], 1 << a);
  }
  // The quarters' evaluations in one batch; a quarter not reached (an earlier one failed) leaves
  // its own unused and uncounted.
  std::array<IGrad, 4> out;
  auto& batch = e.quarters[std::size_t(a)];
  batch.eval(boxes.data(), 4, out.data());
  for (unsigned k = 0; k < 4; ++k) {
    // The quarter keeps the sides of the face on which it lies: its lower or upper one per axis.
    const unsigned kept = (k & 1 ? 2u : 1u) | (k & 2 ? 8u : 4u);
    const Evaluated pre_k{out[k], batch.partial_domain(int(k))};
    if (!face_pieces(e, q[k], a, sides & kept, splits - 1, zero_free_pieces, nullptr, &pre_k)) {
      return false;
    }
  }
  return true;
}

/// The 13 fixed directions of the monotonicity test: the axes, face and body diagonals.
constexpr int kDirections[13][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 0},  {1, -1, 0},
                                    {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}, {1, 1, 1},
                                    {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};

/// How f was proved strictly monotone over a cell whose gradient enclosure is `g`: kCone by
/// Plantinga and Vegter's cone test (0 outside the dot product of two independent copies of G, so
/// that any two gradients of the cell have a positive dot product), else the index of the first
/// of the 13 fixed directions d with 0 outside d.G, else kNotMonotone. Either way every line along
/// the direction meets the surface in the cell at most once.
constexpr int kCone = -1, kNotMonotone = -2;
int monotone(const IGrad& c) {
  const Interval dot = c.g[0] * c.g[0] + c.g[1] * c.g[1] + c.g[2] * c.g[2];
  if (dot.lo() > 0.0) return kCone;
  for (int i = 0; i < 13; ++i) {
    Interval s(0.0);
    for (std::size_t a = 0; a < 3; ++a) {
      if (kDirections[i][a] == 1) s = s + c.g[a];
      if (kDirections[i][a] == -1) s = s - c.g[a];
    }
    if (!s.contains_zero()) return i;
  }
  return kNotMonotone;
}

/// f restricted to face (a, side) of the cell has no critical point (its tangential gradient
/// never vanishes) or no zero, so no closed curve of the surface lies inside the face.
bool face_ok(Evaluators& e, const Box3& b, int a, int side, FaceProof& proof) {
  Box3 f = b;
  f.lo[a] = f.hi[a] = side ? b.hi[a] : b.lo[a];
  const IGrad g = eval_flat(e, f, 1 << a);
  if (e.flat_partial) return false;
  proof.tested = true;
  proof.zero_free = zero_free(g.v);
  for (std::size_t k = 0; k < 3; ++k) {
    if (int(k) != a && !g.g[k].contains_zero()) proof.monotone |= 1u << k;
  }
  const std::size_t u = std::size_t((a + 1) % 3), v = std::size_t((a + 2) % 3);
  if (proof.zero_free || (square(g.g[u]) + square(g.g[v])).lo() > 0.0) return true;
  ProofPieces pieces(1 << a);
  // The whole face is the first piece, already evaluated.
  if (!face_pieces(e, f, a, 15u, kProofSplits, pieces, &g)) return false;
  if (!pieces.any_loose()) return true;
  pieces.resolve(e);
  return pieces.joined(f);
}

/// The local certificate of a cell (docs/mesh.md, "Certified meshing"): f strictly monotone over
/// it, and no closed curve of the surface hidden inside a face nor a double crossing inside an
/// edge, where corner signs cannot see them. The cone test leaves those to Plantinga and Vegter's
/// argument, which holds for it. A fixed direction d does not: a spike thinner than a cell (the
/// graph z = 0.8 exp(-r^2 / 4e-6)) is monotone along z in every cell and crosses their horizontal
/// faces in small circles only, and was lost whole. So a cell certified by d alone also proves
/// each face that d crosses free of critical points of f, and each edge not along d monotone (or
/// zero-free); faces that contain d, and edges along d, need no proof: f is monotone along d
/// there. `strict` proves every face and edge, whatever the certificate.
/// What locally_certified found out about a cell's faces and edges, kept between its attempts
/// (before and after Refiner::tighten): the proofs depend on the cell's box, not on its gradient
/// enclosure, so a face proved or refuted once need not be evaluated again.
struct CellProofs {
  FaceProof face[3][2];
  std::int8_t face_state[3][2] = {};  ///< 0 not tried, 1 proved, -1 refuted
  std::int8_t edge_state[3][4] = {};
};

/// The cell is box `b`, at grid position `at` with edge `size` (in grid steps) at `depth`.
bool locally_certified(Evaluators& e, const Box3& b, const Index3& at, std::uint32_t size,
                       int depth, const IGrad& c, bool strict, CellProofs& memo) {
  const int m = monotone(c);
  if (m == kNotMonotone) return false;
  if (m == kCone && !strict) return true;
  const int* d = m == kCone ? nullptr : kDirections[m];
  auto face = [&](int a, int side) {
    std::int8_t& state = memo.face_state[a][side];
    if (state == 0) {
      Index3 corner = at;
      corner[std::size_t(a)] += side ? size : 0;
      const Key key = make_key(corner);
      const std::uint8_t what = ProofCache::what(depth, a, false);
      if (const ProofCache::Entry* known = e.proofs.find(key, what)) {
        state = known->ok;
        memo.face[a][side] = known->proof;
      } else {
        state = face_ok(e, b, a, side, memo.face[a][side]) ? 1 : -1;
        e.proofs.keep({key, what, state, memo.face[a][side]});
      }
    }
    return state > 0;
  };
  for (int a = 0; a < 3; ++a) {
    if (!strict && d[a] == 0) continue;  // d lies in faces normal to axis a
    if (!face(a, 0) || !face(a, 1)) return false;
  }
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    if (!strict && d[u] == 0 && d[v] == 0) continue;  // edges along d
    for (int k = 0; k < 4; ++k) {
      // The edge lies in the faces normal to u and to v on its sides: their proofs may cover it.
      const bool covered =
          (memo.face_state[u][k & 1] > 0 && memo.face[u][k & 1].covers(a)) ||
          (memo.face_state[v][k >> 1 & 1] > 0 && memo.face[v][k >> 1 & 1].covers(a));
      if (covered) continue;
      std::int8_t& state = memo.edge_state[a][k];
      if (state == 0) {
        Index3 corner = at;
        corner[std::size_t(u)] += (k & 1) ? size : 0;
        corner[std::size_t(v)] += (k & 2) ? size : 0;
        const Key key = make_key(corner);
        const std::uint8_t what = ProofCache::what(depth, a, true);
        if (const ProofCache::Entry* known = e.proofs.find(key, what)) {
          state = known->ok;
        } else {
          Box3 ed = b;
          ed.lo[u] = ed.hi[u] = (k & 1) ? b.hi[u] : b.lo[u];
          ed.lo[v] = ed.hi[v] = (k & 2) ? b.hi[v] : b.lo[v];
          state = edge_ok(e, ed, a) ? 1 : -1;
          e.proofs.keep({key, what, state, FaceProof{}});
        }
      }
      if (state < 0) return false;
    }
  }
  return true;
}

/// What a split cell evaluated for one of its children in a batch of 8 (Refiner::refine()): the
/// bit-for-bit results classify() would get from its own evaluations, counted when it uses them.
struct ChildValues {
  Interval f;  ///< f over the child's box
  bool f_partial = false;
  bool has_centre = false;  ///< f at the child's centre too
  Interval centre;
  bool centre_partial = false;
  bool has_grad = false;  ///< the child's gradient enclosure too
  IGrad grad;
  bool grad_partial = false;
};

/// A piece of phase 1 over a list of cells when processes share it (refine_spread()): a leaf that
/// the top levels already made, or a subtree left to refine, with the gradient enclosures that
/// its parent hands down (Refiner::refine()'s `parent` and `own`).
struct Subtree {
  Index3 at;
  int depth;
  Leaf leaf;  ///< when `done`
  bool done;
  bool has_parent, has_own;
  IGrad parent, own;
  bool tighten_first = false;  ///< Refiner::refine()'s `tighten_first`
  bool has_values = false;     ///< what its parent evaluated for it (Refiner::refine()'s `values`)
  ChildValues values;
};

/// Phase 1: refines one cell into leaves (depth-first order).
class Refiner {
 public:
  Refiner(const Grid& g, const CertifiedMeshSettings& s, std::atomic<std::uint64_t>& count,
          const Progress* progress)
      : grid_(g), settings_(s), count_(count), progress_(progress) {}

  /// `parent`: the gradient enclosure of the cell's parent, if it has one without domain
  /// trouble; `own`: the cell's own, if its parent evaluated it (Children); `tighten_first`:
  /// the parent's tighten() paid (Children::pays), so the cell tries it first (classify()).
  void refine(Evaluators& e, const Index3& at, int depth, Leaves& out,
              const IGrad* parent = nullptr, const IGrad* own = nullptr, bool tighten_first = false,
              const ChildValues* values = nullptr) const {
    IGrad g;
    bool smooth = false;
    Children kids;
    if (const std::optional<Leaf> l =
            classify(e, at, depth, parent, own, tighten_first, g, smooth, kids, values)) {
      return emit(e, out, *l);
    }
    std::array<ChildValues, 8> v;
    evaluate_children(e, at, depth, smooth ? &g : nullptr, kids.valid, v);
    for (std::size_t k = 0; k < 8; ++k) {
      refine(e, child(at, depth, int(k)), depth + 1, out, smooth ? &g : nullptr,
             kids.valid ? &kids.g[k] : nullptr, kids.valid && kids.pays, &v[k]);
    }
  }

  /// refine(), with the children of the first `levels` levels of splits refined in parallel (a
  /// scene of one root cell would use one thread otherwise); the same leaves in the same order.
  void refine_parallel(ThreadEvaluators& evals, const Index3& at, int depth, int levels,
                       Leaves& out, const IGrad* parent = nullptr, const IGrad* own = nullptr,
                       bool tighten_first = false, const ChildValues* values = nullptr) const {
    Evaluators& e = *evals.local();
    if (levels == 0) return refine(e, at, depth, out, parent, own, tighten_first, values);
    IGrad g;
    bool smooth = false;
    Children kids;
    if (const std::optional<Leaf> l =
            classify(e, at, depth, parent, own, tighten_first, g, smooth, kids, values)) {
      return emit(e, out, *l);
    }
    std::array<ChildValues, 8> v;
    evaluate_children(e, at, depth, smooth ? &g : nullptr, kids.valid, v);
    std::array<Leaves, 8> parts;
    tbb::parallel_for(0, 8, [&](int k) {
      RoundingScope scope;
      const auto i = std::size_t(k);
      refine_parallel(evals, child(at, depth, k), depth + 1, levels - 1, parts[i],
                      smooth ? &g : nullptr, kids.valid ? &kids.g[i] : nullptr,
                      kids.valid && kids.pays, &v[i]);
    });
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  }

  /// The first `levels` levels of refine() below a cell, done here: the leaves they make and the
  /// subtrees below them, in refine()'s order (refine_spread()). The leaves are not counted
  /// (settle() counts every leaf of the loop at its end).
  void expand_top(Evaluators& e, const Index3& at, int depth, int levels, std::vector<Subtree>& out,
                  const IGrad* parent = nullptr, const IGrad* own = nullptr,
                  bool tighten_first = false, const ChildValues* values = nullptr) const {
    if (levels == 0) {
      Subtree t{at,
                depth,
                {},
                false,
                parent != nullptr,
                own != nullptr,
                {},
                {},
                tighten_first,
                values != nullptr,
                {}};
      if (parent) t.parent = *parent;
      if (own) t.own = *own;
      if (values) t.values = *values;
      out.push_back(t);
      return;
    }
    IGrad g;
    bool smooth = false;
    Children kids;
    if (const std::optional<Leaf> l =
            classify(e, at, depth, parent, own, tighten_first, g, smooth, kids, values)) {
      out.push_back(Subtree{at, depth, *l, true, false, false, {}, {}, false, false, {}});
      return;
    }
    std::array<ChildValues, 8> v;
    evaluate_children(e, at, depth, smooth ? &g : nullptr, kids.valid, v);
    for (std::size_t k = 0; k < 8; ++k) {
      expand_top(e, child(at, depth, int(k)), depth + 1, levels - 1, out, smooth ? &g : nullptr,
                 kids.valid ? &kids.g[k] : nullptr, kids.valid && kids.pays, &v[k]);
    }
  }

  /// Adds the thread's pending leaves to the shared count; throws when it exceeds the limit, or
  /// when the run was cancelled (checked every 1024 leaves).
  void flush(Evaluators& e) const {
    if (progress_ && progress_->cancelled()) throw Error("certified mesh: cancelled");
    const std::uint64_t n = e.pending_leaves;
    e.pending_leaves = 0;
    if (count_.fetch_add(n, std::memory_order_relaxed) + n > settings_.max_boxes) {
      throw_over_limit();
    }
  }

  /// The leaf count at the start of a shared loop (refine_spread()).
  std::uint64_t count() const { return count_.load(); }
  /// Sets the leaf count after a shared loop, in which this process counted only its own
  /// leaves; throws as flush() does when it exceeds the limit.
  void settle(std::uint64_t count) const {
    count_.store(count);
    if (count > settings_.max_boxes) throw_over_limit();
  }
  [[noreturn]] void throw_over_limit() const {
    throw SettingError("certified mesh: more than " + std::to_string(settings_.max_boxes) +
                       " leaves are needed (the box limit); raise the limit or lower the "
                       "maximum depth");
  }

 private:
  /// The first evaluations of classify() for the 8 children of a split cell, in batches: f over
  /// each child's box; where the children get the cell's gradient `parent` (smooth) for their
  /// mean-value form, f at each centre; and, unless they get their gradients from the cell's
  /// tighten() (`own`), the gradients of the children whose value and the mean-value form with
  /// `parent` do not decide (what classify() would evaluate next), when there are two or more.
  /// A child whose value decides before its centre does leaves that unused (and uncounted),
  /// which the batch costs less than.
  void evaluate_children(Evaluators& e, const Index3& at, int depth, const IGrad* parent, bool own,
                         std::array<ChildValues, 8>& v) const {
    const std::uint32_t h = grid_.size(depth) / 2;
    double line[3][3];
    for (int a = 0; a < 3; ++a) {
      for (std::uint32_t j = 0; j < 3; ++j) line[a][j] = grid_.coord(a, at[std::size_t(a)] + j * h);
    }
    std::array<IBox, 8> boxes;
    std::array<Interval, 8> out;
    for (std::size_t k = 0; k < 8; ++k) {
      for (int a = 0; a < 3; ++a) {
        const std::size_t j = (k >> a) & 1u;
        boxes[k][a] = Interval(line[a][j], line[a][j + 1]);
      }
    }
    e.batch.eval(boxes.data(), 8, out.data());
    for (std::size_t k = 0; k < 8; ++k) {
      v[k].f = out[k];
      v[k].f_partial = e.batch.partial_domain(int(k));
    }
    if (parent) {
      std::array<IBox, 8> points;
      for (std::size_t k = 0; k < 8; ++k) {
        for (int a = 0; a < 3; ++a) points[k][a] = Interval(centre(boxes[k], a));
      }
      e.batch.eval(points.data(), 8, out.data());
      for (std::size_t k = 0; k < 8; ++k) {
        v[k].has_centre = true;
        v[k].centre = out[k];
        v[k].centre_partial = e.batch.partial_domain(int(k));
      }
    }
    if (own) return;
    // classify()'s tests before it evaluates the gradient, with these values.
    std::array<IBox, 8> wanted;
    std::array<std::size_t, 8> which;
    int n = 0;
    for (std::size_t k = 0; k < 8; ++k) {
      if (zero_free(v[k].f) || v[k].f.is_empty()) continue;
      if (parent && !v[k].f_partial && !v[k].centre_partial &&
          zero_free(expand(boxes[k], v[k].centre, parent->g))) {
        continue;
      }
      which[std::size_t(n)] = k;
      wanted[std::size_t(n++)] = boxes[k];
    }
    if (n < 2) return;  // a batch of one costs more than IntervalGradEval
    std::array<IGrad, 8> grads;
    e.batch_g.eval(wanted.data(), n, grads.data());
    for (std::size_t i = 0; i < std::size_t(n); ++i) {
      ChildValues& c = v[which[i]];
      c.has_grad = true;
      c.grad = grads[i];
      c.grad_partial = e.batch_g.partial_domain(int(i));
    }
  }

  Index3 child(const Index3& at, int depth, int k) const {
    const std::uint32_t h = grid_.size(depth) / 2;
    return {at[0] + (k & 1) * h, at[1] + ((k >> 1) & 1) * h, at[2] + ((k >> 2) & 1) * h};
  }

  /// classify() tries the centred form of the gradient only where f's natural interval is at
  /// least this many times its mean-value form's.
  static constexpr double kOverestimated = 2.0;

  /// The gradient enclosures of a cell's 8 children (in child order), when classify evaluated
  /// them to tighten the cell's own (valid: all of them, none with domain trouble).
  struct Children {
    bool valid = false;
    /// The hull of the 8 halved the width of the cell's partials or more (summed over the 3):
    /// the cell's enclosure was mostly overestimation, which tighten() removes, and its
    /// children are likely to gain from tighten() too.
    bool pays = false;
    std::array<IGrad, 8> g;
  };

  /// The leaf that the cell is (empty, certified, or uncertified at the depth limit), or nothing
  /// when it must be split. `g` gets the cell's gradient enclosure when it was evaluated, and
  /// `smooth` whether it is free of domain trouble; `kids` the children's gradient enclosures
  /// when they were evaluated (tighten()), for the children to reuse.
  std::optional<Leaf> classify(Evaluators& e, const Index3& at, int depth, const IGrad* parent,
                               const IGrad* own, bool tighten_first, IGrad& g, bool& smooth,
                               Children& kids, const ChildValues* values = nullptr) const {
    const std::uint32_t s = grid_.size(depth);
    const Box3 b = grid_.box(at, s);
    ++e.evaluations;
    const Interval f = values ? values->f : e.f.eval(IBox(b));
    const bool defined = !(values ? values->f_partial : e.f.partial_domain());
    if (zero_free(f) || f.is_empty()) {
      const std::int8_t sign = !defined || f.is_empty() ? 0 : (f.lo() > 0.0 ? 1 : -1);
      return Leaf{at, std::uint8_t(depth), Kind::kEmpty, sign};
    }
    // The mean-value form often proves what the natural interval could not. The parent's gradient
    // encloses the cell's own, so the form with it encloses the form with the cell's: when it
    // proves the cell empty, the cell's gradient would too, with the same sign, and need not be
    // evaluated.
    std::optional<Interval> fc;
    if (parent && defined) {
      if (values && values->has_centre) {
        ++e.evaluations;
        if (!values->centre_partial) fc = values->centre;
      } else {
        fc = centre_value(e, IBox(b));
      }
      if (fc) {
        const Interval wide = expand(IBox(b), *fc, parent->g);
        if (zero_free(wide)) return empty(at, depth, wide);
      }
    }
    if (own) {
      g = *own;  // evaluated by the parent, without domain trouble
      smooth = true;
    } else if (values && values->has_grad) {
      ++e.evaluations;
      g = values->grad;
      smooth = !values->grad_partial;
    } else {
      ++e.evaluations;
      g = e.g.eval(IBox(b));
      smooth = !e.g.partial_domain();
    }
    bool overestimated = false;  // the natural interval of f is kOverestimated times mv or more
    if (smooth && defined) {
      const Interval mv =
          fc ? intersect(expand(IBox(b), *fc, g.g), g.v) : mean_value(e, IBox(b), g);
      if (zero_free(mv)) return empty(at, depth, mv);
      overestimated = g.v.width() >= kOverestimated * mv.width();
    }
    const bool may_certify = depth >= settings_.min_depth && smooth;
    // Where the cone test fails, the natural gradient's overestimation may be what fails it (a
    // polynomial with cancellation: the thin torus) and the centred form, whose overestimation
    // shrinks with the square of the cell's size, then certifies the cell levels higher. The
    // Hessian costs several gradient evaluations, so it is evaluated only where the natural
    // interval of f overestimates too (measured against the mean-value form): on the thin torus
    // and chubs, where the form pays, f's natural interval is 10 to 1000 times the mean-value
    // form's; on the twist, where it never narrowed a gradient, less than 1.5 times.
    if (may_certify && overestimated && settings_.centred_gradients && monotone(g) != kCone) {
      centre_gradient(e, IBox(b), g);
    }
    const bool may_tighten = may_certify && defined && depth < grid_.max_depth;
    std::optional<IGrad> tight;  // the tightened enclosure, when made before the first attempt
    bool tried = false;          // tighten() was called (and failed unless `tight`)
    CellProofs proofs;
    if (may_certify) {
      // A cell that only a fixed direction proves monotone must prove faces and edges as well
      // (locally_certified); on the thin torus that costs more than the 8 gradient evaluations
      // of tighten(), after which the cone test alone certifies 9 in 10 of those cells. So
      // tighten() comes first there: where the parent's paid (`tighten_first`; on the twist,
      // whose enclosures are tight already, it would mostly be wasted). The leaf is the one the
      // rules' order gives: a cell that either attempt certifies is certified; where the
      // tightened value is zero-free (empty, unless the first attempt certifies) or fails the
      // cone test, both attempts run as they would.
      if (tighten_first && may_tighten && !settings_.strict && monotone(g) >= 0) {
        IGrad t = g;
        tried = true;
        if (tighten(e, at, depth, t, kids)) {
          tight = t;
          if (!zero_free(t.v) && monotone(t) == kCone) {
            return Leaf{at, std::uint8_t(depth), Kind::kCertified, 0};
          }
        }
      }
      if (locally_certified(e, b, at, s, depth, g, settings_.strict, proofs)) {
        return Leaf{at, std::uint8_t(depth), Kind::kCertified, 0};
      }
    }
    if (depth == grid_.max_depth) {
      return Leaf{at, std::uint8_t(depth), Kind::kUncertified, 0};
    }
    if (tight) {
      g = *tight;
    } else if (tried || !(may_tighten && tighten(e, at, depth, g, kids))) {
      return std::nullopt;
    }
    if (zero_free(g.v)) return empty(at, depth, g.v);
    if (locally_certified(e, b, at, s, depth, g, settings_.strict, proofs)) {
      return Leaf{at, std::uint8_t(depth), Kind::kCertified, 0};
    }
    return std::nullopt;
  }

  /// Bounds the gradient enclosure `g` of box b by the centred form as well: g(c) + H(b) (b - c)
  /// around b's centre c (IntervalHessEval, centred_gradient).
  static void centre_gradient(Evaluators& e, const IBox& b, IGrad& g) {
    if (!e.kinks.empty()) {
      // A crease of min or max in the cell (which the natural interval sees as an undecided
      // choice) leaves the Hessian unbounded and the centred form useless: the interval value,
      // a fraction of the Hessian's cost, tells.
      ++e.evaluations;
      e.f.eval(b);
      for (const std::size_t i : e.kinks) {
        if (e.f.choices()[i] == 0) return;
      }
    }
    Vec3 c;
    IBox point;
    for (int a = 0; a < 3; ++a) point[a] = Interval(c[a] = centre(b, a));
    e.evaluations += 2;
    const IGrad gc = e.g.eval(point);
    if (e.g.partial_domain()) return;
    const IHess h = e.h.eval(b);
    if (e.h.partial_domain()) return;
    const std::array<Interval, 3> r = centred_gradient(b, c, gc.g, h.h);
    for (std::size_t a = 0; a < 3; ++a) {
      // Two enclosures of the same partials cannot be disjoint; should rounding ever make them
      // so, the cell keeps its own.
      const Interval t = intersect(g.g[a], r[a]);
      if (!t.is_empty()) g.g[a] = t;
    }
  }

  static Leaf empty(const Index3& at, int depth, const Interval& v) {
    return Leaf{at, std::uint8_t(depth), Kind::kEmpty,
                v.lo() > 0.0 ? std::int8_t(1) : std::int8_t(-1)};
  }

  /// Before a cell that failed its certificate is split, its gradient enclosure is tightened to
  /// the hull of its 8 children's (intersected with its own: both enclose every gradient in the
  /// cell, and every point of the cell lies in a child). The natural interval extension
  /// overestimates in proportion to the box's size, so this halves the overestimation; where the
  /// surface is thin (a tube of radius 0.003 in cells of 0.002), the dependency problem of a
  /// polynomial with cancellation, not the surface's own curvature, is what fails the cone and
  /// direction tests, and the cell then certifies without the 8 leaves, their corners and their
  /// extraction. When it still fails, the children reuse their enclosures, so the evaluations are
  /// not wasted. False (nothing changed) where a child has domain trouble.
  static constexpr double kTightenPays = 0.75;
  bool tighten(Evaluators& e, const Index3& at, int depth, IGrad& g, Children& kids) const {
    const std::uint32_t h = grid_.size(depth) / 2;
    // The grid lines of the children, 3 per axis: the same doubles as grid_.box of each child.
    double line[3][3];
    for (int a = 0; a < 3; ++a) {
      for (std::uint32_t j = 0; j < 3; ++j) line[a][j] = grid_.coord(a, at[std::size_t(a)] + j * h);
    }
    std::array<IBox, 8> boxes;
    for (std::size_t k = 0; k < 8; ++k) {
      for (int a = 0; a < 3; ++a) {
        const std::size_t j = (k >> a) & 1u;
        boxes[k][a] = Interval(line[a][j], line[a][j + 1]);
      }
    }
    // One batch, the same doubles as IntervalGradEval child by child; counted as they were,
    // up to the first child with domain trouble.
    e.batch_g.eval(boxes.data(), 8, kids.g.data());
    IGrad hull_g;
    for (std::size_t k = 0; k < 8; ++k) {
      ++e.evaluations;
      if (e.batch_g.partial_domain(int(k))) return false;
      if (k == 0) {
        hull_g = kids.g[0];
        continue;
      }
      hull_g.v = hull(hull_g.v, kids.g[k].v);
      for (std::size_t a = 0; a < 3; ++a) hull_g.g[a] = hull(hull_g.g[a], kids.g[k].g[a]);
    }
    kids.valid = true;
    IGrad t;
    t.v = intersect(g.v, hull_g.v);
    bool disjoint = t.v.is_empty();
    double before = 0, after = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      t.g[a] = intersect(g.g[a], hull_g.g[a]);
      disjoint = disjoint || t.g[a].is_empty();
      before += g.g[a].hi() - g.g[a].lo();
      if (!t.g[a].is_empty()) after += t.g[a].hi() - t.g[a].lo();
    }
    kids.pays = after <= kTightenPays * before;
    // Two enclosures of the same values cannot be disjoint; should rounding ever make them so,
    // the cell keeps its own.
    if (disjoint) return false;
    g = t;
    return true;
  }

  void emit(Evaluators& e, Leaves& out, const Leaf& l) const {
    out.push_back(l);
    if (++e.pending_leaves == 1024) flush(e);
  }
  const Grid& grid_;
  const CertifiedMeshSettings& settings_;
  std::atomic<std::uint64_t>& count_;
  const Progress* progress_;
};

/// Leaf corners in a hash table, with the sign of f there: +1 (f > 0), -1 (f <= 0, which is how a
/// corner on the surface counts: the mesh follows f = delta for small delta > 0), and whether the
/// interval evaluation could not decide (taken as -1).
///
/// The fine grid is cut into buckets (cubes of 2^bucket_shift grid steps) and the table into one
/// region per bucket, in which its points are hashed (open addressing). The lookups of one leaf,
/// and of the leaves after it (leaves come depth-first, so they lie close by), thus stay in a few
/// cache lines; one table hashed over all points would miss the cache on nearly every lookup.
struct VertexTable {
  struct Slot {
    Key key;
    std::int8_t sign;
    std::uint8_t uncertain;  ///< 1: the sign is undecided; 2 (while filling): to evaluate
    /// The depth of the finest leaf that has the point as a corner. A leaf all of whose corners
    /// have it at most its own depth has no finer neighbour on its faces or edges: such a
    /// neighbour lies in a cell of the leaf's size that shares a side (an edge at least) with
    /// the leaf and is split, and the leaf of that cell's tiling at a shared corner is finer.
    /// Leaves that are split keep their corners, which their children's corners are too, so the
    /// maximum over every leaf ever added is the maximum over the current ones.
    std::uint8_t finest;
  };
  static constexpr Key kNone = ~Key{0};
  BigVector<Slot> slots;
  /// The first slot of each bucket's region (bucket order z, y, x); region.back() is the slot
  /// count. Each region is empty or a power of two at most 3/4 full.
  std::vector<std::uint32_t> region{0, 0};
  std::vector<std::uint32_t> used{0};  ///< points per bucket
  int bucket_shift = 0;
  std::array<std::uint32_t, 3> buckets{1, 1, 1};  ///< per axis

  /// Points on the grid's upper faces have buckets of their own (one more per axis), so that no
  /// coordinate needs clamping.
  std::size_t bucket(Key k) const {
    const Key m = (Key{1} << kKeyBits) - 1;
    const int s = bucket_shift;
    return (((k >> (2 * kKeyBits)) >> s) * buckets[1] + (((k >> kKeyBits) & m) >> s)) * buckets[0] +
           ((k & m) >> s);
  }
  /// The home slot of k in a power-of-two table of n >= 2 slots: the top bits of the Fibonacci
  /// product, which every bit of the key reaches. (Its bits from 32 up, taken before, are not
  /// reached by z, which a key holds from bit 40: the points of a bucket that differ in z only
  /// shared a home slot, and a lookup probed about 6 slots, by callgrind's counts.)
  static std::size_t home(Key k, std::size_t n) {
    return std::size_t((k * 0x9E3779B97F4A7C15ull) >> (64 - std::countr_zero(n)));
  }
  /// The slot of k, or null.
  const Slot* find(Key k) const {
    const std::size_t b = bucket(k);
    const std::uint32_t base = region[b], n = region[b + 1] - base;
    if (n == 0) return nullptr;
    for (std::size_t h = home(k, n);; h = (h + 1) & (n - 1)) {
      const Slot& s = slots[base + h];
      if (s.key == k) return &s;
      if (s.key == kNone) return nullptr;
    }
  }
  Slot* find(Key k) { return const_cast<Slot*>(std::as_const(*this).find(k)); }
  bool contains(Key k) const { return find(k) != nullptr; }
};

/// The interval sign of f at a point: +1, -1 (f <= 0), or 0 when undecided.
std::int8_t point_sign(Evaluators& e, const Vec3& p) {
  ++e.evaluations;
  const Interval v = e.f.eval(IBox(Interval(p.x), Interval(p.y), Interval(p.z)));
  if (e.f.partial_domain() || v.is_empty()) return 0;
  if (v.lo() > 0.0) return 1;
  if (v.hi() <= 0.0) return -1;
  return 0;
}

/// Buckets of about 4 corner entries each, counted over the whole grid: most are empty (far from
/// the surface), those near it hold a few dozen points.
void choose_buckets(VertexTable& t, const Grid& grid, std::size_t entries) {
  const std::uint64_t target = std::max<std::uint64_t>(1, entries / 4);
  for (t.bucket_shift = 0;; ++t.bucket_shift) {
    std::uint64_t total = 1;
    for (std::size_t a = 0; a < 3; ++a) {
      const int bits = grid.root_bits[a] + grid.max_depth;
      t.buckets[a] = (std::uint32_t{1} << bits >> std::min(bits, t.bucket_shift)) + 1;
      total *= t.buckets[a];
    }
    if (total <= target) return;
  }
}

// Entry codes (the low 3 bits of key << 3 | code), in the order in which they decide a point:
// the table's own points (0: f <= 0, 1: f > 0, 2: undecided), then the corners of new leaves (3:
// an empty leaf proves f <= 0, 4: f > 0; 5: a corner of a leaf that may hold surface, 6: one that
// only empty leaves where f may be undefined touch; both evaluated).
constexpr std::uint64_t kFresh = 3;

/// Points for the table: `code` as key << 3 | code, and beside it the depth of the leaf (the
/// finest of the leaves, for a point already in the table) that adds it.
struct Entries {
  BigVector<std::uint64_t> code;
  BigVector<std::uint8_t> depth;
};

/// The table entry of corner k (bit a: upper along axis a) of leaf l: key << 3 | its code.
std::uint64_t corner_entry(const Grid& grid, const Leaf& l, std::uint32_t k) {
  const std::uint32_t s = grid.size(l.depth);
  const std::uint64_t code =
      kFresh + (l.kind != Kind::kEmpty ? 2 : (l.sign < 0 ? 0 : (l.sign > 0 ? 1 : 3)));
  const Key key =
      make_key({l.at[0] + (k & 1) * s, l.at[1] + ((k >> 1) & 1) * s, l.at[2] + ((k >> 2) & 1) * s});
  return (key << 3) | code;
}

/// The table entry of a point already in the table: key << 3 | its code.
std::uint64_t slot_entry(const VertexTable::Slot& s) {
  return s.key << 3 | (s.uncertain == 2 ? 5 : (s.uncertain ? 2 : (s.sign > 0 ? 1 : 0)));
}

/// The corners of `fresh`, in no particular order.
Entries corner_entries(const Grid& grid, const Leaves& fresh, const Exec& exec) {
  Entries out;
  out.code.resize(8 * fresh.size());
  out.depth.resize(8 * fresh.size());
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, fresh.size(), 4096), [&](auto r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        for (std::uint32_t k = 0; k < 8; ++k) {
          out.code[8 * i + k] = corner_entry(grid, fresh[i], k);
          out.depth[8 * i + k] = fresh[i].depth;
        }
      }
    });
  });
  return out;
}

/// The points of table `t` and the corners of `fresh`, grouped by their bucket in `n` (a stable
/// counting sort; within a bucket, the table's points in slot order, then the corners leaf by
/// leaf); `start` gets each bucket's first entry. The keys are computed twice, once to count and
/// once to place, rather than kept in an array of all entries: such arrays (tens of megabytes on
/// the thin torus) cost more in fresh pages, which the kernel must clear, than the arithmetic
/// saves.
///
/// In parallel: the entries are cut into parts (the table's slots, then the leaves in one range
/// per thread), each part counts its own per bucket, the counts become each part's first place
/// in every bucket (bucket by bucket, and in a bucket part by part, so the order is that of one
/// pass over the parts in turn, whatever the thread count), and each part places its own. (One
/// pass took half the corner table's time on the thin torus with 2 threads.)
Entries bucketed_entries(const VertexTable& t, const VertexTable& n, const Grid& grid,
                         const Leaves& fresh, std::vector<std::uint32_t>& start, const Exec& exec) {
  const std::size_t nb = n.region.size() - 1;
  const std::size_t leaf_parts = std::size_t(std::max(1, exec.resolved_threads()));
  const std::size_t parts = 1 + leaf_parts;     // part 0: the table's slots
  const auto leaf_range = [&](std::size_t p) {  // p >= 1
    return std::pair{fresh.size() * (p - 1) / leaf_parts, fresh.size() * p / leaf_parts};
  };
  // Calls put(entry, depth) for every entry of part p, in order.
  const auto each = [&](std::size_t p, auto&& put) {
    if (p == 0) {
      for (const VertexTable::Slot& s : t.slots) {
        if (s.key != VertexTable::kNone) put(slot_entry(s), s.finest);
      }
      return;
    }
    const auto [begin, end] = leaf_range(p);
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t k = 0; k < 8; ++k) put(corner_entry(grid, fresh[i], k), fresh[i].depth);
    }
  };
  // Per part and bucket: its entries, then its next place.
  std::vector<BigVector<std::uint32_t>> at(parts);
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
      if (p == 0 && t.slots.empty()) return;
      at[p].assign(nb, 0);
      BigVector<std::uint32_t>& c = at[p];
      each(p, [&](std::uint64_t e, std::uint8_t) { ++c[n.bucket(e >> 3)]; });
    });
  });
  // Places, in blocks of buckets: each block's total, a scan over the blocks, then each block
  // turns its counts into places.
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (nb + kBlock - 1) / kBlock;
  std::vector<std::size_t> before(blocks + 1, 0);
  const auto block_end = [&](std::size_t b) { return std::min(nb, (b + 1) * kBlock); };
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::size_t k = 0;
      for (std::size_t p = 0; p < parts; ++p) {
        if (at[p].empty()) continue;
        for (std::size_t j = b * kBlock; j < block_end(b); ++j) k += at[p][j];
      }
      before[b + 1] = k;
    });
  });
  for (std::size_t b = 0; b < blocks; ++b) before[b + 1] += before[b];
  const std::size_t total = before[blocks];
  start.assign(nb + 1, 0);
  start[nb] = std::uint32_t(total);
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::size_t next = before[b];
      for (std::size_t j = b * kBlock; j < block_end(b); ++j) {
        start[j] = std::uint32_t(next);
        for (std::size_t p = 0; p < parts; ++p) {
          if (at[p].empty()) continue;
          next += std::exchange(at[p][j], std::uint32_t(next));
        }
      }
    });
  });
  Entries out;
  out.code.resize(total);
  out.depth.resize(total);
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
      if (at[p].empty()) return;
      BigVector<std::uint32_t>& c = at[p];
      each(p, [&](std::uint64_t e, std::uint8_t depth) {
        const std::uint32_t j = c[n.bucket(e >> 3)]++;
        out.code[j] = e;
        out.depth[j] = depth;
      });
    });
  });
  return out;
}

/// Keeps one entry per point of e[0..n), the one with the smallest code, in e[0..returned), with
/// the largest of the point's depths d[0..n) beside it in d[0..returned), through a hash table in
/// `scratch` (one bucket's entries fit the cache).
struct DedupeScratch {
  std::vector<std::uint64_t> code;
  std::vector<std::uint8_t> depth;
};
std::uint32_t dedupe(std::uint64_t* e, std::uint8_t* d, std::size_t n, DedupeScratch& scratch) {
  if (n == 0) return 0;
  std::size_t size = 2;
  while (size < 2 * n) size *= 2;
  scratch.code.assign(size, VertexTable::kNone);
  scratch.depth.assign(size, 0);
  std::uint32_t unique = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t h = VertexTable::home(e[i] >> 3, size);
    while (scratch.code[h] != VertexTable::kNone && (scratch.code[h] >> 3) != (e[i] >> 3)) {
      h = (h + 1) & (size - 1);
    }
    if (scratch.code[h] == VertexTable::kNone) ++unique;
    scratch.code[h] = std::min(scratch.code[h], e[i]);
    scratch.depth[h] = std::max(scratch.depth[h], d[i]);
  }
  std::uint32_t k = 0;
  for (std::size_t h = 0; h < size; ++h) {
    if (scratch.code[h] == VertexTable::kNone) continue;
    e[k] = scratch.code[h];
    d[k++] = scratch.depth[h];
  }
  return unique;
}

/// Puts entry e (a point not in the table, the finest leaf at it of depth `depth`) into the region
/// of its bucket b, which has room.
void put(VertexTable& t, std::uint64_t e, std::uint8_t depth, std::size_t b) {
  const Key key = e >> 3;
  const std::uint64_t code = e & 7;
  const std::uint32_t base = t.region[b], size = t.region[b + 1] - base;
  std::size_t h = VertexTable::home(key, size);
  while (t.slots[base + h].key != VertexTable::kNone) h = (h + 1) & (size - 1);
  VertexTable::Slot& s = t.slots[base + h];
  s.key = key;
  s.sign = (code == 1 || code == 4) ? 1 : -1;
  s.uncertain = code == 2 ? 1 : (code >= 5 ? 2 : 0);
  s.finest = depth;
}

/// Adds the new points among `entries` (corners of new leaves) to the table in place: false,
/// with some added, when a region would be more than 3/4 full (the table is then rebuilt, each
/// region at most half full).
/// Points already in the table get the finest depth of the new leaves at them.
bool add_in_place(VertexTable& t, const Entries& in) {
  // By code (so a point's entries follow each other, the smallest code first), with its depth.
  std::vector<std::pair<std::uint64_t, std::uint8_t>> entries(in.code.size());
  for (std::size_t i = 0; i < entries.size(); ++i) entries[i] = {in.code[i], in.depth[i]};
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i < entries.size();) {
    const Key key = entries[i].first >> 3;
    std::size_t j = i;
    std::uint8_t depth = 0;
    for (; j < entries.size() && (entries[j].first >> 3) == key; ++j) {
      depth = std::max(depth, entries[j].second);
    }
    if (VertexTable::Slot* s = t.find(key)) {
      s->finest = std::max(s->finest, depth);
    } else {
      const std::size_t b = t.bucket(key);
      if (4 * (t.used[b] + 1) > 3 * (t.region[b + 1] - t.region[b])) return false;
      put(t, entries[i].first, depth, b);
      ++t.used[b];
    }
    i = j;
  }
  return true;
}

/// Evaluates the signs of the slots marked to evaluate, in parallel.
void evaluate_signs(VertexTable& t, const Grid& grid, ThreadEvaluators& evals, const Exec& exec) {
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.slots.size(), 4096), [&](auto r) {
      RoundingScope scope;
      Evaluators& e = *evals.local();
      // point_sign() of each point, 8 points to a batch (the same intervals).
      constexpr int kLanes = BatchIntervalEval::kLanes;
      std::array<VertexTable::Slot*, kLanes> todo;
      std::array<IBox, kLanes> points;
      std::array<Interval, kLanes> values;
      int n = 0;
      auto flush = [&] {
        e.batch.eval(points.data(), n, values.data());
        e.evaluations += std::uint64_t(n);
        for (int j = 0; j < n; ++j) {
          const Interval& v = values[std::size_t(j)];
          std::int8_t s = 0;
          if (!e.batch.partial_domain(j) && !v.is_empty())
            s = v.lo() > 0.0 ? 1 : (v.hi() <= 0.0 ? -1 : 0);
          todo[std::size_t(j)]->sign = s == 0 ? -1 : s;
          todo[std::size_t(j)]->uncertain = s == 0;
        }
        n = 0;
      };
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        VertexTable::Slot& v = t.slots[i];
        if (v.key == VertexTable::kNone || v.uncertain != 2) continue;
        const Vec3 p = grid.point(key_point(v.key));
        todo[std::size_t(n)] = &v;
        points[std::size_t(n)] = IBox(Interval(p.x), Interval(p.y), Interval(p.z));
        if (++n == kLanes) flush();
      }
      if (n > 0) flush();
    });
  });
}

/// Adds the corners of `fresh` (all leaves, or the refinement of split ones) to the table, each
/// with what is known of its sign: proved by an empty leaf, else evaluated. Points already in the
/// table keep theirs. They go into the regions in place if there is room; otherwise the table is
/// rebuilt, in parallel over buckets.
void add_vertices(VertexTable& t, const Grid& grid, const Leaves& fresh, ThreadEvaluators& evals,
                  const Exec& exec) {
  if (!t.slots.empty()) {
    if (add_in_place(t, corner_entries(grid, fresh, exec))) {
      return evaluate_signs(t, grid, evals, exec);
    }
  }
  std::size_t points = 8 * fresh.size();
  for (const VertexTable::Slot& s : t.slots) points += s.key != VertexTable::kNone;
  VertexTable n;
  choose_buckets(n, grid, points);
  n.region.assign(std::size_t{n.buckets[0]} * n.buckets[1] * n.buckets[2] + 1, 0);
  std::vector<std::uint32_t> start;
  Entries entries = bucketed_entries(t, n, grid, fresh, start, exec);
  const std::size_t nb = n.region.size() - 1;
  std::vector<std::uint32_t> unique(nb, 0);
  tbb::enumerable_thread_specific<DedupeScratch> scratch;
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 256), [&](auto r) {
      for (std::size_t b = r.begin(); b < r.end(); ++b) {
        unique[b] = dedupe(entries.code.data() + start[b], entries.depth.data() + start[b],
                           start[b + 1] - start[b], scratch.local());
      }
    });
  });
  for (std::size_t b = 0; b < nb; ++b) {
    std::uint32_t size = unique[b] == 0 ? 0 : 2;
    while (size < 2 * unique[b]) size *= 2;
    n.region[b + 1] = n.region[b] + size;
  }
  n.slots.assign(n.region.back(), VertexTable::Slot{VertexTable::kNone, 0, 0, 0});
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 256), [&](auto r) {
      for (std::size_t b = r.begin(); b < r.end(); ++b) {
        for (std::size_t i = 0; i < unique[b]; ++i) {
          put(n, entries.code[start[b] + i], entries.depth[start[b] + i], b);
        }
      }
    });
  });
  n.used = std::move(unique);
  t = std::move(n);
  evaluate_signs(t, grid, evals, exec);
}

/// A mesh vertex on an edge piece: its id (lower end's key and axis), and its ends.
struct Crossing {
  Key id;
  Key lo, hi;
  int axis;
};

/// What extraction produced for one leaf.
struct CellOut {
  bool split = false;      ///< a global rule failed: split the leaf (or, at max depth, give up)
  bool uncertain = false;  ///< a corner's sign was not decided
  bool blocked = false;    ///< a finer neighbour's piece or edge failed a rule
  /// A segment strays from the surface (a thin rim cut back): split for fidelity, which is no
  /// rule, so a leaf that cannot be split for it stays certified.
  bool refine = false;
  std::uint64_t open_chains = 0;
  /// From the extracting thread's arena (Round::arenas), or, decoded from another process, from
  /// operator new.
  ArenaVector<std::pair<Key, Vec3>> crossings;  ///< local vertices 0..n-1
  ArenaVector<Vec3> centres;                    ///< local vertices n..
  ArenaVector<std::array<std::uint32_t, 3>> triangles;

  CellOut() = default;
  explicit CellOut(Arena* a)
      : crossings(ArenaAllocator<std::pair<Key, Vec3>>(a)),
        centres(ArenaAllocator<Vec3>(a)),
        triangles(ArenaAllocator<std::array<std::uint32_t, 3>>(a)) {}
};

/// The crossings one extractor placed, by id: up to four leaves share an edge piece, and each
/// placement (regula falsi, several evaluations of f) is kept for the leaves after it. Open
/// addressing in one array: a node-based map allocated once per crossing.
class PlacedCrossings {
 public:
  const Vec3* find(Key id) const {
    if (slots_.empty()) return nullptr;
    for (std::size_t h = slot_of(id);; h = (h + 1) & (slots_.size() - 1)) {
      if (slots_[h].first == id) return &slots_[h].second;
      if (slots_[h].first == kNone) return nullptr;
    }
  }
  /// Adds id (not present) at p; returns p.
  const Vec3& insert(Key id, const Vec3& p) {
    if (4 * (used_ + 1) > 3 * slots_.size()) grow();
    std::size_t h = slot_of(id);
    while (slots_[h].first != kNone) h = (h + 1) & (slots_.size() - 1);
    slots_[h] = {id, p};
    ++used_;
    return slots_[h].second;
  }

 private:
  // An id is an edge's lower end (at most 60 bits) shifted by 2: never all ones.
  static constexpr Key kNone = ~Key{0};
  std::size_t slot_of(Key id) const { return VertexTable::home(id, slots_.size()); }
  void grow() {
    std::vector<std::pair<Key, Vec3>> old(std::max<std::size_t>(1024, 2 * slots_.size()),
                                          {kNone, Vec3{}});
    old.swap(slots_);
    used_ = 0;
    for (const auto& [id, p] : old) {
      if (id != kNone) insert(id, p);
    }
  }
  std::vector<std::pair<Key, Vec3>> slots_;
  std::size_t used_ = 0;
};

class Extractor {
 public:
  Extractor(const Grid& g, const VertexTable& t, const CertifiedMeshSettings& s, Evaluators& e,
            Arena& arena)
      : grid_(g), table_(t), settings_(s), e_(e), arena_(arena) {}

  CellOut run(const Leaf& leaf) {
    leaf_ = leaf;
    size_ = grid_.size(leaf.depth);
    certify_ = leaf.kind == Kind::kCertified;
    out_ = CellOut(&arena_);
    segments_.clear();
    crossings_.clear();
    if (quiet()) return std::move(out_);
    if (!finer_ && settings_.simple_leaves && simple()) {
      loops();
      return std::move(out_);
    }
    for (int a = 0; a < 3; ++a) {
      for (int side = 0; side < 2; ++side) face(a, side);
    }
    loops();
    return std::move(out_);
  }

 private:
  // True when the leaf's boundary holds no crossing, seen cheaply: its 8 corners have one sign
  // and no finer neighbour puts a corner on its faces or edges (every such corner would make a
  // face centre or an edge midpoint a leaf corner). Most leaves are quiet.
  bool quiet() {
    const Index3& p = leaf_.at;
    const std::uint32_t s = size_, h = s / 2;
    finer_ = false;
    bool same = true, maybe_finer = false;
    for (std::uint32_t k = 0; k < 8; ++k) {
      corner_keys_[k] =
          make_key({p[0] + (k & 1) * s, p[1] + ((k >> 1) & 1) * s, p[2] + ((k >> 2) & 1) * s});
      const VertexTable::Slot* slot = lookup(corner_keys_[k]);
      corner_signs_[k] = table_sign(slot);
      corner_finer_[k] = slot && slot->finest > leaf_.depth;
      maybe_finer = maybe_finer || corner_finer_[k];
      same = same && corner_signs_[k] == corner_signs_[0];
    }
    // Face centres (one coordinate at 0 or s, the others at h) and edge midpoints (one at h):
    // looked up only where a corner's finest leaf is finer than this one (VertexTable::Slot).
    for (std::uint32_t k = 0; k < 27 && s > 1 && maybe_finer && !finer_; ++k) {
      const std::uint32_t c[3] = {k % 3, (k / 3) % 3, k / 9};
      const int mids = (c[0] == 1) + (c[1] == 1) + (c[2] == 1);
      if (mids != 1 && mids != 2) continue;
      Index3 q;
      for (std::size_t a = 0; a < 3; ++a) q[a] = p[a] + (c[a] == 0 ? 0 : (c[a] == 1 ? h : s));
      finer_ = lookup(make_key(q)) != nullptr;
    }
    return same && !finer_;
  }

  // What face() finds on the 6 faces of a leaf without finer neighbours, as a function of the
  // signs at its corners alone (bit k: corner k positive): its crossings as leaf edges (lower
  // corner, upper corner) and its segments (indices of the up and down crossings), in face()'s
  // order. A face with 4 crossings needs f at its centre: such a leaf is `ambiguous` and takes
  // face() (which also marks it to split).
  struct SimpleCase {
    bool ambiguous = false;
    std::uint8_t crossings = 0, segments = 0;
    std::array<std::array<std::uint8_t, 2>, 12> edge{};
    std::array<std::array<std::uint8_t, 2>, 12> segment{};
  };
  static const std::array<SimpleCase, 256>& simple_cases() {
    static const std::array<SimpleCase, 256> table = [] {
      std::array<SimpleCase, 256> t{};
      for (unsigned signs = 0; signs < 256; ++signs) {
        SimpleCase& c = t[signs];
        auto positive = [&](int k) { return ((signs >> k) & 1u) != 0; };
        for (int f = 0; f < 6 && !c.ambiguous; ++f) {
          const int a = f / 2, side = f % 2;
          // piece()'s cycle of a whole face, and pair_crossings() over it.
          std::array<int, 4> cycle{};
          for (int i = 0; i < 4; ++i) cycle[std::size_t(i)] = face_corner(a, side, kDu[i], kDv[i]);
          if (side == 0) std::reverse(cycle.begin(), cycle.end());
          std::array<std::uint8_t, 4> xs{};
          std::array<bool, 4> up{};
          std::size_t n = 0;
          for (std::size_t i = 0; i < 4; ++i) {
            const int p = cycle[i], q = cycle[(i + 1) % 4];
            if (positive(p) == positive(q)) continue;
            // p and q differ in one bit: the lower corner along that axis has the smaller index.
            const auto lo = std::uint8_t(std::min(p, q)), hi = std::uint8_t(std::max(p, q));
            std::uint8_t x = 0;
            while (x < c.crossings && c.edge[x] != std::array<std::uint8_t, 2>{lo, hi}) ++x;
            if (x == c.crossings) c.edge[c.crossings++] = {lo, hi};
            xs[n] = x;
            up[n++] = !positive(p);
          }
          if (n > 2) {
            c.ambiguous = true;
          } else if (n == 2) {
            c.segment[c.segments++] = up[0] ? std::array<std::uint8_t, 2>{xs[0], xs[1]}
                                            : std::array<std::uint8_t, 2>{xs[1], xs[0]};
          }
        }
      }
      return t;
    }();
    return table;
  }

  // The crossings and segments of a leaf without finer neighbours from simple_cases(), exactly as
  // face() would make them (about half the leaves that hold crossings on the thin torus); false,
  // with nothing made, when a face is ambiguous.
  bool simple() {
    unsigned signs = 0;
    for (unsigned k = 0; k < 8; ++k) signs |= unsigned(corner_signs_[k] > 0) << k;
    const SimpleCase& c = simple_cases()[signs];
    if (c.ambiguous) return false;
    for (std::size_t i = 0; i < c.crossings; ++i) {
      const Key lo = corner_keys_[c.edge[i][0]], hi = corner_keys_[c.edge[i][1]];
      const int axis = std::countr_zero(unsigned(c.edge[i][0] ^ c.edge[i][1]));
      crossings_.push_back({(lo << 2) | Key(axis), lo, hi, axis});
    }
    for (std::size_t i = 0; i < c.segments; ++i) {
      segments_.emplace_back(crossings_[c.segment[i][0]].id, crossings_[c.segment[i][1]].id);
    }
    return true;
  }

  // The key of the point at w along axis a and (u, v) along the axes after it: make_key() of
  // that point, with the fields' shifts looked up instead of the axes computed modulo 3.
  static Key key_at(int a, std::uint32_t w, std::uint32_t u, std::uint32_t v) {
    static constexpr int kShift[3][3] = {
        {0, kKeyBits, 2 * kKeyBits}, {kKeyBits, 2 * kKeyBits, 0}, {2 * kKeyBits, 0, kKeyBits}};
    const int* sh = kShift[a];
    return Key(w) << sh[0] | Key(u) << sh[1] | Key(v) << sh[2];
  }

  // The leaf corner at (du, dv) (0 or 1 each, along the axes after a) of face (a, side).
  static constexpr int kDu[4] = {0, 1, 1, 0}, kDv[4] = {0, 0, 1, 1};
  static int face_corner(int a, int side, int du, int dv) {
    return side << a | du << ((a + 1) % 3) | dv << ((a + 2) % 3);
  }

  // Cuts face (a, side) into the pieces that the leaves on its other side make. A finer leaf
  // with a corner on the face (its sides included) has a finer leaf at one of the face's
  // corners, and one with a corner on a side at one of the side's ends (VertexTable::Slot): so
  // only such faces and sides are looked up.
  void face(int a, int side) {
    const std::uint32_t w = leaf_.at[std::size_t(a)] + (side ? size_ : 0);
    // The face's corners in the order of piece()'s cycle (kDu, kDv); side k of the cycle runs
    // from its corner k to corner k + 1.
    for (int i = 0; i < 4; ++i)
      face_corners_[std::size_t(i)] = face_corner(a, side, kDu[i], kDv[i]);
    for (std::size_t k = 0; k < 4; ++k) {
      side_finer_[k] = corner_finer_[std::size_t(face_corners_[k])] ||
                       corner_finer_[std::size_t(face_corners_[(k + 1) % 4])];
    }
    face_finer_ = finer_ && (side_finer_[0] || side_finer_[2]);
    piece(a, side, w, leaf_.at[std::size_t((a + 1) % 3)], leaf_.at[std::size_t((a + 2) % 3)],
          size_);
  }

  void piece(int a, int side, std::uint32_t w, std::uint32_t u0, std::uint32_t v0,
             std::uint32_t s) {
    const std::uint32_t h = s / 2;
    if (s > 1 && face_finer_ && lookup(key_at(a, w, u0 + h, v0 + h))) {
      for (int k = 0; k < 4; ++k) piece(a, side, w, u0 + (k & 1) * h, v0 + (k >> 1) * h, h);
      return;
    }
    // The piece's boundary, counter-clockwise seen from outside the leaf, with the sign at
    // each point: a corner of the whole face is a leaf corner, whose sign quiet() read.
    cycle_.clear();
    cycle_signs_.clear();
    const std::array<std::array<std::uint32_t, 2>, 4> c = {
        {{u0, v0}, {u0 + s, v0}, {u0 + s, v0 + s}, {u0, v0 + s}}};
    for (int i = 0; i < 4; ++i) {
      const auto& p = c[std::size_t(i)];
      const auto& q = c[std::size_t((i + 1) % 4)];
      const Key k = key_at(a, w, p[0], p[1]);
      cycle_.push_back(k);
      cycle_signs_.push_back(s == size_ ? corner_signs_[std::size_t(face_corners_[std::size_t(i)])]
                                        : sign(k));
      // A side of the whole face: looked up only where one of its ends has a finer leaf.
      if (s < size_ || side_finer_[std::size_t(i)]) side_points(a, w, p, q, s);
    }
    if (side == 0) {
      std::reverse(cycle_.begin(), cycle_.end());
      std::reverse(cycle_signs_.begin(), cycle_signs_.end());
    }
    pair_crossings(a, w, u0, v0, s);
  }

  // Appends the leaf corners strictly between p and q (a side of a piece), in order.
  void side_points(int a, std::uint32_t w, std::array<std::uint32_t, 2> p,
                   std::array<std::uint32_t, 2> q, std::uint32_t len) {
    if (len < 2) return;
    const std::array<std::uint32_t, 2> m = {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2};
    const Key km = key_at(a, w, m[0], m[1]);
    if (!face_finer_) return;
    const VertexTable::Slot* slot = lookup(km);
    if (!slot) return;
    side_points(a, w, p, m, len / 2);
    cycle_.push_back(km);
    // Strictly inside a side of a piece: not a corner of the leaf.
    cycle_signs_.push_back(table_sign(slot));
    side_points(a, w, m, q, len / 2);
  }

  // The sign at a cycle point: one of the leaf's corners (read once by quiet()) or another.
  std::int8_t sign(Key k) {
    for (std::size_t i = 0; i < 8; ++i) {
      if (corner_keys_[i] == k) return corner_signs_[i];
    }
    return table_sign(k);
  }

  std::int8_t table_sign(Key k) { return table_sign(lookup(k)); }

  // The table's slot of k (null if none), through a direct-mapped cache of recent lookups: a
  // corner is shared by up to 8 leaves, a face centre or edge midpoint is asked for by quiet()
  // and by the faces being cut, a piece's corners and sides by the pieces next to it, and a
  // face by the leaves on both its sides, which come close together in the leaves' order. The
  // table does not change while an extractor lives (one round's extraction).
  const VertexTable::Slot* lookup(Key k) {
    Memo& m = memo_[std::size_t((k * 0x9E3779B97F4A7C15ull) >> (64 - kMemoBits))];
    if (m.key != k) m = {k, table_.find(k)};
    return m.slot;
  }
  std::int8_t table_sign(const VertexTable::Slot* s) {
    if (!s) {  // cannot happen: every cycle point is a leaf corner
      out_.uncertain = true;
      return -1;
    }
    if (s->uncertain) out_.uncertain = true;
    return s->sign;
  }

  // The crossings of one piece, paired into segments (up crossing to down crossing).
  void pair_crossings(int a, std::uint32_t w, std::uint32_t u0, std::uint32_t v0, std::uint32_t s) {
    const std::size_t n = cycle_.size();
    std::vector<std::pair<Key, bool>>& xs = piece_crossings_;  // crossing id, up (- to +)
    xs.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const Key p = cycle_[i], q = cycle_[j];
      check_inner_edge(p, q);
      const std::int8_t sp = cycle_signs_[i], sq = cycle_signs_[j];
      if (sp == sq) continue;
      xs.emplace_back(add_crossing(p, q), sp < 0);
    }
    if (xs.empty()) return;
    if (xs.size() > 2) {
      // Splitting the leaf that owns the piece (the finer side) resolves it; a coarser leaf that
      // only sees the piece waits for that and is uncertified if it never happens.
      (s == size_ ? out_.split : out_.blocked) = true;
      // Best effort: the sign at the piece's centre says which side is connected.
      const Vec3 centre = grid_.point(key_point(key_at(a, w, u0 + s / 2, v0 + s / 2)));
      const Vec3 mid = s > 1 ? centre
                             : 0.5 * (grid_.point(key_point(key_at(a, w, u0, v0))) +
                                      grid_.point(key_point(key_at(a, w, u0 + s, v0 + s))));
      const bool negative_connected = point_sign(e_, mid) <= 0;
      const std::size_t m = xs.size();
      for (std::size_t i = 0; i < m; ++i) {
        if (!xs[i].second) continue;
        const std::size_t j = negative_connected ? (i + 1) % m : (i + m - 1) % m;
        segments_.emplace_back(xs[i].first, xs[j].first);
      }
      return;
    }
    if (xs[0].second)
      segments_.emplace_back(xs[0].first, xs[1].first);
    else
      segments_.emplace_back(xs[1].first, xs[0].first);
  }

  // An edge piece inside a face of this leaf lies on an edge of a finer neighbour, which this
  // leaf's own edge checks do not cover: check it here.
  void check_inner_edge(Key p, Key q) {
    if (!certify_ || !settings_.strict) return;
    // The two pieces on either side of an inner edge walk it in opposite directions, and the
    // check does not depend on the direction: do it once.
    if (q < p) return;
    const Index3 ip = key_point(p), iq = key_point(q);
    int axis = 0;
    while (axis < 2 && ip[std::size_t(axis)] == iq[std::size_t(axis)]) ++axis;
    for (int b = 0; b < 3; ++b) {
      if (b == axis) continue;
      const std::uint32_t c = ip[std::size_t(b)], lo = leaf_.at[std::size_t(b)];
      if (c != lo && c != lo + size_) {
        Box3 ed{grid_.point(ip), grid_.point(iq)};
        for (int k = 0; k < 3; ++k) {
          if (ed.lo[k] > ed.hi[k]) std::swap(ed.lo[k], ed.hi[k]);
        }
        if (!edge_ok(e_, ed, axis)) out_.blocked = true;  // the finer neighbour's edge
        return;
      }
    }
  }

  Key add_crossing(Key p, Key q) {
    const Index3 ip = key_point(p), iq = key_point(q);
    int axis = 0;
    while (axis < 2 && ip[std::size_t(axis)] == iq[std::size_t(axis)]) ++axis;
    const bool p_low = ip[std::size_t(axis)] < iq[std::size_t(axis)];
    const Key lo = p_low ? p : q, hi = p_low ? q : p;
    const Key id = (lo << 2) | Key(axis);
    for (const Crossing& c : crossings_) {
      if (c.id == id) return id;
    }
    crossings_.push_back({id, lo, hi, axis});
    return id;
  }

  // Regula falsi (Illinois) on the edge piece; the bracket keeps the vertex on it. The vertex
  // stays 2^-20 of the piece away from its ends: a corner where f = 0 counts as negative (the
  // mesh follows f = delta for a small delta > 0), so the crossing lies just off that corner, and
  // the crossings of the several edges that meet there stay distinct.
  Vec3 place(const Crossing& c) {
    const Vec3 a = grid_.point(key_point(c.lo)), b = grid_.point(key_point(c.hi));
    double ta = 0, tb = 1;
    double fa = e_.p.eval(a), fb = e_.p.eval(b);
    auto at = [&](double t) {
      constexpr double kOff = 0x1p-20;
      Vec3 p = a;
      p[c.axis] = a[c.axis] + std::clamp(t, kOff, 1 - kOff) * (b[c.axis] - a[c.axis]);
      return p;
    };
    if (!(std::isfinite(fa) && std::isfinite(fb)) || (fa > 0) == (fb > 0)) return at(0.5);
    int side = 0;
    double last = -1;
    for (int i = 0; i < settings_.edge_steps; ++i) {
      double t = (ta * fb - tb * fa) / (fb - fa);
      if (!(t > ta && t < tb)) t = 0.5 * (ta + tb);
      if (std::fabs(t - last) < 1e-12) break;  // converged: further steps move it by less
      last = t;
      const double ft = e_.p.eval(at(t));
      if (!std::isfinite(ft) || ft == 0) return at(t);
      if ((ft > 0) == (fa > 0)) {
        ta = t, fa = ft;
        if (side == -1) fb *= 0.5;
        side = -1;
      } else {
        tb = t, fb = ft;
        if (side == 1) fa *= 0.5;
        side = 1;
      }
    }
    return at((ta * fb - tb * fa) / (fb - fa));
  }

  // Places the leaf's crossings (out_.crossings, in the order of crossings_).
  void place_crossings() {
    out_.crossings.clear();
    // Exact sizes: these vectors are made for some 100 000 leaves, and growing them by doubling
    // would allocate each several times.
    out_.crossings.reserve(crossings_.size());
    out_.triangles.reserve(segments_.size());  // a loop of m > 3 segments gives m triangles
    for (const Crossing& c : crossings_) {
      // Up to four leaves share an edge piece: each placement is kept for the leaves after it.
      const Vec3* at = placed_.find(c.id);
      out_.crossings.emplace_back(c.id, at ? *at : placed_.insert(c.id, place(c)));
    }
  }

  std::uint32_t local(Key id) const {
    for (std::size_t i = 0; i < out_.crossings.size(); ++i) {
      if (out_.crossings[i].first == id) return std::uint32_t(i);
    }
    return 0;
  }

  // Follows the segments from segment s0 into loop_ (local vertex numbers); false when the chain
  // does not close.
  bool chain(std::size_t s0) {
    loop_.clear();
    for (std::size_t s = s0;;) {
      used_[s] = true;
      loop_.push_back(local(segments_[s].first));
      const Key next = segments_[s].second;
      if (next == segments_[s0].first) return true;
      std::size_t t = 0;
      while (t < segments_.size() && (used_[t] || segments_[t].first != next)) ++t;
      if (t == segments_.size()) return false;
      s = t;
    }
  }

  // Chains the segments into loops and fans each loop.
  void loops() {
    if (segments_.empty()) return;
    place_crossings();
    used_.assign(segments_.size(), 0);
    bent_ = false;
    int n_loops = 0;
    for (std::size_t s0 = 0; s0 < segments_.size(); ++s0) {
      if (used_[s0]) continue;
      if (!chain(s0)) {
        ++out_.open_chains;
        out_.split = true;
        continue;
      }
      ++n_loops;
      fan(loop_);
    }
    if (n_loops > 1) out_.split = true;
    // Only a leaf that stays certified is split for fidelity: elsewhere its children would add
    // uncertified cells, not fidelity.
    const bool certified = certify_ && !out_.split && !out_.blocked && !out_.uncertain;
    if (certified && bent_ && !leaf_.keep && leaf_.depth < settings_.min_depth + kFidelityLevels) {
      check_segments();
    }
  }

  // A segment across a face piece is a chord of the surface's arc there. Where the surface turns
  // through 180 degrees within the piece, as at a thin blade's rim, the chord cuts the rim back by
  // up to the piece's size, and no fan centre in either leaf can restore it: the leaf is split
  // when the Newton step from a segment's midpoint is longer than kFidelityTolerance of the
  // leaf's shortest edge, at most kFidelityLevels below min_depth.
  static constexpr int kFidelityLevels = 1;
  static constexpr double kFidelityTolerance = 0.25;
  void check_segments() {
    const double tol = kFidelityTolerance * shortest_edge(grid_.box(leaf_.at, size_));
    for (const auto& [from, to] : segments_) {
      const Vec3 m = 0.5 * (out_.crossings[local(from)].second + out_.crossings[local(to)].second);
      const PGrad g = e_.pg.eval(m);
      if (std::isfinite(g.v) && std::fabs(g.v) > tol * std::sqrt(dot(g.g, g.g))) {
        out_.refine = true;
        return;
      }
    }
  }

  void fan(const std::vector<std::uint32_t>& loop) {
    const std::size_t m = loop.size();
    if (m < 3) {
      out_.split = true;
      return;
    }
    if (m == 3) {
      out_.triangles.push_back({loop[0], loop[2], loop[1]});
      return;
    }
    std::vector<Vec3>& p = points_;
    p.resize(m);
    Vec3 mean{};
    for (std::size_t i = 0; i < m; ++i) {
      p[i] = out_.crossings[loop[i]].second;
      mean = mean + p[i];
    }
    mean = mean / double(m);
    const Box3 box = grid_.box(leaf_.at, size_);
    const Vec3 pulled = pull(clamp_inside(mean, box), box);
    bent_ = bent_ || bent(p, mean, pulled, box);
    Vec3 c = pulled;
    if (!fan_embeds(p, c)) {
      c = clamp_inside(mean, box);
      if (!fan_embeds(p, c)) out_.split = true;
    }
    const auto ci = std::uint32_t(out_.crossings.size() + out_.centres.size());
    out_.centres.push_back(c);
    for (std::size_t i = 0; i < m; ++i) {
      out_.triangles.push_back({ci, loop[(i + 1) % m], loop[i]});
    }
  }

  // True when the fan's centre, pulled onto the surface, lies farther than kBendGate of the
  // leaf's shortest edge from the loop's mean plane: the surface bends within the leaf, and its
  // segments are worth checking (check_segments).
  static constexpr double kBendGate = 0.1;
  static bool bent(const std::vector<Vec3>& p, const Vec3& mean, const Vec3& c, const Box3& b) {
    Vec3 n{};
    for (std::size_t i = 0; i < p.size(); ++i)
      n = n + cross(p[i] - mean, p[(i + 1) % p.size()] - mean);
    const double n2 = dot(n, n), off = dot(c - mean, n);
    return n2 > 0 && off * off > kBendGate * kBendGate * shortest_edge(b) * shortest_edge(b) * n2;
  }

  static double shortest_edge(const Box3& b) {
    return std::min({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  }

  static Vec3 clamp_inside(Vec3 p, const Box3& b) {
    for (int a = 0; a < 3; ++a) {
      const double margin = 1e-3 * (b.hi[a] - b.lo[a]);
      p[a] = std::clamp(p[a], b.lo[a] + margin, b.hi[a] - margin);
    }
    return p;
  }

  // Newton steps towards f = 0 along the gradient, kept inside the cell; a step that does not
  // lower |f| is not taken.
  Vec3 pull(Vec3 c, const Box3& b) {
    PGrad g = e_.pg.eval(c);
    for (int i = 0; i < settings_.centre_steps && std::isfinite(g.v); ++i) {
      const double gg = g.g.x * g.g.x + g.g.y * g.g.y + g.g.z * g.g.z;
      if (!(gg > 0)) break;
      const Vec3 n = clamp_inside(c - (g.v / gg) * g.g, b);
      const PGrad gn = e_.pg.eval(n);
      if (!(std::fabs(gn.v) < std::fabs(g.v))) break;
      c = n, g = gn;
    }
    return c;
  }

  // True when the fan of `p` around `c` projects one-to-one along the loop's Newell normal: all
  // triangles turn the same way and wind once around c. Every turn is positive, so each step
  // turns counter-clockwise by less than pi (seen along n) and the loop winds k >= 1 times; the
  // steps from below the line through c along p[0] - c (y < 0, y measured along n x (p[0] - c))
  // to on or above it pass that line on p[0]'s side, once per winding, so k is their count. (The
  // angles summed with atan2 before cost 1.7 % of the thin torus's instructions.)
  static bool fan_embeds(const std::vector<Vec3>& p, const Vec3& c) {
    const std::size_t m = p.size();
    Vec3 n{};
    // Relative to c: absolute coordinates far from the origin would cancel in the sum.
    for (std::size_t i = 0; i < m; ++i) n = n + cross(p[i] - c, p[(i + 1) % m] - c);
    const Vec3 up = cross(n, p[0] - c);
    int windings = 0;
    double y = dot(p[0] - c, up);
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 a = p[i] - c, b = p[(i + 1) % m] - c;
      if (!(dot(cross(a, b), n) > 0)) return false;
      const double next = dot(b, up);
      windings += y < 0 && next >= 0;
      y = next;
    }
    return windings == 1;
  }

  const Grid& grid_;
  const VertexTable& table_;
  const CertifiedMeshSettings& settings_;
  Evaluators& e_;
  Arena& arena_;  ///< of the leaves' CellOuts
  Leaf leaf_{};
  std::uint32_t size_ = 1;
  bool certify_ = false;
  bool bent_ = false;  ///< a fan of this leaf found the surface bending (bent())
  CellOut out_;
  std::vector<Key> cycle_;
  std::vector<std::int8_t> cycle_signs_;  ///< the sign at each point of cycle_
  std::vector<Crossing> crossings_;
  std::vector<std::pair<Key, Key>> segments_;
  PlacedCrossings placed_;  ///< crossings placed by this extractor (one range of leaves)
  /// The leaf's corners and their signs, and whether a finer neighbour puts corners on its faces.
  std::array<Key, 8> corner_keys_{};
  std::array<std::int8_t, 8> corner_signs_{};
  bool finer_ = false;
  /// Per leaf corner: the finest leaf there is finer than this one; per side of the face being
  /// cut (in the order of piece()'s cycle), one of its ends is such a corner; and one of the
  /// face's corners is.
  std::array<bool, 8> corner_finer_{};
  std::array<bool, 4> side_finer_{};
  std::array<int, 4> face_corners_{};  ///< the leaf corners of the face being cut, by cycle point
  bool face_finer_ = false;
  struct Memo {
    Key key = VertexTable::kNone;  // never a point's key
    const VertexTable::Slot* slot = nullptr;
  };
  static constexpr int kMemoBits = 10;
  std::array<Memo, std::size_t{1} << kMemoBits> memo_{};
  // Scratch space kept between leaves.
  std::vector<std::pair<Key, bool>> piece_crossings_;
  std::vector<std::uint32_t> loop_;
  std::vector<std::uint8_t> used_;
  std::vector<Vec3> points_;
};

Grid make_grid(const CertifiedMeshSettings& s) {
  Grid g;
  g.bounds = s.bounds;
  const Vec3 size = s.bounds.size();
  const double shortest = std::fmin(size.x, std::fmin(size.y, size.z));
  const int cap = static_cast<int>(std::ceil(std::log2(s.max_roots_per_axis)));
  for (int a = 0; a < 3; ++a) {
    const int bits = static_cast<int>(std::lround(std::log2(size[a] / shortest)));
    g.root_bits[std::size_t(a)] = std::clamp(bits, 0, cap);
  }
  g.max_depth = s.max_depth;
  return g;
}

/// What the loops shared with other processes add up to (refine_spread(), extract_spread()).
struct SpreadTally {
  /// Interval evaluations of the items other processes computed (subtrees refined, leaves
  /// extracted): added to this process's own count, they make the one-process count.
  std::uint64_t remote_evaluations = 0;
  SpreadBalance balance;  ///< per process, summed over the loops

  void add(const SpreadBalance& b) {
    if (balance.ranks.empty()) balance.ranks.resize(b.ranks.size());
    for (std::size_t k = 0; k < b.ranks.size(); ++k) {
      RankLoad& l = balance.ranks[k];
      l.items += b.ranks[k].items;
      l.work += b.ranks[k].work;
      l.busy += b.ranks[k].busy;
      l.idle += b.ranks[k].idle;
    }
  }
};

static_assert(std::is_trivially_copyable_v<Leaf>, "leaves travel between processes as bytes");

/// Phase 1 over a list of cells shared with other processes (Exec::spread): every process does
/// the first levels below the cells (a few hundred cells: cheap, and the same in each), so that
/// there are enough subtrees to share (at least 256 per process, up to 4 levels); the spread
/// hands the subtrees out, each is refined by one thread of one process, and every process ends
/// with every subtree's leaves, put together in the order of refine_all(): the same leaves.
/// A subtree that would take this process over the box limit is sent as "over the limit", so that
/// every process throws the same error after the loop rather than one alone in the middle of it.
Leaves refine_spread(const Refiner& r, const std::vector<std::pair<Index3, int>>& cells,
                     ThreadEvaluators& evals, const Exec& exec, SpreadTally& tally) {
  Spread& spread = *exec.spread;
  const std::uint64_t before = r.count();
  int levels = 0;
  while (levels < 4 && (cells.size() << (3 * levels)) < 256 * std::size_t(spread.size())) ++levels;
  std::vector<Subtree> tasks;
  {
    RoundingScope scope;
    Evaluators& e = *evals.local();
    for (const auto& c : cells) r.expand_top(e, c.first, c.second, levels, tasks);
  }
  std::vector<std::size_t> items;  // the tasks that are subtrees
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    if (!tasks[t].done) items.push_back(t);
  }
  const std::size_t n = items.size();
  std::vector<std::string> results(n);
  std::vector<std::uint64_t> work(n, 0);
  std::vector<char> mine(n, 0);
  std::atomic<bool> over{false};
  spread.begin(n, nullptr);
  const int threads = exec.resolved_threads();
  exec.run([&] {
    tbb::parallel_for(0, threads, [&](int) {
      RoundingScope scope;
      Evaluators& e = *evals.local();
      Leaves out;
      try {
        for (std::int64_t k = spread.next(); k >= 0; k = spread.next()) {
          const auto i = static_cast<std::size_t>(k);
          mine[i] = 1;
          std::string& res = results[i];
          if (over.load(std::memory_order_relaxed)) {
            put_bytes(res, std::uint8_t{1});
            continue;
          }
          const Subtree& t = tasks[items[i]];
          const std::uint64_t e0 = e.evaluations;
          out.clear();
          try {
            r.refine(e, t.at, t.depth, out, t.has_parent ? &t.parent : nullptr,
                     t.has_own ? &t.own : nullptr, t.tighten_first,
                     t.has_values ? &t.values : nullptr);
          } catch (const SettingError&) {  // this process alone is over the box limit
            over.store(true);
            put_bytes(res, std::uint8_t{1});
            continue;
          }
          work[i] = e.evaluations - e0;
          put_bytes(res, std::uint8_t{0});
          put_values(res, out);
        }
      } catch (...) {
        spread.fail();  // the process's other threads stop too
        throw;
      }
    });
  });
  // This process's leaves were counted as they were made; the count is settled below.
  for (auto& e : evals) e->pending_leaves = 0;
  tally.add(spread.finish(results, work));
  std::size_t total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (results[i][0] != 0) over.store(true);
    total += (results[i].size() - 1) / sizeof(Leaf);
    if (!mine[i]) tally.remote_evaluations += work[i];
  }
  if (over.load()) r.throw_over_limit();
  for (const Subtree& t : tasks) total += t.done;
  r.settle(before + total);
  Leaves leaves;
  leaves.reserve(total);
  std::size_t next = 0;
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    if (tasks[t].done) {
      leaves.push_back(tasks[t].leaf);
      continue;
    }
    const std::string& res = results[next++];
    const bool whole = append_rest(res, 1, leaves);  // after put_bytes(res, std::uint8_t{0})
    IAA_CHECK(whole);
  }
  return leaves;
}

/// Phase 1 over a list of cells, in parallel; leaves in the order of the cells, each cell's
/// leaves depth-first, whatever the thread count (and the number of processes, with
/// Exec::spread and a tally).
Leaves refine_all(const Refiner& r, const std::vector<std::pair<Index3, int>>& cells,
                  ThreadEvaluators& evals, const Exec& exec, SpreadTally* tally = nullptr) {
  if (exec.spread && tally) return refine_spread(r, cells, evals, exec, *tally);
  std::vector<Leaves> parts(cells.size());
  // Few cells (a scene of one root cell): their top levels split in parallel too, so that there
  // are at least 256 tasks.
  int levels = 0;
  while (levels < 3 && (cells.size() << (3 * levels)) < 256) ++levels;
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, cells.size(), [&](std::size_t i) {
      RoundingScope scope;
      r.refine_parallel(evals, cells[i].first, cells[i].second, levels, parts[i]);
    });
  });
  for (auto& e : evals) r.flush(*e);
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  Leaves out;
  out.reserve(total);
  for (auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

/// Per thread, the arena of the CellOuts it extracts (in every round): the CellOuts' arrays are
/// freed with it, at once, when the Round goes.
using CellArenas = tbb::enumerable_thread_specific<Arena>;

struct Round {
  CellArenas arenas;  ///< declared first, so that it outlives `outs`
  VertexTable table;
  BigVector<CellOut> outs;  ///< per leaf (empty for empty leaves)
};

/// Leaves per item of a shared extraction.
constexpr std::size_t kExtractItem = 256;

/// extract_all() shared with other processes (Exec::spread): the leaves in items of
/// kExtractItem; each process extracts the items the spread hands it, and every process ends with
/// every leaf's CellOut. Each leaf's CellOut depends on the leaf and the vertex table alone (the
/// crossings an extractor keeps for the leaves after it are placed the same by any extractor), so
/// they are the one-process ones.
void extract_spread(const Grid& grid, const Leaves& leaves, const VertexTable& table,
                    const CertifiedMeshSettings& s, ThreadEvaluators& evals, const Exec& exec,
                    CellArenas& arenas, BigVector<CellOut>& outs, const std::vector<char>* todo,
                    SpreadTally& tally) {
  Spread& spread = *exec.spread;
  const std::size_t n = (leaves.size() + kExtractItem - 1) / kExtractItem;
  std::vector<std::string> results(n);
  std::vector<std::uint64_t> work(n, 0);
  std::vector<char> mine(n, 0);
  spread.begin(n, nullptr);
  exec.run([&] {
    tbb::parallel_for(0, exec.resolved_threads(), [&](int) {
      RoundingScope scope;
      Evaluators& e = *evals.local();
      try {
        for (std::int64_t k = spread.next(); k >= 0; k = spread.next()) {
          const auto item = static_cast<std::size_t>(k);
          if (exec.progress && exec.progress->cancelled()) throw Error("certified mesh: cancelled");
          mine[item] = 1;
          const std::uint64_t e0 = e.evaluations;
          Extractor x(grid, table, s, e, arenas.local());
          std::string& res = results[item];
          const std::size_t end = std::min(leaves.size(), (item + 1) * kExtractItem);
          for (std::size_t i = item * kExtractItem; i < end; ++i) {
            if ((todo && !(*todo)[i]) || leaves[i].kind == Kind::kEmpty) continue;
            outs[i] = x.run(leaves[i]);
            const CellOut& o = outs[i];
            put_bytes(res, std::uint32_t(i - item * kExtractItem));
            put_bytes(res,
                      std::uint8_t(o.split | o.uncertain << 1 | o.blocked << 2 | o.refine << 3));
            put_bytes(res, o.open_chains);
            put_bytes(res, std::uint64_t(o.crossings.size()));
            for (const auto& [key, p] : o.crossings) {
              put_bytes(res, key);
              put_bytes(res, p);
            }
            put_vector(res, o.centres);
            put_vector(res, o.triangles);
          }
          work[item] = e.evaluations - e0;
        }
      } catch (...) {
        spread.fail();  // the process's other threads stop too
        throw;
      }
    });
  });
  tally.add(spread.finish(results, work));
  for (std::size_t item = 0; item < n; ++item) {
    if (mine[item]) continue;
    tally.remote_evaluations += work[item];
    const std::string& res = results[item];
    std::size_t pos = 0;
    while (pos < res.size()) {
      const std::size_t i = item * kExtractItem + take_bytes<std::uint32_t>(res, pos);
      CellOut& o = outs[i];
      const auto flags = take_bytes<std::uint8_t>(res, pos);
      o.split = flags & 1;
      o.uncertain = flags & 2;
      o.blocked = flags & 4;
      o.refine = flags & 8;
      o.open_chains = take_bytes<std::uint64_t>(res, pos);
      o.crossings.resize(take_bytes<std::uint64_t>(res, pos));
      for (auto& [key, p] : o.crossings) {
        key = take_bytes<Key>(res, pos);
        p = take_bytes<Vec3>(res, pos);
      }
      take_vector(res, pos, o.centres);
      take_vector(res, pos, o.triangles);
    }
  }
}

/// Extraction of every non-empty leaf, or of those `todo` marks (CellOut per leaf, empty for
/// empty leaves); shared with other processes with Exec::spread and a tally.
void extract_all(const Grid& grid, const Leaves& leaves, const VertexTable& table,
                 const CertifiedMeshSettings& s, ThreadEvaluators& evals, const Exec& exec,
                 CellArenas& arenas, BigVector<CellOut>& outs,
                 const std::vector<char>* todo = nullptr, SpreadTally* tally = nullptr) {
  if (exec.spread && tally)
    return extract_spread(grid, leaves, table, s, evals, exec, arenas, outs, todo, *tally);
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 256), [&](auto range) {
      if (exec.progress && exec.progress->cancelled()) throw Error("certified mesh: cancelled");
      RoundingScope scope;
      Extractor x(grid, table, s, *evals.local(), arenas.local());
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        if (todo && !(*todo)[i]) continue;
        outs[i] = leaves[i].kind != Kind::kEmpty ? x.run(leaves[i]) : CellOut{};
      }
    });
  });
}

/// The leaves after a round: the failing certified ones replaced by their refinement.
struct Split {
  Leaves leaves;
  std::vector<std::int64_t> origin;  ///< per leaf: its index before the split, or -1 if new
  Leaves fresh;                      ///< the new leaves
  Leaves split;                      ///< the leaves that were split
};

Split split_failed(const Grid& grid, const Refiner& r, const Leaves& leaves,
                   const BigVector<CellOut>& outs, ThreadEvaluators& evals, const Exec& exec,
                   SpreadTally& tally) {
  Split out;
  std::vector<std::pair<Index3, int>> cells;
  std::vector<std::size_t> where;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const Leaf& l = leaves[i];
    const bool fidelity = outs[i].refine && !l.keep;
    if (l.kind != Kind::kCertified || !(outs[i].split || fidelity) || l.depth == grid.max_depth)
      continue;
    const std::uint32_t h = grid.size(l.depth) / 2;
    for (int k = 0; k < 8; ++k) {
      cells.push_back(
          {{l.at[0] + (k & 1) * h, l.at[1] + ((k >> 1) & 1) * h, l.at[2] + ((k >> 2) & 1) * h},
           l.depth + 1});
    }
    where.push_back(i);
  }
  if (where.empty()) return out;
  const Leaves fresh = refine_all(r, cells, evals, exec, &tally);
  // The new leaves of where[j] follow each other in `fresh`, in the order of `where`.
  out.leaves.reserve(leaves.size() + fresh.size());
  std::size_t next = 0, w = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    if (w < where.size() && where[w] == i) {
      ++w;
      const Leaf& p = leaves[i];
      const std::uint32_t s = grid.size(p.depth);
      auto inside = [&](const Leaf& f) {
        for (std::size_t a = 0; a < 3; ++a) {
          if (f.at[a] < p.at[a] || f.at[a] >= p.at[a] + s) return false;
        }
        return true;
      };
      const std::size_t first = next;
      bool uncertified = false;
      while (next < fresh.size() && inside(fresh[next])) {
        uncertified = uncertified || fresh[next].kind == Kind::kUncertified;
        ++next;
      }
      if (uncertified && !outs[i].split) {
        // A split for fidelity alone that would leave uncertified cells is undone.
        out.leaves.push_back(p);
        out.leaves.back().keep = 1;
        out.origin.push_back(std::int64_t(i));
        continue;
      }
      for (std::size_t k = first; k < next; ++k) {
        out.leaves.push_back(fresh[k]);
        out.origin.push_back(-1);
      }
      out.fresh.insert(out.fresh.end(), fresh.begin() + std::ptrdiff_t(first),
                       fresh.begin() + std::ptrdiff_t(next));
      out.split.push_back(p);
    } else {
      out.leaves.push_back(leaves[i]);
      out.origin.push_back(std::int64_t(i));
    }
  }
  return out;
}

/// Finds the leaves that touch (share a face, an edge or a corner with) a given leaf, through a
/// map of the leaves by depth and position: for each of the leaf's 26 neighbour cells of its own
/// size, the coarser leaf that holds it, or the finer leaves inside it that touch the leaf.
class Neighbours {
 public:
  Neighbours(const Grid& grid, const Leaves& leaves) : grid_(grid) {
    index_.reserve(leaves.size());
    for (std::size_t i = 0; i < leaves.size(); ++i)
      index_.emplace(id(leaves[i].depth, leaves[i].at), i);
    for (std::size_t a = 0; a < 3; ++a)
      extent_[a] = std::int64_t(grid.size(0)) << grid.root_bits[a];
  }

  /// Sets mark[i] for every leaf i that touches `leaf`.
  void mark_around(const Leaf& leaf, std::vector<char>& mark) {
    leaf_ = leaf;
    size_ = grid_.size(leaf.depth);
    mark_ = &mark;
    for (int k = 0; k < 27; ++k) {
      Index3 q;
      if (k != 13 && neighbour_cell(k, q) && !coarser(q)) collect(leaf.depth, q);
    }
  }

 private:
  // A leaf's lower corner is below 2^19 per axis (kGridBits), so make_key(at) fills bits 0..58
  // and the depth (at most kGridBits) fits in bits 59..63.
  static Key id(int depth, const Index3& at) { return (Key(depth) << 59) | make_key(at); }
  static_assert(CertifiedMeshSettings::kGridBits < kKeyBits &&
                    2 * kKeyBits + CertifiedMeshSettings::kGridBits <= 59 &&
                    CertifiedMeshSettings::kGridBits < 32,
                "leaf ids: a corner below 2^kGridBits per axis in bits 0..58, the depth above");

  // The corner of neighbour cell k (offsets -1, 0, 1 per axis, x fastest); false outside the grid.
  bool neighbour_cell(int k, Index3& q) const {
    for (std::size_t a = 0; a < 3; ++a) {
      const int d = (k / (a == 0 ? 1 : (a == 1 ? 3 : 9))) % 3 - 1;
      const std::int64_t c = std::int64_t(leaf_.at[a]) + d * size_;
      if (c < 0 || c >= extent_[a]) return false;
      q[a] = std::uint32_t(c);
    }
    return true;
  }

  // Marks the leaf of the leaf's depth or coarser that holds the cell at q, if there is one.
  bool coarser(const Index3& q) {
    for (int depth = leaf_.depth; depth >= 0; --depth) {
      const std::uint32_t size = grid_.size(depth);
      const auto it =
          index_.find(id(depth, {q[0] / size * size, q[1] / size * size, q[2] / size * size}));
      if (it != index_.end()) {
        (*mark_)[it->second] = 1;
        return true;
      }
    }
    return false;
  }

  // Marks the leaves at or inside the cell (depth, at) that touch the leaf's closed box.
  void collect(int depth, const Index3& at) {
    const std::int64_t size = grid_.size(depth);
    for (std::size_t a = 0; a < 3; ++a) {
      if (at[a] > leaf_.at[a] + size_ || at[a] + size < std::int64_t(leaf_.at[a])) return;
    }
    const auto it = index_.find(id(depth, at));
    if (it != index_.end()) {
      (*mark_)[it->second] = 1;
      return;
    }
    if (depth == grid_.max_depth) return;
    const std::uint32_t h = std::uint32_t(size / 2);
    for (std::uint32_t k = 0; k < 8; ++k) {
      collect(depth + 1,
              {at[0] + (k & 1) * h, at[1] + ((k >> 1) & 1) * h, at[2] + ((k >> 2) & 1) * h});
    }
  }

  const Grid& grid_;
  std::unordered_map<Key, std::size_t> index_;
  std::array<std::int64_t, 3> extent_{};
  Leaf leaf_{};
  std::int64_t size_ = 1;
  std::vector<char>* mark_ = nullptr;
};

/// Marks the leaves that touch one of the `split` leaves: their face pieces may have changed.
std::vector<char> touching(const Grid& grid, const Leaves& leaves, const Leaves& split) {
  std::vector<char> mark(leaves.size(), 0);
  Neighbours n(grid, leaves);
  for (const Leaf& l : split) n.mark_around(l, mark);
  return mark;
}

/// Welds the crossings of all leaves by id into the soup's first vertices, in the order of their
/// ids (every leaf that shares a crossing placed it at the same point, so which copy is kept is
/// moot). Returns the vertex of each crossing, numbered leaf by leaf; `first` gets the number
/// of each leaf's first crossing.
std::vector<std::uint32_t> weld(const Round& r, const Exec& exec, TriangleSoup& soup,
                                std::vector<std::uint32_t>& first) {
  std::uint32_t n = 0;
  std::size_t centres = 0;
  first.resize(r.outs.size());
  for (std::size_t i = 0; i < r.outs.size(); ++i) {
    first[i] = n;
    n += std::uint32_t(r.outs[i].crossings.size());
    centres += r.outs[i].centres.size();
  }
  BigVector<std::pair<Key, std::uint32_t>> ids(n);  // crossing id, its number
  BigVector<const Vec3*> at(n);
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, r.outs.size(), 1024), [&](auto range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const CellOut& o = r.outs[i];
        for (std::uint32_t k = 0; k < o.crossings.size(); ++k) {
          ids[first[i] + k] = {o.crossings[k].first, first[i] + k};
          at[first[i] + k] = &o.crossings[k].second;
        }
      }
    });
    detail::radix_sort(ids.data(), ids.size(), [](const auto& e) { return e.first; });
  });
  // Numbered in blocks: each block counts the ids that start a run of equal ids, a scan gives
  // each block its first number, then every block numbers and copies its own (the numbers are
  // those of one pass in id order).
  constexpr std::size_t kBlock = std::size_t{1} << 14;
  const std::size_t blocks = (std::size_t(n) + kBlock - 1) / kBlock;
  const auto starts_run = [&](std::size_t j) { return j == 0 || ids[j].first != ids[j - 1].first; };
  const auto block_end = [&](std::size_t b) { return std::min<std::size_t>(n, (b + 1) * kBlock); };
  std::vector<std::size_t> before(blocks + 1, 0);  // unique ids in the blocks before each
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::size_t k = 0;
      for (std::size_t j = b * kBlock; j < block_end(b); ++j) k += starts_run(j);
      before[b + 1] = k;
    });
  });
  for (std::size_t b = 0; b < blocks; ++b) before[b + 1] += before[b];
  // The soup's final size (welded crossings, then the fans' centres), reserved once: grown by
  // doubling, its copies were a third of the mesher's page faults.
  const std::size_t base = soup.vertices.size();
  soup.vertices.reserve(base + before[blocks] + centres);
  soup.vertices.resize(base + before[blocks]);
  std::vector<std::uint32_t> vertex(n);
  exec.run([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      // A block's first id continues the previous block's last run unless it starts one (the
      // very first id always does, so `next - 1` is never taken before a vertex exists).
      std::size_t next = base + before[b];
      for (std::size_t j = b * kBlock; j < block_end(b); ++j) {
        if (starts_run(j)) soup.vertices[next++] = *at[ids[j].second];
        vertex[ids[j].second] = std::uint32_t(next - 1);
      }
    });
  });
  return vertex;
}

/// Joins the leaves' pieces into one mesh (crossings welded by id) and fills the statistics.
void assemble(const Grid& grid, const Leaves& leaves, const Round& r, bool strict, const Exec& exec,
              CertifiedMesh& m) {
  TriangleSoup& soup = m.soup;
  std::vector<std::uint32_t> first_crossing;
  const std::vector<std::uint32_t> vertex = weld(r, exec, soup, first_crossing);
  // Per leaf, its first centre vertex and first triangle in the soup.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> first(leaves.size() + 1);
  std::uint32_t vertices = std::uint32_t(soup.vertices.size()), triangles = 0;
  CertifiedMeshStats& st = m.stats;
  RoundingScope scope;
  double certified_diagonal = 0;  // over certified leaves that may hold surface
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const Leaf& l = leaves[i];
    st.finest_depth = std::max(st.finest_depth, int(l.depth));
    if (l.kind == Kind::kEmpty) {
      ++st.empty_leaves;
      continue;
    }
    const CellOut& o = r.outs[i];
    first[i] = {vertices, triangles};
    if (!o.triangles.empty()) {
      vertices += std::uint32_t(o.centres.size());
      triangles += std::uint32_t(o.triangles.size());
    }
    const Box3 box = grid.box(l.at, grid.size(l.depth));
    const bool certified = l.kind == Kind::kCertified && !o.split && !o.blocked && !o.uncertain;
    if (certified) {
      ++st.certified_leaves;
    } else {
      ++st.uncertified_leaves;
      m.uncertified.push_back({box, int(l.depth), o.uncertain ? 2 : 1});
    }
    st.open_chains += o.open_chains;
    const Vec3 d = box.size();
    const double diagonal = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (!certified) st.uncertified_diagonal = std::fmax(st.uncertified_diagonal, diagonal);
    if (certified) certified_diagonal = std::fmax(certified_diagonal, diagonal);
    if (certified && !o.triangles.empty()) {
      st.mesh_to_surface = std::fmax(st.mesh_to_surface, diagonal);
    }
  }
  soup.vertices.resize(vertices);
  soup.triangles.resize(triangles);
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](auto range) {
      std::vector<std::uint32_t> map;
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const CellOut& o = r.outs[i];
        if (leaves[i].kind == Kind::kEmpty || o.triangles.empty()) continue;
        map.resize(o.crossings.size() + o.centres.size());
        for (std::size_t k = 0; k < o.crossings.size(); ++k) map[k] = vertex[first_crossing[i] + k];
        for (std::size_t k = 0; k < o.centres.size(); ++k) {
          map[o.crossings.size() + k] = first[i].first + std::uint32_t(k);
          soup.vertices[first[i].first + k] = o.centres[k];
        }
        std::size_t at = first[i].second;
        for (const auto& t : o.triangles) soup.triangles[at++] = {map[t[0]], map[t[1]], map[t[2]]};
      }
    });
  });
  // The table's slots (millions, most of them empty) are counted in parallel.
  const auto& slots = r.table.slots;
  exec.run([&] {
    st.uncertain_corners = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, slots.size(), std::size_t{1} << 16), std::uint64_t{0},
        [&](const auto& range, std::uint64_t k) {
          for (std::size_t i = range.begin(); i < range.end(); ++i)
            k += slots[i].key != VertexTable::kNone && slots[i].uncertain;
          return k;
        },
        std::plus<>());
  });
  st.surface_to_mesh = strict ? st.mesh_to_surface : certified_diagonal + st.mesh_to_surface;
}

}  // namespace

std::array<int, 3> certified_root_cells(const CertifiedMeshSettings& settings) {
  const Grid g = make_grid(settings);
  return {1 << g.root_bits[0], 1 << g.root_bits[1], 1 << g.root_bits[2]};
}

int certified_depth_for_edge(const CertifiedMeshSettings& settings, double edge) {
  const std::array<int, 3> roots = certified_root_cells(settings);
  double longest = 0;
  for (int a = 0; a < 3; ++a) {
    longest = std::fmax(longest, settings.bounds.size()[a] / roots[std::size_t(a)]);
  }
  int d = 0;
  while (d < settings.max_depth && std::ldexp(longest, -d) > edge) ++d;
  return d;
}

int certified_depth_for_resolution(const CertifiedMeshSettings& settings, int resolution) {
  const Vec3 size = settings.bounds.size();
  const double longest = std::fmax(size.x, std::fmax(size.y, size.z));
  return certified_depth_for_edge(settings, 2 * longest / std::max(resolution, 1));
}

CertifiedMesh mesh_certified(const Tape& tape, const CertifiedMeshSettings& settings,
                             const Exec& exec) {
  settings.validate();
  const Grid grid = make_grid(settings);
  ThreadEvaluators evals([&] { return std::make_unique<Evaluators>(tape, settings.proof_cache); });
  std::atomic<std::uint64_t> count{0};
  const Refiner refiner(grid, settings, count, exec.progress);
  std::vector<std::pair<Index3, int>> roots;
  const std::uint32_t s = grid.size(0);
  for (std::uint32_t z = 0; z < (1u << grid.root_bits[2]); ++z) {
    for (std::uint32_t y = 0; y < (1u << grid.root_bits[1]); ++y) {
      for (std::uint32_t x = 0; x < (1u << grid.root_bits[0]); ++x) {
        roots.push_back({{x * s, y * s, z * s}, 0});
      }
    }
  }
  ProgressPhase phase(exec.progress, "certified mesh", 1);
  CertifiedMesh m;
  CertifiedMeshStats& st = m.stats;
  auto clock = std::chrono::steady_clock::now();
  // Adds the time since the last call to `phase_seconds`.
  auto lap = [&](double& phase_seconds) {
    const auto now = std::chrono::steady_clock::now();
    phase_seconds += std::chrono::duration<double>(now - clock).count();
    clock = now;
  };
  SpreadTally tally;
  Leaves leaves = refine_all(refiner, roots, evals, exec, &tally);
  lap(st.seconds_refine);
  // Round 1 extracts every leaf; later rounds only the new leaves and those touching a split one.
  Round r;
  add_vertices(r.table, grid, leaves, evals, exec);
  lap(st.seconds_table);
  r.outs.resize(leaves.size());
  extract_all(grid, leaves, r.table, settings, evals, exec, r.arenas, r.outs, nullptr, &tally);
  lap(st.seconds_extract);
  for (;;) {
    if (phase.cancelled()) throw Error("certified mesh: cancelled");
    ++st.rounds;
    Split sp = split_failed(grid, refiner, leaves, r.outs, evals, exec, tally);
    lap(st.seconds_refine);
    if (sp.split.empty()) break;
    add_vertices(r.table, grid, sp.fresh, evals, exec);
    lap(st.seconds_table);
    std::vector<char> todo = touching(grid, sp.leaves, sp.split);
    BigVector<CellOut> outs(sp.leaves.size());
    for (std::size_t i = 0; i < sp.leaves.size(); ++i) {
      if (sp.origin[i] < 0)
        todo[i] = 1;
      else if (!todo[i])
        outs[i] = std::move(r.outs[std::size_t(sp.origin[i])]);
    }
    leaves = std::move(sp.leaves);
    extract_all(grid, leaves, r.table, settings, evals, exec, r.arenas, outs, &todo, &tally);
    r.outs = std::move(outs);
    lap(st.seconds_extract);
  }
  assemble(grid, leaves, r, settings.strict, exec, m);
  st.leaves = leaves.size();
  st.roots = certified_root_cells(settings);
  st.interval_evaluations = tally.remote_evaluations;
  for (const auto& e : evals) st.interval_evaluations += e->evaluations;
  m.balance = std::move(tally.balance);
  lap(st.seconds_assemble);
  phase.advance(1);
  return m;
}

}  // namespace iaa
