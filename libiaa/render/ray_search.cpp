#include "render/ray_search.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "expr/ray_poly.h"
#include "render/piece_stack.h"
#include "scene/camera.h"

namespace iaa {

namespace {

/// Most pieces of a segment_may_hit march (widths double: 40 cover a range 2^38 times the first).
constexpr int kMaxMarch = 40;

Interval dot(const std::array<Interval, 3>& g, const IBox& d) {
  return g[0] * d.x + g[1] * d.y + g[2] * d.z;
}

/// Pushes `range` onto `st` as pieces to search front to back: with `first` > 0, pieces of width
/// first, first, 2 first, 4 first, ... from the front (each after the first as wide as all
/// before it; at most kMaxMarch), pushed back to front; else the whole range as one piece.
template <class Stack>
void push_march(Stack& st, Interval range, double first) {
  double ends[kMaxMarch + 1];
  int n = 0;
  ends[n++] = range.lo();
  double w = first;  // width of the next piece
  while (first > 0 && n < kMaxMarch && ends[n - 1] + w < range.hi()) {
    ends[n] = ends[n - 1] + w;
    ++n;
    if (n > 2) w *= 2;
  }
  ends[n++] = range.hi();
  for (int k = n - 1; k > 0; --k) st.push(ends[k - 1], ends[k]);
}

/// Sign of f at the exact point origin + t * dir: +1, -1, or 0 when intervals cannot tell.
int sign_at(RenderContext& ctx, const Vec3& o, const IBox& dir, double t) {
  const IBox p = segment_box(o, dir, Interval(t));
  if (!box_inside(p, ctx.bounds())) return 0;
  const Interval f = ctx.eval(p);
  return f.certainly_positive() ? 1 : (f.certainly_negative() ? -1 : 0);
}

/// Tries to prove a root in or around out->t: a strict sign change between two depths, on a
/// segment inside the bounds where f is continuous. When the ends of the piece are too close to
/// the root for intervals to tell the sign, the bracket is widened a little (staying in range).
void certify(RenderContext& ctx, const Vec3& o, const IBox& dir, const Interval& range, double tol,
             RayHit* out) {
  for (double grow : {0.0, 1.0, 16.0, 256.0}) {
    const double a = std::max(range.lo(), out->t.lo() - grow * tol);
    const double b = std::min(range.hi(), out->t.hi() + grow * tol);
    const IBox seg = segment_box(o, dir, Interval(a, b));
    if (!box_inside(seg, ctx.bounds())) return;
    const int sa = sign_at(ctx, o, dir, a), sb = sign_at(ctx, o, dir, b);
    if (sa == 0 || sb == 0) continue;
    if (sa == sb) return;
    bool partial = false;
    if (ctx.setup.may_partial) ctx.eval(seg, &partial);
    if (partial) return;
    out->certified = true;
    out->t = Interval(a, b);
    return;
  }
}

/// A PieceStack whose pieces carry F over their boxes (the segment's pieces clipped to the
/// bounds), evaluated ahead: when the top piece has none yet, it and the next pieces below it
/// without one, up to kAhead, are evaluated in one call of RenderContext::eval_batch. A piece whose
/// clipped box is empty gets the empty interval without an evaluation, as the searches one piece at
/// a time skip it. Pushed pieces have no value until evaluated; a piece evaluated ahead keeps its
/// value under the pieces pushed above it. So the pieces popped, and their enclosures, are those of
/// a search one piece at a time; only the evaluations of pieces never popped (past a hit) are spent
/// in vain.
class EvaluatedPieceStack {
 public:
  static constexpr int kCapacity = PieceStack::kCapacity;
  static constexpr int kAhead = SpecializingEval::kBatch;

  EvaluatedPieceStack(RenderContext& ctx, const Vec3& o, const IBox& dir)
      : ctx_(ctx), o_(o), dir_(dir) {}

  /// False when full: the caller must then treat the piece conservatively (keep it).
  bool push(double a, double b) {
    if (n_ == kCapacity) return false;
    a_[n_] = a;
    b_[n_] = b;
    done_[n_] = false;
    ++n_;
    return true;
  }
  bool has_room(int k) const { return n_ + k <= kCapacity; }
  /// The top piece [a, b] and F over its box.
  bool pop(double* a, double* b, Interval* f) {
    if (n_ == 0) return false;
    if (!done_[n_ - 1]) evaluate_ahead();
    --n_;
    *a = a_[n_];
    *b = b_[n_];
    *f = Interval::raw(lo_[n_], hi_[n_]);
    return true;
  }

 private:
  void evaluate_ahead() {
    IBox boxes[kAhead];
    int which[kAhead];
    int k = 0;
    for (int i = n_ - 1; i >= 0 && k < kAhead; --i) {
      if (done_[i]) continue;
      done_[i] = true;
      boxes[k] = clip_box(segment_box(o_, dir_, Interval(a_[i], b_[i])), ctx_.bounds());
      if (boxes[k].is_empty()) {
        lo_[i] = Interval::kInf;  // the empty interval
        hi_[i] = -Interval::kInf;
      } else {
        which[k++] = i;
      }
    }
    if (k == 0) return;
    Interval out[kAhead];
    bool partial[kAhead];  // not used: the searches one piece at a time did not look at it
    ctx_.eval_batch(boxes, k, out, partial);
    for (int j = 0; j < k; ++j) {
      lo_[which[j]] = out[j].lo();
      hi_[which[j]] = out[j].hi();
    }
  }

  RenderContext& ctx_;
  const Vec3& o_;
  const IBox& dir_;
  // Left uninitialised, as PieceStack's (only entries below n_ are read).
  double a_[kCapacity];
  double b_[kCapacity];
  double lo_[kCapacity];
  double hi_[kCapacity];
  bool done_[kCapacity];
  int n_ = 0;
};

}  // namespace

RayHit search_ray(RenderContext& ctx, const Vec3& o, const IBox& dir, Interval range, double tol,
                  double newton_from, bool certify_hit, double first) {
  RayHit out;
  if (range.is_empty()) return out;
  PieceStack st;
  push_march(st, range, first);
  // Newton is tried once pieces are this narrow; wider pieces rarely have F' away from 0.
  // (The pieces are evaluated one at a time: evaluated ahead two or four per pass, as
  // segment_may_hit's, the halves of kept pieces mostly came in vain, and chubs took 1.018x the
  // instructions, the twist the same.)
  const double newton_width = std::max(tol, newton_from);
  double a = 0, b = 0;
  while (st.pop(&a, &b)) {
    const IBox seg = segment_box(o, dir, Interval(a, b));
    const IBox box = clip_box(seg, ctx.bounds());
    if (box.is_empty()) continue;
    bool partial = false;
    const Interval f = ctx.eval(box, &partial);
    if (f.is_empty() || !f.contains_zero()) continue;
    const double m = 0.5 * (a + b);
    if (b - a <= tol || m <= a || m >= b || !st.has_room(2)) {
      out.hit = true;
      out.t = Interval(a, b);
      // Certify by a strict sign change at the ends of a piece where f is continuous.
      if (certify_hit) certify(ctx, o, dir, range, tol, &out);
      return out;
    }
    // Newton only where the whole piece lies inside the bounds: its mean-value argument needs F'
    // over the whole segment, and a root it proves must be one of the scene (inside the bounds).
    if (b - a <= newton_width && !partial && box_inside(seg, ctx.bounds())) {
      // Interval Newton on g(t) = f(o + t dir): every root t* of [a, b] lies in
      // m - G(m) / G'([a, b]) when G' excludes 0 (mean value theorem).
      bool gpartial = false;
      const IGrad g = ctx.eval_grad(box, &gpartial);
      const Interval fp = dot(g.g, dir);
      if (!gpartial && fp.contains_zero()) {
        // Mean-value form G(m) + G'([a, b]) ([a, b] - m): near a grazing ray f stays small but
        // positive over long stretches, where the natural enclosure keeps pieces only through
        // overestimation and bisection would exclude them one tolerance at a time.
        const Interval mv = ctx.eval(segment_box(o, dir, Interval(m))) + fp * (Interval(a, b) - m);
        if (!mv.contains_zero()) continue;
      }
      if (!gpartial && !fp.contains_zero()) {
        double lo = a, hi = b;
        bool proved = false, excluded = false;
        for (int it = 0; it < 40; ++it) {
          const double mm = 0.5 * (lo + hi);
          const Interval fm = ctx.eval(segment_box(o, dir, Interval(mm)));
          const Interval n = Interval(mm) - fm / fp;
          const Interval next = intersect(n, Interval(lo, hi));
          if (next.is_empty()) {
            excluded = true;  // no root in [lo, hi]
            break;
          }
          if (n.lo() > lo && n.hi() < hi) proved = true;  // N inside: a unique root exists
          const bool shrunk = next.width() < 0.5 * (hi - lo);
          lo = next.lo();
          hi = next.hi();
          if (hi - lo <= tol || !shrunk) break;
        }
        if (excluded) continue;
        if (proved && hi - lo <= tol) {
          out.hit = true;
          out.certified = true;
          out.t = Interval(lo, hi);
          return out;
        }
        // Not converged: bisect what is left.
        const double m2 = 0.5 * (lo + hi);
        if (m2 > lo && m2 < hi) {
          st.push(m2, hi);
          st.push(lo, m2);
        } else {
          st.push(lo, hi);
        }
        continue;
      }
    }
    st.push(m, b);
    st.push(a, m);
  }
  return out;
}

RayHit search_shading_ray(RenderContext& ctx, const Vec3& o, const IBox& dir, Interval range,
                          double tol, double newton_from, double first) {
  if (!ctx.ray_poly) return search_ray(ctx, o, dir, range, tol, newton_from, false, first);
  RayHit out;
  if (range.is_empty()) return out;
  RayPolynomial& rp = *ctx.ray_poly;
  const int n = rp.degree();
  constexpr int kCoefs = RayPolynomial::kMaxDegree + 1;
  // Pieces [sa, sb] of s = t - t0 with the Bernstein coefficients of g over them, searched front
  // to back as search_ray's: a depth-first bisection keeps one piece per level plus one.
  struct Piece {
    double sa, sb;
    Interval b[kCoefs];
  };
  constexpr int kCapacity = 64;
  Piece st[kCapacity];
  int top = 0;
  const double t0 = range.lo();
  double len = 0;
  {
    Interval c[kCoefs];
    rp.restrict(o, dir, t0, c);
    len = (Interval(range.hi()) - Interval(t0)).hi();  // rounded up: covers range
    st[0].sa = 0;
    st[0].sb = len;
    bernstein_from_power(c, n, len, st[0].b);
    top = 1;
  }
  // Pieces that leave the bounds are kept only where their box meets them (as search_ray's); the
  // hull over the whole piece encloses g over the part inside. Where the whole range lies inside
  // (most shading rays), no piece needs the test.
  const bool inside =
      box_inside(segment_box(o, dir, Interval(t0) + Interval(0, len)), ctx.bounds());
  while (top > 0) {
    Piece& p = st[--top];
    ++ctx.evals;  // an enclosure of F over the piece
    const Interval t = Interval(t0) + Interval(p.sa, p.sb);
    if (!inside && clip_box(segment_box(o, dir, t), ctx.bounds()).is_empty()) continue;
    if (!bernstein_hull(p.b, n).contains_zero()) continue;
    // The halves' ends: each half's claimed range holds the exact half de Casteljau's step
    // describes (its ends meet at the exact midpoint, between these two doubles).
    const double m_up = 0.5 * (p.sa + p.sb), m_dn = -(0.5 * ((-p.sa) - p.sb));
    if (t.width() <= tol || !(m_dn > p.sa) || !(m_up < p.sb) || top + 2 > kCapacity) {
      out.hit = true;
      out.t = t;
      return out;
    }
    // p is the top slot: the second half goes there, the first half above it (popped first).
    Piece& first = st[top + 1];
    bernstein_halves(p.b, n, first.b, p.b);
    first.sa = p.sa;
    first.sb = m_up;
    p.sa = m_dn;
    top += 2;
  }
  return out;
}

bool segment_may_hit(RenderContext& ctx, const Vec3& o, const IBox& dir, Interval range, double tol,
                     double first, double* at, double* narrowest, double from) {
  if (range.is_empty()) return false;
  // F over each piece is evaluated ahead, up to four pieces per pass of the batched evaluator
  // (EvaluatedPieceStack): the pieces and their enclosures of a search one piece at a time.
  EvaluatedPieceStack st(ctx, o, dir);
  // Marched from the front: each piece is excluded with one evaluation where bisection of the
  // whole range would spend two per level on the way down to the front.
  push_march(st, range, first);
  double a = 0, b = 0;
  Interval f;
  while (st.pop(&a, &b, &f)) {
    if (f.is_empty() || !f.contains_zero()) continue;
    if (narrowest && a >= from) *narrowest = std::min(*narrowest, b - a);
    const double m = 0.5 * (a + b);
    if (b - a <= tol || m <= a || m >= b || !st.has_room(2)) {
      if (at) *at = a;
      return true;
    }
    st.push(m, b);
    st.push(a, m);
  }
  return false;
}

}  // namespace iaa
