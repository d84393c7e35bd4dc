// The enclosure octree (octree.h). Three phases:
// 1. A short breadth-first pass from the root down to a "split level" with enough candidate cells
//    to feed the threads (chosen from the surface alone, never from the thread count).
// 2. One depth-first task per candidate cell (a subtree) in parallel: evaluate F on the cell,
//    discard it when 0 is not in F, split it until the leaf depth, classify the leaf with its
//    corner signs (cached per subtree so that shared corners are evaluated once), and refine
//    possible leaves up to refine_possible levels further.
// 3. Gather the subtrees' leaves into canonical order (depth, then Morton order). Depth-first
//    traversal with children in Morton order already yields Morton order within one depth, and
//    the subtrees are themselves in Morton order, so a stable bucketing by depth is enough.
// The subtrees, their traversal and their corner caches do not depend on the thread count, so
// the leaves *and* the evaluation counts are identical for any number of threads.
#include "enclose/octree.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>

#include "core/error.h"
#include "core/spread.h"
#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/specialize.h"

namespace iaa {

namespace {

using Index = std::array<std::uint32_t, 3>;

/// A mean-value (centred) expansion of f over a cell: f(x) is in fc + g . (x - c) for every x of
/// any box that holds c and lies in the cell, where g encloses the gradient over the cell and fc
/// is f(c) evaluated on the degenerate box. Sound for continuous, piecewise differentiable f (the
/// gradient enclosure contains the generalized gradients at kinks); made only where the cell has
/// no partial domain and g is finite. Where the natural interval overestimates (x^4 - x^2 near
/// its critical points) this bound is tight to second order in the cell size, which removes most
/// of the "possible" shell around the surface.
struct Expansion {
  std::array<Interval, 3> g;
  Interval fc;
  double c[3];
  /// Filled by prepare(cell): per axis, the term g[a] * (X[a] - c[a]) for the lower and upper
  /// half of the cell (the children's extents: [lo, c] and [c, hi]) and for the points lo and hi
  /// (the children's corners other than c). The children's bounds and corner values are then a
  /// sum of three terms, the same intervals bound() would compute, without multiplying again.
  Interval half[3][2];
  Interval end[3][2];

  Interval bound(const IBox& box) const {
    Interval r = fc;
    for (int a = 0; a < 3; ++a) r += g[a] * (box[a] - Interval(c[a]));
    return r;
  }
  void prepare(const IBox& cell) {
    for (int a = 0; a < 3; ++a) {
      const Interval ca(c[a]);
      half[a][0] = g[a] * (Interval(cell[a].lo(), c[a]) - ca);
      half[a][1] = g[a] * (Interval(c[a], cell[a].hi()) - ca);
      end[a][0] = g[a] * (Interval(cell[a].lo()) - ca);
      end[a][1] = g[a] * (Interval(cell[a].hi()) - ca);
    }
  }
  /// bound() on child `k` (bit a of k: upper half along axis a). Needs prepare().
  Interval child_bound(unsigned k) const {
    Interval r = fc;
    for (int a = 0; a < 3; ++a) r += half[a][(k >> a) & 1];
    return r;
  }
  /// bound() at the point whose coordinate along axis a is lo, c or hi for off[a] = 0, 1, 2 (at
  /// c the term is g * [0, 0] = [0, 0], and adding it is exact). Needs prepare().
  Interval point_bound(const int off[3]) const {
    Interval r = fc;
    for (int a = 0; a < 3; ++a) {
      if (off[a] != 1) r += end[a][off[a] >> 1];
    }
    return r;
  }
};

/// F over a cell evaluated ahead of its visit, and whether it met a partial domain; with
/// `has_grad`, its gradient `grad` as well (grad.v is then f).
struct Evaluated {
  Interval f;
  bool partial = false;
  bool has_grad = false;
  IGrad grad;
};

/// The split level is the first level with at least kMinSubtrees candidate cells, and at least
/// depth - kMaxSubtreeDepth so that each subtree (and its corner cache) stays small, unless the
/// breadth-first pass (sequential, and not bounded by max_boxes) already holds kMaxSubtrees.
constexpr std::size_t kMinSubtrees = 512;
constexpr std::size_t kMaxSubtrees = std::size_t{1} << 15;
constexpr int kMaxSubtreeDepth = 5;

/// Map from a cell corner (integer coordinates on the grid of the deepest cells) to the proved
/// sign of f there: +1 (certainly > 0), -1 (certainly < 0) or 0 (not proved). One per subtree, so
/// that what is evaluated does not depend on the thread count. The corners of the leaf depth (all
/// of them when nothing is refined) live in a dense array, one byte each, indexed directly, as
/// long as the subtree is at most kDenseSpan leaves wide; the corners of refined cells and of
/// wider subtrees use open addressing. Both hold the same information: the split changes the speed
/// only.
class CornerCache {
 public:
  static constexpr std::uint32_t kDenseSpan = 64;

  /// Empties the cache for a subtree whose finest-grid corners lie in [origin, origin + span]^3;
  /// corners with all coordinates multiples of 2^coarse_shift (those of the leaf depth) are
  /// stored densely.
  void reset(const std::array<std::uint32_t, 3>& origin, std::uint32_t span, int coarse_shift) {
    origin_ = origin;
    shift_ = coarse_shift;
    coarse_mask_ = (std::uint32_t{1} << coarse_shift) - 1;
    dense_ = (span >> coarse_shift) <= kDenseSpan;
    if (dense_) {
      side_ = (span >> coarse_shift) + 1;
      dense_signs_.assign(std::size_t{side_} * side_ * side_, kUnknown);
    }
    if (!dense_ || coarse_shift > 0) {
      slots_.assign(1024, Slot{});
      used_ = 0;
    }
  }

  /// The sign of corner (x, y, z) if it is there, else null.
  const std::int8_t* find(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    if (is_dense(x, y, z)) {
      const std::int8_t* s = &dense_signs_[dense_index(x, y, z)];
      return *s == kUnknown ? nullptr : s;
    }
    const Slot* s = probe(x, y, z);
    return s->x == kEmpty ? nullptr : &s->sign;
  }

  /// Returns the sign slot of corner (x, y, z); `*found` tells whether it was already there.
  std::int8_t* find_or_insert(std::uint32_t x, std::uint32_t y, std::uint32_t z, bool* found) {
    if (is_dense(x, y, z)) {
      std::int8_t* s = &dense_signs_[dense_index(x, y, z)];
      *found = *s != kUnknown;
      return s;
    }
    if (2 * (used_ + 1) > slots_.size()) grow();
    Slot* s = probe(x, y, z);
    *found = s->x != kEmpty;
    if (!*found) {
      s->x = x;
      s->y = y;
      s->z = z;
      ++used_;
    }
    return &s->sign;
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;  // keys are at most 2^29
  static constexpr std::int8_t kUnknown = 2;            // not a sign: not evaluated yet
  struct Slot {
    std::uint32_t x = kEmpty, y = 0, z = 0;
    std::int8_t sign = 0;
  };

  bool is_dense(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return dense_ && ((x | y | z) & coarse_mask_) == 0;
  }
  std::size_t dense_index(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return (std::size_t{(z - origin_[2]) >> shift_} * side_ + ((y - origin_[1]) >> shift_)) *
               side_ +
           ((x - origin_[0]) >> shift_);
  }

  Slot* probe(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    std::uint64_t h =
        x * 0x9E3779B97F4A7C15ull ^ y * 0xC2B2AE3D27D4EB4Full ^ z * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = h & mask;; i = (i + 1) & mask) {
      Slot& s = slots_[i];
      if (s.x == kEmpty || (s.x == x && s.y == y && s.z == z)) return &s;
    }
  }
  void grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    for (const Slot& s : old) {
      if (s.x != kEmpty) *probe(s.x, s.y, s.z) = s;
    }
  }

  bool dense_ = false;
  int shift_ = 0;
  std::uint32_t coarse_mask_ = 0;
  std::array<std::uint32_t, 3> origin_{};
  std::uint32_t side_ = 0;
  std::vector<std::int8_t> dense_signs_;
  std::vector<Slot> slots_;
  std::size_t used_ = 0;
};

/// The hot loop's grid coordinates (a RoundingScope is open).
inline double grid_coord_up(double lo, double hi, std::uint64_t i, int depth) {
  return grid_coordinate_upward(lo, hi, i, depth);
}

/// State shared by all subtree tasks.
struct Shared {
  const Tape* tape;
  Box3 bounds;
  int depth;      ///< leaf depth
  int max_depth;  ///< depth + refine_possible
  std::uint64_t max_boxes;
  bool centered_form;
  bool all_corner_signs;
  const Progress* progress = nullptr;
  std::atomic<std::uint64_t> leaves{0};
  std::atomic<bool> over_limit{false};
  std::atomic<bool> cancelled{false};
};

/// Depth-first enclosure of one subtree; owns its evaluators, point cache and output.
class SubtreeWorker {
 public:
  explicit SubtreeWorker(Shared& sh) : sh_(sh), se_(*sh.tape) {
    // The batch evaluates with the whole tape, and makes no regions: where the tape has min or
    // max, the specializing evaluator's regions (and with them the signs of zero gradient
    // bounds, specialize.h) would depend on it, so it is used only where there are none.
    if (!sh.tape->has_min_max()) {
      batch_.emplace(*sh.tape);
      batch_grad_.emplace(*sh.tape);
    }
  }

  /// Starts the subtree of cell (idx, d): empties the corner cache, the leaves and the counts, so
  /// that one worker (and its evaluators) serves many subtrees with the same results as fresh ones.
  void start(const Index& idx, int d) {
    const int shift = sh_.max_depth - d;
    cache_.reset({idx[0] << shift, idx[1] << shift, idx[2] << shift}, std::uint32_t{1} << shift,
                 sh_.max_depth - sh_.depth);
    cells_.clear();
    evaluations_ = 0;
    corner_evaluations_ = 0;
    expansion_signs_ = 0;
    own_calls_ = 0;
    own_rejects_ = 0;
  }

  /// Encloses the subtree of cell (idx, d). `parent`, when given, is the mean-value expansion of
  /// f over the parent cell, on which f is defined everywhere (no partial domain). Its centre is a
  /// corner of this cell and its gradient encloses the gradient over this cell, so it bounds f here
  /// with no evaluation at all, about as tightly as this cell's own expansion would. `pre`, when
  /// given, is F over this cell and its partial-domain flag, evaluated already (with the cell's
  /// siblings, by a batched evaluator: the same interval as se_.eval gives), and perhaps its
  /// gradient (the same as se_.eval_grad gives).
  void visit(const Index& idx, int d, const Expansion* parent, const Evaluated* pre = nullptr) {
    if (sh_.over_limit.load(std::memory_order_relaxed) ||
        sh_.cancelled.load(std::memory_order_relaxed)) {
      return;
    }
    if (++visits_ % 4096 == 0 && sh_.progress && sh_.progress->cancelled()) {
      sh_.cancelled.store(true, std::memory_order_relaxed);
      return;
    }
    Interval f = Interval::whole();
    bool partial = true;
    if (parent) {
      f = parent->child_bound((idx[0] & 1) | (idx[1] & 1) << 1 | (idx[2] & 1) << 2);
      partial = false;  // partial domain is inclusion-monotone: none on the parent, none here
      if (!f.contains_zero()) return;
    }
    const IBox box = cell_ibox(idx, d);
    Expansion own_exp;
    bool exp_valid = false;
    // The natural interval value and the cell's own gradient in one evaluation, then the
    // mean-value form around the cell's centre.
    const auto own = [&] {
      ++evaluations_;
      if (!sh_.centered_form) {
        f = pre ? pre->f : se_.eval(box);
        partial = pre ? pre->partial : se_.partial_domain();
        return;
      }
      // Where most evaluated cells turn out empty (a parent expansion too weak to reject them,
      // as on the twist's steep blades), the natural interval alone, at a fraction of the cost
      // of value and gradient, is tried first and the gradient evaluated only for cells it
      // keeps. Its value is the one the gradient evaluation computes (the same interval rules),
      // so the cells kept and their bounds do not depend on the choice, only the time does. The
      // choice is made from this subtree's counts alone.
      ++own_calls_;
      if (values_first()) {
        const Interval v = pre ? pre->f : se_.eval(box);
        const bool v_partial = pre ? pre->partial : se_.partial_domain();
        if (!v_partial && !intersect(f, v).contains_zero()) {
          f = intersect(f, v);
          partial = false;
          ++own_rejects_;
          return;
        }
      }
      const bool pre_grad = pre && pre->has_grad;
      const IGrad r = pre_grad ? pre->grad : se_.eval_grad(box);
      partial = pre_grad ? pre->partial : se_.partial_domain();
      f = intersect(f, r.v);
      if (!partial && !f.contains_zero()) ++own_rejects_;
      if (partial || !f.contains_zero()) return;
      for (int a = 0; a < 3; ++a) {
        if (!r.g[a].is_finite()) return;
        own_exp.g[a] = r.g[a];
        own_exp.c[a] = grid_coord_up(sh_.bounds.lo[a], sh_.bounds.hi[a], 2 * idx[a] + 1ull, d + 1);
      }
      own_exp.fc = point_value(own_exp.c[0], own_exp.c[1], own_exp.c[2]);
      if (d < sh_.max_depth) {  // the centre is a corner of the children: remember its sign
        const int shift = sh_.max_depth - d - 1;
        remember_sign((2 * idx[0] + 1) << shift, (2 * idx[1] + 1) << shift,
                      (2 * idx[2] + 1) << shift, own_exp.fc);
      }
      if (!own_exp.fc.is_finite()) return;
      exp_valid = true;
      f = intersect(f, own_exp.bound(box));
    };
    if (d < sh_.depth) {
      own();
      if (f.contains_zero()) split(idx, d, box, exp_valid ? &own_exp : nullptr);
      return;
    }
    // A leaf. Crossing when its corners prove a sign change of a continuous f; with the parent's
    // expansion at hand the leaf's own evaluation is only needed when it is not.
    if (!parent) {
      own();
      if (!f.contains_zero()) return;  // certified empty (or f undefined on the whole cell)
    }
    signs_ = 0;  // where f may be undefined (partial), no corner sign is recorded
    n_missing_ = 0;
    if (!partial && corners_have_both_signs(idx, d, parent)) {
      if (sh_.all_corner_signs) all_signs(idx, d, parent);
      emit(idx, d, CellClass::kCrossing, f);
      return;
    }
    if (parent) {
      own();  // a possible leaf: try the tighter bound of its own evaluation
      if (!f.contains_zero()) return;
    }
    if (d < sh_.max_depth) {
      split(idx, d, box, exp_valid ? &own_exp : nullptr);  // refine a possible leaf
    } else {
      emit(idx, d, CellClass::kPossible, f);  // all its corners were looked at
    }
  }

  /// Publishes the leaf count to the shared limit check.
  void flush() {
    const std::uint64_t total =
        sh_.leaves.fetch_add(pending_, std::memory_order_relaxed) + pending_;
    pending_ = 0;
    if (total > sh_.max_boxes) sh_.over_limit.store(true, std::memory_order_relaxed);
  }

  std::vector<Cell>& cells() { return cells_; }
  std::uint64_t evaluations() const { return evaluations_; }
  std::uint64_t corner_evaluations() const { return corner_evaluations_; }
  std::uint64_t expansion_signs() const { return expansion_signs_; }

 private:
  void emit(const Index& idx, int d, CellClass cls, const Interval& f) {
    cells_.push_back(Cell{idx, static_cast<std::uint8_t>(d), cls, signs_, f});
    if (++pending_ == 256) flush();
  }

  /// True when own() tries the natural interval value alone before the gradient (see there).
  bool values_first() const { return own_calls_ > 32 && 3 * own_rejects_ > 2 * own_calls_; }

  void split(const Index& idx, int d, const IBox& box, Expansion* g) {
    if (g) g->prepare(box);
    const auto child = [&](std::uint32_t c) {
      return Index{2 * idx[0] + (c & 1), 2 * idx[1] + ((c >> 1) & 1), 2 * idx[2] + ((c >> 2) & 1)};
    };
    // The children that the parent's expansion does not reject are evaluated together, in one
    // pass of a batched evaluator: with their gradients where their own evaluations will take
    // the mean-value form (and those of leaves only where no parent expansion may spare them by
    // their corners' signs), else their natural interval values (no mean-value form, or own()
    // trying values first). A child whose own() then takes the other path (the counts changed on
    // the way) evaluates again or leaves the value unused; the values, the gradients (the same
    // intervals as se_'s, whose tape has no min or max here), the counts and so the leaves are
    // the same as with one evaluation per child.
    Evaluated pre[8];
    bool have_pre = false;
    const bool values = !sh_.centered_form || values_first();
    const bool grads = !values && (d + 1 < sh_.depth || !g);
    if (batch_ && (values || grads)) {
      IBox boxes[8];
      std::uint32_t which[8];
      int n = 0;
      for (std::uint32_t c = 0; c < 8; ++c) {
        if (g && !g->child_bound(c).contains_zero()) continue;
        which[n] = c;
        boxes[n++] = cell_ibox(child(c), d + 1);
      }
      if (n > 0 && values) {
        Interval v[8];
        batch_->eval(boxes, n, v);
        for (int j = 0; j < n; ++j) pre[which[j]] = {v[j], batch_->partial_domain(j), false, {}};
        have_pre = true;
      } else if (n > 0) {
        IGrad r[8];
        batch_grad_->eval(boxes, n, r);
        for (int j = 0; j < n; ++j) {
          pre[which[j]] = {r[j].v, batch_grad_->partial_domain(j), true, r[j]};
        }
        have_pre = true;
      }
    }
    for (std::uint32_t c = 0; c < 8; ++c) visit(child(c), d + 1, g, have_pre ? &pre[c] : nullptr);
  }

  /// f on the degenerate box of a point: its sign, when certain, is proved. Returns whole() where
  /// f may be undefined.
  Interval point_value(double x, double y, double z) {
    const Interval v = se_.eval(IBox(Interval(x), Interval(y), Interval(z)));
    ++corner_evaluations_;
    return se_.partial_domain() || v.is_empty() ? Interval::whole() : v;
  }

  /// Proved sign of f at corner (x, y, z) of the finest grid, found once per subtree: from the
  /// expansion `e` of a cell holding the corner when it decides, else by evaluating the point.
  /// `off` places the corner in the expansion's cell (Expansion::point_bound).
  int corner_sign(std::uint32_t x, std::uint32_t y, std::uint32_t z, const Expansion* e,
                  const int off[3]) {
    bool found = false;
    std::int8_t* sign = cache_.find_or_insert(x, y, z, &found);
    if (!found) {
      Interval v = Interval::whole();
      if (e) v = e->point_bound(off);
      if (!v.certainly_positive() && !v.certainly_negative()) {
        const Box3& b = sh_.bounds;
        const int L = sh_.max_depth;
        v = point_value(grid_coord_up(b.lo.x, b.hi.x, x, L), grid_coord_up(b.lo.y, b.hi.y, y, L),
                        grid_coord_up(b.lo.z, b.hi.z, z, L));
      } else {
        ++expansion_signs_;
      }
      *sign = v.certainly_positive() ? 1 : (v.certainly_negative() ? -1 : 0);
    }
    return *sign;
  }

  /// Records the proved sign of an already evaluated corner.
  void remember_sign(std::uint32_t x, std::uint32_t y, std::uint32_t z, const Interval& v) {
    bool found = false;
    std::int8_t* sign = cache_.find_or_insert(x, y, z, &found);
    if (!found) *sign = v.certainly_positive() ? 1 : (v.certainly_negative() ? -1 : 0);
  }

  IBox cell_ibox(const Index& idx, int d) const {
    IBox b;
    for (int a = 0; a < 3; ++a) {
      b[a] = Interval(grid_coord_up(sh_.bounds.lo[a], sh_.bounds.hi[a], idx[a], d),
                      grid_coord_up(sh_.bounds.lo[a], sh_.bounds.hi[a], idx[a] + 1ull, d));
    }
    return b;
  }

  /// True when two corners of the cell have proved values of opposite strict signs.
  /// The corners already in the cache are looked at first, so that a sign change among them
  /// costs no evaluation. A corner not in the cache is bounded first by the parent's expansion
  /// `parent` (when given; the corner lies in the parent cell, where the expansion encloses f at
  /// every point), which proves most signs with a few interval operations instead of an evaluation
  /// of the tape; only corners it leaves undecided are evaluated.
  bool corners_have_both_signs(const Index& idx, int d, const Expansion* parent) {
    const int shift = sh_.max_depth - d;
    bool pos = false, neg = false;
    n_missing_ = 0;
    signs_ = 0;
    for (std::uint32_t c = 0; c < 8; ++c) {
      const std::int8_t* sign =
          cache_.find((idx[0] + (c & 1)) << shift, (idx[1] + ((c >> 1) & 1)) << shift,
                      (idx[2] + ((c >> 2) & 1)) << shift);
      if (!sign) {
        missing_[n_missing_++] = c;
        continue;
      }
      record(c, *sign);
      pos |= *sign > 0;
      neg |= *sign < 0;
    }
    int k = 0;
    for (; k < n_missing_ && !(pos && neg); ++k) {
      const int sign = missing_sign(idx, d, parent, missing_[k]);
      pos |= sign > 0;
      neg |= sign < 0;
    }
    // The corners not looked at stay in missing_ for all_signs().
    std::copy(missing_ + k, missing_ + n_missing_, missing_);
    n_missing_ -= k;
    return pos && neg;
  }

  /// After corners_have_both_signs: proves the signs of the corners it did not look at.
  void all_signs(const Index& idx, int d, const Expansion* parent) {
    for (int k = 0; k < n_missing_; ++k) missing_sign(idx, d, parent, missing_[k]);
    n_missing_ = 0;
  }

  /// The sign of corner c of cell (idx, d), not in the cache: found and recorded.
  int missing_sign(const Index& idx, int d, const Expansion* parent, std::uint32_t c) {
    const int shift = sh_.max_depth - d;
    const int off[3] = {int((idx[0] & 1) + (c & 1)), int((idx[1] & 1) + ((c >> 1) & 1)),
                        int((idx[2] & 1) + ((c >> 2) & 1))};
    const int sign = corner_sign((idx[0] + (c & 1)) << shift, (idx[1] + ((c >> 1) & 1)) << shift,
                                 (idx[2] + ((c >> 2) & 1)) << shift, parent, off);
    record(c, sign);
    return sign;
  }

  void record(std::uint32_t c, int sign) {
    if (sign < 0) signs_ |= std::uint16_t(1u << (2 * c));
    if (sign > 0) signs_ |= std::uint16_t(2u << (2 * c));
  }

  Shared& sh_;
  SpecializingEval se_;  ///< cells inside a cell that decided a min/max run the pruned tape
  std::optional<BatchIntervalEval> batch_;  ///< a cell's children at once (tapes without min/max)
  std::optional<BatchIntervalGradEval> batch_grad_;  ///< the same, with their gradients
  CornerCache cache_;
  std::vector<Cell> cells_;
  std::uint64_t evaluations_ = 0;
  std::uint64_t corner_evaluations_ = 0;
  std::uint64_t expansion_signs_ = 0;
  // This subtree's cell evaluations and how many of them excluded 0 (see own() in visit).
  std::uint64_t own_calls_ = 0, own_rejects_ = 0;
  std::uint64_t pending_ = 0;
  std::uint64_t visits_ = 0;
  // The leaf being classified: its proved corner signs (Cell::corner_signs) and the corners not
  // looked at yet.
  std::uint16_t signs_ = 0;
  std::uint32_t missing_[8];
  int n_missing_ = 0;
};

/// Morton order of two indices of one depth, bits interleaved z y x from the most significant
/// end (x least significant), compared without building the codes: the axis whose differing bit
/// is highest decides, ties going to the more significant axis.
bool morton_less(const Index& a, const Index& b) {
  const auto msb_less = [](std::uint32_t p, std::uint32_t q) { return p < q && p < (p ^ q); };
  int axis = 2;
  std::uint32_t best = a[2] ^ b[2];
  for (int i = 1; i >= 0; --i) {
    const std::uint32_t diff = a[i] ^ b[i];
    if (msb_less(best, diff)) {
      best = diff;
      axis = i;
    }
  }
  return a[axis] < b[axis];
}

}  // namespace

double grid_coordinate(double lo, double hi, std::uint64_t i, int depth) {
  if (!rounding_is_upward()) {
    RoundingScope scope;
    return grid_coordinate(lo, hi, i, depth);
  }
  return grid_coordinate_upward(lo, hi, i, depth);
}

bool canonical_less(const Cell& a, const Cell& b) {
  if (a.depth != b.depth) return a.depth < b.depth;
  return morton_less(a.index, b.index);
}

void EncloseSettings::validate() const {
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const double lo = bounds.lo[a], hi = bounds.hi[a];
    if (!std::isfinite(lo) || !std::isfinite(hi)) {
      throw SettingError(std::string("bounds: the ") + kAxis[a] + " range must be finite");
    }
    if (!std::isfinite(hi - lo)) {
      throw SettingError(std::string("bounds: the ") + kAxis[a] +
                         " range is too wide (its width overflows a double)");
    }
    if (!(lo < hi)) {
      throw SettingError(std::string("bounds: the ") + kAxis[a] + " range [" + std::to_string(lo) +
                         ", " + std::to_string(hi) + "] is " + (lo == hi ? "empty" : "inverted") +
                         "; it must have lo < hi");
    }
  }
  if (depth < 1 || depth > kMaxDepth) {
    throw SettingError("depth must be between 1 and " + std::to_string(kMaxDepth) + ", got " +
                       std::to_string(depth));
  }
  if (refine_possible < 0 || refine_possible > kMaxRefine) {
    throw SettingError("refine_possible must be between 0 and " + std::to_string(kMaxRefine) +
                       ", got " + std::to_string(refine_possible));
  }
  if (max_boxes < 1) throw SettingError("max_boxes must be at least 1");
}

Box3 Enclosure::box(const Cell& c) const {
  if (!rounding_is_upward()) {
    RoundingScope scope;
    return box(c);
  }
  Box3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = grid_coordinate_upward(bounds.lo[a], bounds.hi[a], c.index[a], c.depth);
    b.hi[a] = grid_coordinate_upward(bounds.lo[a], bounds.hi[a], c.index[a] + 1ull, c.depth);
  }
  return b;
}

std::uint64_t Enclosure::count(CellClass cls) const {
  std::uint64_t n = 0;
  for (const auto& d : counts_by_depth) n += d[cls == CellClass::kCrossing ? 0 : 1];
  return n;
}

namespace {

/// Phase 2 shared with other processes (Exec::spread): this process encloses the subtrees the
/// spread hands it with its threads, then every subtree's leaves and counts come back to it. A
/// subtree skipped because this process went over max_boxes is sent as "over the limit", so that
/// every process ends with the same over_limit.
static_assert(std::is_trivially_copyable_v<Cell>, "cells travel between processes as bytes");

SpreadBalance enclose_spread(Shared& sh, const std::vector<Index>& frontier, int level,
                             std::vector<std::vector<Cell>>& parts,
                             std::vector<std::uint64_t>& evals,
                             std::vector<std::uint64_t>& corner_evals,
                             std::vector<std::uint64_t>& exp_signs, const ProgressPhase& phase,
                             const Exec& exec) {
  Spread& spread = *exec.spread;
  const std::size_t n = frontier.size();
  std::vector<std::string> results(n);
  std::vector<std::uint64_t> work(n, 0);
  spread.begin(n, &phase);
  const int threads = exec.resolved_threads();
  exec.run([&] {
    tbb::parallel_for(0, threads, [&](int) {
      RoundingScope scope;
      SubtreeWorker w(sh);
      try {
        for (std::int64_t k = spread.next(); k >= 0; k = spread.next()) {
          const auto i = static_cast<std::size_t>(k);
          std::string& res = results[i];
          if (sh.over_limit.load(std::memory_order_relaxed)) {
            put_bytes(res, std::uint8_t{1});
            continue;
          }
          w.start(frontier[i], level);
          w.visit(frontier[i], level, nullptr);
          w.flush();
          const std::vector<Cell>& cells = w.cells();
          put_bytes(res, std::uint8_t{0});
          put_bytes(res, w.evaluations());
          put_bytes(res, w.corner_evaluations());
          put_bytes(res, w.expansion_signs());
          put_values(res, cells);
          work[i] = w.evaluations() + w.corner_evaluations();
          phase.advance(1);
        }
      } catch (...) {
        spread.fail();  // the process's other threads stop too
        throw;
      }
    });
  });
  SpreadBalance balance = spread.finish(results, work);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t pos = 0;
    if (take_bytes<std::uint8_t>(results[i], pos)) {
      sh.over_limit.store(true);
      continue;
    }
    evals[i] = take_bytes<std::uint64_t>(results[i], pos);
    corner_evals[i] = take_bytes<std::uint64_t>(results[i], pos);
    exp_signs[i] = take_bytes<std::uint64_t>(results[i], pos);
    parts[i].clear();
    const bool whole = append_rest(results[i], pos, parts[i]);
    IAA_CHECK(whole);
    std::string().swap(results[i]);
  }
  // No process may have seen the limit pass (each counts its own leaves): the total decides.
  std::uint64_t total = 0;
  for (const auto& part : parts) total += part.size();
  if (total > sh.max_boxes) sh.over_limit.store(true);
  return balance;
}

}  // namespace

Enclosure enclose(const Tape& tape, const EncloseSettings& settings, const Exec& exec) {
  settings.validate();
  Shared sh;
  sh.tape = &tape;
  sh.bounds = settings.bounds;
  sh.depth = settings.depth;
  sh.max_depth = settings.depth + settings.refine_possible;
  sh.max_boxes = settings.max_boxes;
  sh.centered_form = settings.centered_form;
  sh.all_corner_signs = settings.all_corner_signs;
  sh.progress = exec.progress;

  Enclosure out;
  out.bounds = settings.bounds;
  out.counts_by_depth.assign(static_cast<std::size_t>(sh.max_depth + 1), {0, 0});

  // Phase 1: breadth first, in Morton order, until enough candidate cells for the threads.
  std::vector<Index> frontier{{0, 0, 0}};
  int level = 0;
  {
    RoundingScope scope;
    // Eight cells per pass of the batched evaluator: the same intervals as IntervalEval's.
    BatchIntervalEval be(tape);
    constexpr int kLanes = BatchIntervalEval::kLanes;
    while (level < sh.depth && !frontier.empty() &&
           (frontier.size() < kMinSubtrees ||
            (level < sh.depth - kMaxSubtreeDepth && frontier.size() < kMaxSubtrees))) {
      std::vector<Index> next;
      for (std::size_t i0 = 0; i0 < frontier.size(); i0 += kLanes) {
        const int m = static_cast<int>(std::min<std::size_t>(kLanes, frontier.size() - i0));
        IBox boxes[kLanes];
        for (int j = 0; j < m; ++j) {
          const Index& idx = frontier[i0 + static_cast<std::size_t>(j)];
          for (int a = 0; a < 3; ++a) {
            boxes[j][a] =
                Interval(grid_coord_up(sh.bounds.lo[a], sh.bounds.hi[a], idx[a], level),
                         grid_coord_up(sh.bounds.lo[a], sh.bounds.hi[a], idx[a] + 1ull, level));
          }
        }
        Interval v[kLanes];
        be.eval(boxes, m, v);
        for (int j = 0; j < m; ++j) {
          const Index& idx = frontier[i0 + static_cast<std::size_t>(j)];
          ++out.evaluations;
          if (!v[j].contains_zero()) continue;
          for (std::uint32_t c = 0; c < 8; ++c) {
            next.push_back(
                {2 * idx[0] + (c & 1), 2 * idx[1] + ((c >> 1) & 1), 2 * idx[2] + ((c >> 2) & 1)});
          }
        }
      }
      frontier.swap(next);
      ++level;
    }
  }

  // Phase 2: one depth-first task per frontier cell.
  const std::size_t n = frontier.size();
  std::vector<std::vector<Cell>> parts(n);
  std::vector<std::uint64_t> evals(n, 0), corner_evals(n, 0), exp_signs(n, 0);
  if (exec.spread) {
    ProgressPhase phase(exec.progress, "enclose", n);
    out.balance =
        enclose_spread(sh, frontier, level, parts, evals, corner_evals, exp_signs, phase, exec);
  } else {
    ProgressPhase phase(exec.progress, "enclose", n);
    exec.run([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const auto& r) {
        RoundingScope scope;
        SubtreeWorker w(sh);
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          if (phase.cancelled()) sh.cancelled.store(true, std::memory_order_relaxed);
          if (sh.cancelled.load(std::memory_order_relaxed) ||
              sh.over_limit.load(std::memory_order_relaxed)) {
            return;
          }
          w.start(frontier[i], level);
          w.visit(frontier[i], level, nullptr);
          w.flush();
          parts[i] = std::move(w.cells());
          evals[i] = w.evaluations();
          corner_evals[i] = w.corner_evaluations();
          exp_signs[i] = w.expansion_signs();
          phase.advance(1);
        }
      });
    });
  }
  if (sh.cancelled.load()) throw Error("enclose: cancelled");
  if (sh.over_limit.load()) {
    throw SettingError("max_boxes: the enclosure needs more than " +
                       std::to_string(settings.max_boxes) + " boxes at depth " +
                       std::to_string(settings.depth) +
                       (settings.refine_possible > 0
                            ? " with refine_possible " + std::to_string(settings.refine_possible)
                            : std::string()) +
                       "; lower the depth (or refine_possible) or raise max_boxes");
  }

  // Phase 3: gather in canonical order: depth major, then subtree order, then traversal order.
  const std::size_t depths = out.counts_by_depth.size();
  std::vector<std::uint64_t> per(n * depths, 0);  // leaves of subtree i at depth d
  for (std::size_t i = 0; i < n; ++i) {
    out.evaluations += evals[i];
    out.corner_evaluations += corner_evals[i];
    out.expansion_signs += exp_signs[i];
    for (const Cell& c : parts[i]) {
      ++per[i * depths + c.depth];
      ++out.counts_by_depth[c.depth][c.cls == CellClass::kCrossing ? 0 : 1];
    }
  }
  std::vector<std::uint64_t> offset(n * depths, 0);
  std::uint64_t total = 0;
  for (std::size_t d = 0; d < depths; ++d) {
    for (std::size_t i = 0; i < n; ++i) {
      offset[i * depths + d] = total;
      total += per[i * depths + d];
    }
  }
  out.cells.resize(total);
  exec.run([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& r) {
      std::vector<std::uint64_t> pos(depths);
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        for (std::size_t d = 0; d < depths; ++d) pos[d] = offset[i * depths + d];
        for (const Cell& c : parts[i]) out.cells[pos[c.depth]++] = c;
        std::vector<Cell>().swap(parts[i]);
      }
    });
  });
  return out;
}

}  // namespace iaa
