// Interval evaluation with the interval gradient and the interval Hessian, by second-order
// forward-mode differentiation over intervals: encloses f, every partial derivative and every
// second partial derivative over a box, where f is twice continuously differentiable on it.
//
// Its use is the *centred form of the gradient* (centred_gradient below): each partial g_i over a
// box B lies in g_i(c) + sum_j H_ij(B) (B_j - c_j) for a point c of B (the mean-value theorem
// applied to g_i, whose own gradient is row i of the Hessian). The natural interval extension of
// the gradient overestimates in proportion to B's size; this form's overestimation shrinks with
// the square of it, so on a small cell it is close to the gradient's true range. The certified
// mesher's cone and direction tests need nothing else (docs/mesh.md, "Centred gradients").
//
// Where f is not twice differentiable somewhere in the box (a kink of abs, min or max that the box
// does not decide; sqrt, log or a real power at 0; a pole) the second derivatives there are
// unbounded ([-inf, inf]): the centred form then gives nothing, never a wrong bound. This holds
// along the axes where the box has width: along an axis where it is a point, an entry may be a
// one-sided value (abs(x) y over x = [0, 0] gives H_xy = 1), which centred_gradient never uses
// (a point axis adds nothing to the form).
#pragma once

#include <array>

#include "core/vec.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_loop.h"

namespace iaa {

/// An interval value, its interval gradient and its interval Hessian (the 6 entries of the
/// symmetric matrix: xx, xy, xz, yy, yz, zz; see hess_index).
struct IHess {
  Interval v;
  std::array<Interval, 3> g;
  std::array<Interval, 6> h;
};

/// Index of the Hessian entry (i, j) in IHess::h, for either order of i and j.
constexpr std::size_t hess_index(std::size_t i, std::size_t j) {
  constexpr std::size_t k[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  return k[i][j];
}

namespace detail {

namespace ihess {
using G = std::array<Interval, 3>;
/// The pairs (i, j), i <= j, of each entry of IHess::h.
inline constexpr std::size_t kRow[6] = {0, 0, 0, 1, 1, 2};
inline constexpr std::size_t kCol[6] = {0, 1, 2, 1, 2, 2};

/// Entry k of the outer product g g^T, tight on the diagonal (g_i^2 >= 0).
inline Interval outer(const G& g, std::size_t k) {
  return kRow[k] == kCol[k] ? square(g[kRow[k]]) : g[kRow[k]] * g[kCol[k]];
}
/// phi(u) for phi' in d1 and phi'' in d2 over u's values (the chain rule):
/// g_i = d1 u_i, h_ij = d1 u_ij + d2 u_i u_j.
inline IHess chain(const Interval& v, const IHess& u, const Interval& d1, const Interval& d2) {
  IHess r;
  r.v = v;
  for (std::size_t i = 0; i < 3; ++i) r.g[i] = d1 * u.g[i];
  for (std::size_t k = 0; k < 6; ++k) r.h[k] = d1 * u.h[k] + d2 * outer(u.g, k);
  return r;
}
/// A value whose derivatives are unknown (not differentiable, or a pole, somewhere in the box).
inline IHess rough(const Interval& v) {
  IHess r;
  r.v = v;
  r.g.fill(Interval::whole());
  r.h.fill(Interval::whole());
  return r;
}
/// f applied to every component (value, partials, Hessian entries) of a: a linear rule.
template <class F>
inline IHess each(const IHess& a, F f) {
  IHess r;
  r.v = f(a.v);
  for (std::size_t i = 0; i < 3; ++i) r.g[i] = f(a.g[i]);
  for (std::size_t k = 0; k < 6; ++k) r.h[k] = f(a.h[k]);
  return r;
}
/// f applied to every pair of components of a and b: a linear rule.
template <class F>
inline IHess each(const IHess& a, const IHess& b, F f) {
  IHess r;
  r.v = f(a.v, b.v);
  for (std::size_t i = 0; i < 3; ++i) r.g[i] = f(a.g[i], b.g[i]);
  for (std::size_t k = 0; k < 6; ++k) r.h[k] = f(a.h[k], b.h[k]);
  return r;
}
/// The value v of min or max at a crease inside the box: the gradient the hull of both sides',
/// the Hessian unknown.
inline IHess crease(const Interval& v, const IHess& a, const IHess& b) {
  IHess r = rough(v);
  r.g = igrad::hulls(a.g, b.g, kAllVars);
  return r;
}
}  // namespace ihess

// Rules of the interval + gradient + Hessian mode. Each rule is the interval extension of the
// calculus rule (first and second order) evaluated with enclosures of its arguments, hence an
// enclosure of the derivatives wherever they exist; where they may not, unbounded.
struct IntervalHessRules {
  using Num = IHess;
  static constexpr bool kTracksChoices = true;
  static IHess constant(double v) {
    IHess r;
    r.v = Interval(v);
    return r;
  }
  static IHess add(const IHess& a, const IHess& b) {
    return ihess::each(a, b, [](const Interval& x, const Interval& y) { return x + y; });
  }
  static IHess sub(const IHess& a, const IHess& b) {
    return ihess::each(a, b, [](const Interval& x, const Interval& y) { return x - y; });
  }
  static IHess neg(const IHess& a) {
    return ihess::each(a, [](const Interval& x) { return -x; });
  }
  // (ab)_ij = a_ij b + a b_ij + a_i b_j + a_j b_i
  static IHess mul(const IHess& a, const IHess& b) {
    IHess r;
    r.v = a.v * b.v;
    for (std::size_t i = 0; i < 3; ++i) r.g[i] = a.g[i] * b.v + b.g[i] * a.v;
    for (std::size_t k = 0; k < 6; ++k) {
      const std::size_t i = ihess::kRow[k], j = ihess::kCol[k];
      const Interval cross =
          i == j ? iaa::scale(a.g[i] * b.g[i], 2.0) : a.g[i] * b.g[j] + a.g[j] * b.g[i];
      r.h[k] = a.h[k] * b.v + b.h[k] * a.v + cross;
    }
    return r;
  }
  static IHess scale(const IHess& a, double c) {
    return ihess::each(a, [c](const Interval& x) { return iaa::scale(x, c); });
  }
  static IHess div_const(const IHess& a, double c) {
    return ihess::each(a, [c](const Interval& x) { return iaa::div_const(x, c); });
  }
  // a / b = a (1/b), with (1/b)' = -1/b^2 and (1/b)'' = 2/b^3.
  static IHess div(const IHess& a, const IHess& b, Domain* d) {
    const Interval v = divide(a.v, b.v, d);
    if (b.v.contains_zero()) return ihess::rough(v);
    const Interval q = Interval(1.0) / b.v;
    IHess r = mul(a, ihess::chain(q, b, -iaa::square(q), iaa::scale(iaa::pow_int(q, 3), 2.0)));
    r.v = v;
    return r;
  }
  static IHess pow_int(const IHess& a, int n) {
    if (n == 0) return constant(1.0);
    if (n == 1) return a;
    return ihess::chain(iaa::pow_int(a.v, n), a, iaa::scale(iaa::pow_int(a.v, n - 1), n),
                        iaa::scale(iaa::pow_int(a.v, n - 2), double(n) * double(n - 1)));
  }
  /// Real power: value and gradient by the gradient mode's rule, the Hessian left unbounded (rare
  /// in surfaces; the centred form then falls back on the natural gradient).
  static IHess pow(const IHess& a, const IHess& b, Domain* d) {
    const IGrad ga{a.v, a.g}, gb{b.v, b.g};
    const IGrad p = IntervalGradRules::pow(ga, gb, d, kAllVars);
    IHess r = ihess::rough(p.v);
    r.g = p.g;
    return r;
  }
  static IHess square(const IHess& a) {
    return ihess::chain(iaa::square(a.v), a, iaa::scale(a.v, 2.0), Interval(2.0));
  }
  // sqrt' = 1 / (2 sqrt), sqrt'' = -1 / (4 sqrt^3) = -2 (sqrt')^3; unbounded where u reaches 0.
  static IHess sqrt(const IHess& a, Domain* d) {
    const Interval v = iaa::sqrt(a.v, d);
    if (a.v.lo() <= 0.0) return ihess::rough(v);
    const Interval d1 = Interval(1.0) / iaa::scale(v, 2.0);
    return ihess::chain(v, a, d1, iaa::scale(iaa::pow_int(d1, 3), -2.0));
  }
  static IHess exp(const IHess& a) {
    const Interval v = iaa::exp(a.v);
    return ihess::chain(v, a, v, v);
  }
  static IHess log(const IHess& a, Domain* d) {
    const Interval v = iaa::log(a.v, d);
    if (a.v.lo() <= 0.0) return ihess::rough(v);
    const Interval d1 = Interval(1.0) / a.v;
    return ihess::chain(v, a, d1, -iaa::square(d1));
  }
  static IHess sin(const IHess& a) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return ihess::chain(s, a, c, -s);
  }
  static IHess cos(const IHess& a) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return ihess::chain(c, a, -s, -c);
  }
  static std::pair<IHess, IHess> sincos(const IHess& a) {
    Interval s, c;
    iaa::sincos(a.v, &s, &c);
    return {ihess::chain(s, a, c, -s), ihess::chain(c, a, -s, -c)};
  }
  // tan' = 1 + tan^2, tan'' = 2 tan (1 + tan^2); unbounded across a pole.
  static IHess tan(const IHess& a, Domain* d) {
    Domain here = Domain::kFull;
    const Interval v = iaa::tan(a.v, &here);
    if (here == Domain::kPartial) {
      *d = Domain::kPartial;
      return ihess::rough(v);
    }
    const Interval d1 = Interval(1.0) + iaa::square(v);
    return ihess::chain(v, a, d1, iaa::scale(v * d1, 2.0));
  }
  // atan' = 1 / (1 + u^2), atan'' = -2u / (1 + u^2)^2.
  static IHess atan(const IHess& a) {
    const Interval d1 = Interval(1.0) / (Interval(1.0) + iaa::square(a.v));
    return ihess::chain(iaa::atan(a.v), a, d1, iaa::scale(a.v * iaa::square(d1), -2.0));
  }
  // A decided side is that side (the point rule's slope +1 at 0, as in the gradient mode); a kink
  // inside the box leaves the gradient the hull of both sides and the Hessian unbounded.
  static IHess abs(const IHess& a) {
    if (a.v.lo() >= 0.0) return a;
    if (a.v.hi() < 0.0) return neg(a);
    IHess r = ihess::rough(iaa::abs(a.v));
    for (std::size_t i = 0; i < 3; ++i) r.g[i] = hull(a.g[i], -a.g[i]);
    return r;
  }
  static IHess min(const IHess& a, const IHess& b, std::uint8_t* c) {
    *c = min_choice(a.v, b.v);
    if (*c == 1) return a;
    return *c == 2 ? b : ihess::crease(iaa::min(a.v, b.v), a, b);
  }
  static IHess max(const IHess& a, const IHess& b, std::uint8_t* c) {
    *c = max_choice(a.v, b.v);
    if (*c == 1) return a;
    return *c == 2 ? b : ihess::crease(iaa::max(a.v, b.v), a, b);
  }
};

}  // namespace detail

/// Evaluates a tape with its gradient and Hessian over boxes. One per thread; no allocation per
/// call. The evaluator keeps a pointer to its tape, which must outlive it.
class IntervalHessEval {
 public:
  explicit IntervalHessEval(const Tape& tape) : loop_(tape) {}
  explicit IntervalHessEval(Tape&&) = delete;
  /// Evaluates under a RoundingScope, opening one when the caller has none.
  IHess eval(const IBox& b) {
    if (rounding_is_upward()) [[likely]]
      return run(b);
    RoundingScope scope;
    return run(b);
  }
  /// The last evaluation met a partial domain or a pole: its results enclose nothing.
  bool partial_domain() const { return loop_.partial_domain(); }

 private:
  IHess run(const IBox& b) {
    const Interval o(0.0), l(1.0);
    IHess x, y, z;
    x.v = b.x;
    x.g = {l, o, o};
    y.v = b.y;
    y.g = {o, l, o};
    z.v = b.z;
    z.g = {o, o, l};
    return loop_.run(x, y, z);
  }
  detail::TapeLoop<detail::IntervalHessRules> loop_;
};

/// The centred form of the gradient over box b around its point c: g(c) + H(b) (b - c), for `gc`
/// an enclosure of the gradient at c and `h` the Hessian enclosure over b (IntervalHessEval),
/// both without domain trouble. Each component encloses that partial over b wherever f is twice
/// continuously differentiable on b (elsewhere h is unbounded and so is the component). Axes along
/// which b is a point add nothing.
inline std::array<Interval, 3> centred_gradient(const IBox& b, const Vec3& c,
                                                const std::array<Interval, 3>& gc,
                                                const std::array<Interval, 6>& h) {
  IAA_ASSERT_UPWARD();
  std::array<Interval, 3> r = gc;
  for (std::size_t j = 0; j < 3; ++j) {
    const Interval& bj = b[int(j)];
    if (bj.lo() == bj.hi()) continue;
    const Interval d = bj - Interval(c[int(j)]);
    for (std::size_t i = 0; i < 3; ++i) r[i] = r[i] + h[hess_index(i, j)] * d;
  }
  return r;
}

}  // namespace iaa
