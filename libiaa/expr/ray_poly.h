// A polynomial surface restricted to a ray, as a polynomial in the depth, and its Bernstein form.
//
// Where f is a polynomial in x, y, z (its tape has only + - * neg, products and quotients by
// constants, squares and integer powers n >= 0), g(s) = f(o + (t0 + s) d) is a polynomial in s of
// degree at most f's. Its coefficients are computed once per ray with interval arithmetic over the
// direction box (each coefficient's interval holds the coefficient of every direction in the box);
// after that, an enclosure of f over a piece of the ray costs a few operations on degree + 1
// intervals instead of a pass over the tape. In Bernstein form over a piece [0, L] the range of g
// lies in the hull of the coefficients (the convex hull property: g is a convex combination of
// them at every s), which narrows quadratically with the piece where the natural interval
// extension narrows linearly, and keeps the correlation between the three coordinates along the
// ray that a box around the piece loses. Halving a piece is de Casteljau's step at 1/2: the
// Bernstein coefficients of both halves from the piece's, exact but for outward rounding.
// The idea is surf's (a ray's restriction as a univariate polynomial); the enclosures are ours.
#pragma once

#include <vector>

#include "core/interval.h"
#include "core/vec.h"
#include "expr/tape.h"

namespace iaa {

class RayPolynomial {
 public:
  /// The highest degree served (Bernstein forms of degree n cost O(n^2) per halving).
  static constexpr int kMaxDegree = 12;

  /// Checks whether `tape` is a polynomial of degree at most kMaxDegree (every slot's degree
  /// bound by structure within it). The evaluator keeps a pointer to the tape.
  explicit RayPolynomial(const Tape& tape);
  explicit RayPolynomial(Tape&&) = delete;

  /// True when the tape is such a polynomial (else restrict() must not be called).
  bool usable() const { return usable_; }
  /// Degree bound of f, by structure (0 <= degree() <= kMaxDegree when usable()).
  int degree() const { return degree_; }

  /// The coefficients c[0..degree()] of g(s) = f(o + (t0 + s) d) in powers of s: c[k] encloses
  /// the k-th coefficient for every d in `dir`. Outward rounded; needs a RoundingScope.
  void restrict(const Vec3& o, const IBox& dir, double t0, Interval* c);

 private:
  const Tape* tape_;
  bool usable_ = false;
  int degree_ = 0;
  std::vector<int> deg_;        ///< per slot, its degree bound
  std::vector<Interval> coef_;  ///< per slot, kMaxDegree + 1 coefficients
};

/// The Bernstein coefficients b[0..n] over s in [0, len] of the polynomial with power
/// coefficients c[0..n] (g(s) = sum_k c_k s^k): for every s in [0, len], g(s) lies in the hull of
/// the b_j, and b_0 = g(0), b_n encloses g(len). `len` >= 0. Outward rounded; needs a
/// RoundingScope.
void bernstein_from_power(const Interval* c, int n, double len, Interval* b);

/// De Casteljau's step at 1/2: from Bernstein coefficients b[0..n] over a piece, those over its
/// first half (`left`) and its second half (`right`). `right` may be `b` itself (b is read
/// before either is written). Outward rounded; needs a RoundingScope.
void bernstein_halves(const Interval* b, int n, Interval* left, Interval* right);

/// The hull of b[0..n]: an enclosure of g over the piece.
Interval bernstein_hull(const Interval* b, int n);

}  // namespace iaa
