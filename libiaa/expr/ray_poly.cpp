#include "expr/ray_poly.h"

#include <algorithm>
#include <cassert>

namespace iaa {

namespace {

constexpr int kStride = RayPolynomial::kMaxDegree + 1;

/// out = p * q (degrees dp, dq; dp + dq <= kMaxDegree). `out` may not alias p or q.
inline void poly_mul(const Interval* p, int dp, const Interval* q, int dq, Interval* out) {
  for (int k = 0; k <= dp + dq; ++k) {
    // The products p_i q_j with i + j = k.
    const int i0 = std::max(0, k - dq), i1 = std::min(k, dp);
    Interval sum = p[i0] * q[k - i0];
    for (int i = i0 + 1; i <= i1; ++i) sum += p[i] * q[k - i];
    out[k] = sum;
  }
}

/// out = p^2 (degree dp, 2 dp <= kMaxDegree), each cross product once and doubled, each square
/// taken as one (never below 0): tighter and about half the products of poly_mul(p, p).
inline void poly_square(const Interval* p, int dp, Interval* out) {
  for (int k = 0; k <= 2 * dp; ++k) {
    const int i0 = std::max(0, k - dp);
    Interval cross(0.0);
    bool any = false;
    for (int i = i0; 2 * i < k; ++i) {
      cross = any ? cross + p[i] * p[k - i] : p[i] * p[k - i];
      any = true;
    }
    Interval sum = any ? scale(cross, 2.0) : Interval(0.0);
    if (k % 2 == 0) sum = any ? sum + square(p[k / 2]) : square(p[k / 2]);
    out[k] = sum;
  }
}

/// out = p^n (n >= 0, n dp <= kMaxDegree) by binary powering, in squares where it can.
void pow_int(const Interval* p, int dp, int n, Interval* out) {
  if (n == 0) {
    out[0] = Interval(1.0);
    return;
  }
  if (n == 1) {
    std::copy(p, p + dp + 1, out);
    return;
  }
  Interval half[kStride], rest[kStride];
  pow_int(p, dp, n / 2, half);
  if (n % 2 == 0) {
    poly_square(half, dp * (n / 2), out);
    return;
  }
  poly_square(half, dp * (n / 2), rest);
  poly_mul(rest, dp * (n / 2) * 2, p, dp, out);
}

/// C(n, k) for n <= kMaxDegree: exact in a double.
double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;  // exact: every partial is C(n-k+i, i)
  return r;
}

}  // namespace

RayPolynomial::RayPolynomial(const Tape& tape)
    : tape_(&tape), deg_(static_cast<std::size_t>(tape.size()), 0) {
  const auto ins = tape.instrs();
  deg_[0] = deg_[1] = deg_[2] = 1;
  bool ok = true;
  for (int i = tape.first_op(); i < tape.size() && ok; ++i) {
    const Instr& in = ins[static_cast<std::size_t>(i)];
    const int da = deg_[static_cast<std::size_t>(in.a)];
    const int db = in.b >= 0 ? deg_[static_cast<std::size_t>(in.b)] : 0;
    int d = 0;
    switch (in.op) {
      case Op::kAdd:
      case Op::kSub:
        d = std::max(da, db);
        break;
      case Op::kMul:
        d = da + db;
        break;
      case Op::kScale:
      case Op::kDivConst:
      case Op::kNeg:
        d = da;
        break;
      case Op::kSquare:
        d = 2 * da;
        break;
      case Op::kPowInt:
        // Negative powers are quotients; a power beyond the degree bound ends the check before
        // the product can overflow.
        ok = in.power >= 0 && in.power <= kMaxDegree;
        d = ok ? in.power * da : 0;
        break;
      default:  // anything else is not a polynomial
        ok = false;
        break;
    }
    if (d > kMaxDegree) ok = false;
    deg_[static_cast<std::size_t>(i)] = d;
  }
  usable_ = ok;
  if (!usable_) return;
  degree_ = deg_[static_cast<std::size_t>(tape.root())];
  coef_.assign(static_cast<std::size_t>(tape.size()) * kStride, Interval(0.0));
  const auto consts = tape.constants();
  for (int i = 3; i < tape.first_op(); ++i) {
    coef_[static_cast<std::size_t>(i) * kStride] = Interval(consts[static_cast<std::size_t>(i)]);
  }
}

void RayPolynomial::restrict(const Vec3& o, const IBox& dir, double t0, Interval* c) {
  assert(usable_);
  IAA_ASSERT_UPWARD();
  Interval* s = coef_.data();
  // x = (o_x + t0 d_x) + s d_x, for every d_x in its interval: the start point's enclosure and
  // the direction are the two coefficients.
  const double oc[3] = {o.x, o.y, o.z};
  for (int v = 0; v < 3; ++v) {
    const Interval d = dir[v];
    s[v * kStride] = Interval(oc[v]) + Interval(t0) * d;
    s[v * kStride + 1] = d;
  }
  const auto ins = tape_->instrs();
  const double* k = tape_->constants().data();
  for (int i = tape_->first_op(); i < tape_->size(); ++i) {
    const Instr& in = ins[static_cast<std::size_t>(i)];
    const int d = deg_[static_cast<std::size_t>(i)];
    const Interval* a = s + static_cast<std::size_t>(in.a) * kStride;
    const int da = deg_[static_cast<std::size_t>(in.a)];
    const Interval* b = in.b >= 0 ? s + static_cast<std::size_t>(in.b) * kStride : nullptr;
    const int db = in.b >= 0 ? deg_[static_cast<std::size_t>(in.b)] : 0;
    Interval* out = s + static_cast<std::size_t>(i) * kStride;
    switch (in.op) {
      case Op::kAdd:
        for (int j = 0; j <= d; ++j) out[j] = (j <= da ? a[j] : 0.0) + (j <= db ? b[j] : 0.0);
        break;
      case Op::kSub:
        for (int j = 0; j <= d; ++j) out[j] = (j <= da ? a[j] : 0.0) - (j <= db ? b[j] : 0.0);
        break;
      case Op::kMul:
        poly_mul(a, da, b, db, out);
        break;
      case Op::kScale:
        for (int j = 0; j <= d; ++j) out[j] = scale(a[j], k[in.b]);
        break;
      case Op::kDivConst:
        for (int j = 0; j <= d; ++j) out[j] = div_const(a[j], k[in.b]);
        break;
      case Op::kNeg:
        for (int j = 0; j <= d; ++j) out[j] = -a[j];
        break;
      case Op::kSquare:
        poly_square(a, da, out);
        break;
      case Op::kPowInt:
        pow_int(a, da, in.power, out);
        break;
      default:
        assert(false && "not a polynomial tape");
        break;
    }
  }
  const Interval* r = s + static_cast<std::size_t>(tape_->root()) * kStride;
  std::copy(r, r + degree_ + 1, c);
}

void bernstein_from_power(const Interval* c, int n, double len, Interval* b) {
  IAA_ASSERT_UPWARD();
  assert(n >= 0 && n <= RayPolynomial::kMaxDegree && len >= 0);
  // Over [0, len], g(s) = sum_k a_k u^k with u = s / len in [0, 1] and a_k = c_k len^k; then
  // b_j = sum_{k <= j} C(j, k) / C(n, k) a_k. With alpha_k = a_k / C(n, k), b_j is the binomial
  // transform sum_k C(j, k) alpha_k: a Pascal triangle of sums, n + 1 quotients in all.
  Interval w[RayPolynomial::kMaxDegree + 1];
  Interval power(1.0);
  for (int k = 0; k <= n; ++k) {
    w[k] = c[k] * power;
    if (k > 0 && k < n) w[k] = div_const(w[k], binomial(n, k));
    power = power * Interval(len);
  }
  // Row m of the triangle: w[i] = sum_l C(m, l) alpha_{i + l}; its first entry is b_m.
  b[0] = w[0];
  for (int m = 1; m <= n; ++m) {
    for (int i = 0; i + m <= n; ++i) w[i] = w[i] + w[i + 1];
    b[m] = w[0];
  }
}

void bernstein_halves(const Interval* b, int n, Interval* left, Interval* right) {
  IAA_ASSERT_UPWARD();
  Interval w[RayPolynomial::kMaxDegree + 1];
  std::copy(b, b + n + 1, w);
  left[0] = w[0];
  right[n] = w[n];
  for (int r = 1; r <= n; ++r) {
    for (int i = 0; i + r <= n; ++i) w[i] = scale(w[i] + w[i + 1], 0.5);
    left[r] = w[0];
    right[n - r] = w[n - r];
  }
}

Interval bernstein_hull(const Interval* b, int n) {
  double lo = b[0].lo(), hi = b[0].hi();
  for (int j = 1; j <= n; ++j) {
    lo = std::min(lo, b[j].lo());
    hi = std::max(hi, b[j].hi());
  }
  return Interval::raw(lo, hi);
}

}  // namespace iaa
