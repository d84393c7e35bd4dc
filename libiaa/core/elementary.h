// Point kernels of sin, cos, exp and log with a proved error bound, for the interval rules of
// interval.cpp (one argument reduction and a polynomial per endpoint, no libm call, no switch of
// the rounding mode) and for point evaluation.
//
// Each kernel returns a double v with |v - f(x)| <= kRelErr * |v| + abs_err, whatever the rounding
// mode of the thread (an operation rounded in any IEEE mode is within 2^-52 of its exact result,
// relatively: the bounds below count every operation that way). The interval rules widen v by
// that bound (interval.cpp). The derivation is written beside each kernel;
// tests/core/elementary_mpfr_test.cpp measures the error against MPFR on random and hard
// arguments and checks that it stays within half the bound.
//
// Polynomials are Taylor polynomials: their remainder is bounded by the next term (Lagrange), so
// the approximation error needs no minimax certificate. Coefficients are 1/n! rounded to nearest
// (hex literals: -frounding-math keeps GCC from folding 1.0/6.0 at compile time); each carries a
// relative error below 2^-53.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace iaa::elementary {

/// Relative error bound of every kernel here: 8 * 2^-52 (the derivations give at most 6.5 *
/// 2^-52; the margin keeps the bound valid for |v| instead of |f(x)|).
inline constexpr double kRelErr = 0x1p-49;

/// Largest |x| the trigonometric reduction handles (|k| < 2^20 below): as interval.cpp's limit,
/// beyond which sin and cos give [-1, 1].
inline constexpr double kTrigMax = 1e6;

/// x = k pi/2 + r: the quadrant k and the reduced argument r, |r| <= 0.78540.
struct Quadrant {
  double r;
  std::int64_t k;
};

/// Cody and Waite's reduction by pi/2 in three parts, for |x| <= kTrigMax (not checked).
///
/// k = trunc(x (2/pi) +- 1/2): y = x (2/pi) is within 2^-30 of the exact quotient for |x| <=
/// 1e6, so |x 2/pi - k| <= 1/2 + 2^-29 and |r| <= pi/4 + 2^-28 < 0.78540 (the conversion truncates
/// in every rounding mode). pi/2 = C1 + C2 + C3 + d, |d| < 2^-122: C1 and C2 have 33 significant
/// bits, so k C1 and k C2 are exact for |k| < 2^20.
/// - x - k C1 is exact: for k != 0, |x| >= 0.78 is a multiple of 2^-53, as is k C1 (a multiple
///   of 2^-32); the difference is below 1 in magnitude, so it has at most 53 bits.
/// - (x - k C1) - k C2 is a multiple of 2^-66: exact when below 2^-13, else rounded with relative
///   error <= 2^-52.
/// - k C3 has error <= 2^-101 (|k C3| < 2^-49), k d < 2^-102; the last subtraction rounds with
///   relative error <= 2^-52.
/// So |r_computed - r| <= 2^-51 |r| + 2^-99 for k != 0, and r = x exactly for k = 0.
inline constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
inline constexpr double kHalfPi1 = 0x1.921fb544p+0, kHalfPi2 = 0x1.0b4611a6p-34,
                        kHalfPi3 = 0x1.3198a2e037073p-69;
inline Quadrant reduce_half_pi(double x) {
  const double y = x * kTwoOverPi;
  const auto k = static_cast<std::int64_t>(y + std::copysign(0.5, y));
  const double kd = static_cast<double>(k);
  return {((x - kd * kHalfPi1) - kd * kHalfPi2) - kd * kHalfPi3, k};
}

/// Absolute error of the reduction as it reaches sin and cos (see reduce_half_pi), to add to
/// kRelErr * |v| when k != 0: 2^-99 rounded far up.
inline constexpr double kReducedAbsErr = 0x1p-96;

/// c as a T: a double, or a vector of 2 or 4 doubles with c in every lane (a constant of the
/// vector type, rather than a scalar GCC broadcasts at run time).
template <class T>
constexpr T splat(double c) {
  if constexpr (sizeof(T) == sizeof(double)) {
    return c;
  } else if constexpr (sizeof(T) == 2 * sizeof(double)) {
    return T{c, c};
  } else {
    static_assert(sizeof(T) == 4 * sizeof(double), "a double, or a vector of 2 or 4");
    return T{c, c, c, c};
  }
}

/// sin r for |r| <= 0.786, as r + r (z P(z)), z = r^2, P(z) = (sin r - r) / r^3 to z^6 (the
/// Taylor polynomial of sin to r^15).
/// Bound (e = 2^-52): the remainder is <= |r|^17 / 17! <= 0.27 e |r|. P lies in [-1/6, -0.156]
/// and its terms after -1/6 are below 0.031 of it, so P is computed within 1.7 e relatively
/// (the coefficient 0.5 e, the last add e, the tail 0.1 e); z, z P and r (z P)
/// add e each: 4.7 e on t = r z P, where |t| <= 0.103 |r| and |s| >= 0.897 |r|. With the last
/// add, |s - sin r| <= (0.54 + 1 + 0.3) e |s|. The reduction's error dr moves sin r by at most
/// |dr| <= 2^-51 |r| + 2^-99 <= 2.3 e |s| + 2^-99: 4.2 e |s| + 2^-99 in all. An underflow of z
/// or t adds at most a few 2^-1074.
template <class T>
inline T sin_poly(T r) {
  constexpr auto K = splat<T>;
  // P = -1/3! + z T, the tail T by Estrin's scheme in w = z^2 (shorter dependency chains than
  // Horner's). z T <= 0.0052 |P|, so T's own rounding errors (a few e) count for under 0.03 e.
  const T z = r * r, w = z * z;
  const T t = (K(0x1.1111111111111p-7) - z * K(0x1.a01a01a01a01ap-13)) +            // 1/5!, 1/7!
              w * (K(0x1.71de3a556c734p-19) - z * K(0x1.ae64567f544e4p-26)) +       // 1/9!, 1/11!
              (w * w) * (K(0x1.6124613a86d09p-33) - z * K(0x1.ae7f3e733b81fp-41));  // 1/13!, 1/15!
  const T p = K(-0x1.5555555555555p-3) + z * t;                                     // -1/3!
  return r + r * (z * p);
}

/// cos r for |r| <= 0.786, as 1 + z Q(z), z = r^2, Q(z) = (cos r - 1) / r^2 to z^7 (the Taylor
/// polynomial of cos to r^16).
/// Bound (e = 2^-52): the remainder is <= r^18 / 18! <= 0.01 e. Q lies in [-1/2, -0.474] and is
/// computed within 1.6 e (the last add e, the tail z T <= 0.026 |Q| 0.3 e); z Q, |z Q| <= 0.31,
/// within 3.6 e, i.e. 1.1 e absolutely; with the last add and c >= 0.707, |c - cos r| <= (1.6 + 1 +
/// 0.02) e |c|. The reduction's error dr moves cos r by at most |sin r| |dr| <= 0.71 (2^-51 0.786 +
/// 2^-99) <= 1.6 e |c| + 2^-99: 4.3 e |c| + 2^-99 in all.
template <class T>
inline T cos_poly(T r) {
  constexpr auto K = splat<T>;
  // Q = -1/2 + z T, the tail T by Estrin's scheme as in sin_poly (z T <= 0.026 |Q|).
  const T z = r * r, w = z * z;
  const T t =
      (K(0x1.5555555555555p-5) - z * K(0x1.6c16c16c16c17p-10)) +              // 1/4!, 1/6!
      w * (K(0x1.a01a01a01a01ap-16) - z * K(0x1.27e4fb7789f5cp-22)) +         // 1/8!, 1/10!
      (w * w) * ((K(0x1.1eed8eff8d898p-29) - z * K(0x1.93974a8c07c9dp-37)) +  // 1/12!, 1/14!
                 w * K(0x1.ae7f3e733b81fp-45));                               // 1/16!
  const T q = K(-0.5) + z * t;
  return K(1.0) + z * q;
}

/// sin x from the reduction x = k pi/2 + r and s = sin r, c = cos r: s, c, -s, -c for k = 0, 1,
/// 2, 3 mod 4. cos x = sin(x + pi/2) is the same with k + 1.
inline double sin_of(std::int64_t k, double s, double c) {
  // Branch-free (the quadrant of an interval's end is unpredictable): select by a mask of the
  // bits, then flip the sign bit for k = 2, 3 mod 4 (k & 3 is k mod 4 also for k < 0).
  const std::uint64_t odd = 0 - static_cast<std::uint64_t>(k & 1);
  const std::uint64_t bits =
      (std::bit_cast<std::uint64_t>(c) & odd) | (std::bit_cast<std::uint64_t>(s) & ~odd);
  return std::bit_cast<double>(bits ^ (static_cast<std::uint64_t>(k & 2) << 62));
}

/// An argument reduced by reduce_half_pi, with sin r and cos r.
struct ReducedTrig {
  Quadrant q;
  double s, c;
};

#if defined(__GNUC__) || defined(__clang__)
#define IAA_ELEMENTARY_LANES 1
/// Two doubles (or integers) in one SSE2 register on x86-64 (GCC's and Clang's vector
/// extension; plain pairs elsewhere). Operations on them work lane by lane, as on scalars.
using V2d = double __attribute__((vector_size(16)));
using V2l = std::int64_t __attribute__((vector_size(16)));
using V2u = std::uint64_t __attribute__((vector_size(16)));

/// reduce_half_pi, sin_poly and cos_poly of two arguments at once, one per lane: the same
/// operations in the same order on each lane, so the results are the same doubles as the scalar
/// kernels' in every rounding mode (no FMA contraction: the build targets baseline x86-64, which
/// has none; tests/core/elementary_mpfr_test.cpp checks bit equality in all four modes). The
/// error bounds above hold unchanged. About half the instructions of two scalar passes: the
/// interval rules of sin and cos take both ends of an interval here. |x| <= kTrigMax (not
/// checked).
struct TrigLanes {
  V2d r;
  V2l k;
  V2d s, c;
};
using V2i = std::int32_t __attribute__((vector_size(8)));
inline TrigLanes reduce_sin_cos_lanes(V2d x) {
  const V2d y = x * kTwoOverPi;
  // copysign(0.5, y) by the sign bit; the truncation to int32 (|k| < 2^20) is reduce_half_pi's.
  const V2d half = std::bit_cast<V2d>((std::bit_cast<V2u>(y) & 0x8000000000000000ULL) |
                                      std::bit_cast<std::uint64_t>(0.5));
  const V2i k = __builtin_convertvector(y + half, V2i);
  const V2d kd = __builtin_convertvector(k, V2d);
  const V2d r = ((x - kd * kHalfPi1) - kd * kHalfPi2) - kd * kHalfPi3;
  return {r, __builtin_convertvector(k, V2l), sin_poly(r), cos_poly(r)};
}

/// sin_of on both lanes (the same bit operations).
inline V2d sin_of_lanes(V2l k, V2d s, V2d c) {
  const V2u odd = std::bit_cast<V2u>(0 - (k & 1));
  const V2u bits = (std::bit_cast<V2u>(c) & odd) | (std::bit_cast<V2u>(s) & ~odd);
  return std::bit_cast<V2d>(bits ^ (std::bit_cast<V2u>(k & 2) << 62));
}
#endif

/// The reduction and both polynomials of two arguments (reduce_sin_cos_lanes where the vector
/// extension exists): the same doubles as reduce_half_pi, sin_poly and cos_poly of each.
inline void reduce_sin_cos2(double a, double b, ReducedTrig* ra, ReducedTrig* rb) {
#ifdef IAA_ELEMENTARY_LANES
  const TrigLanes t = reduce_sin_cos_lanes(V2d{a, b});
  *ra = {{t.r[0], t.k[0]}, t.s[0], t.c[0]};
  *rb = {{t.r[1], t.k[1]}, t.s[1], t.c[1]};
#else
  const Quadrant qa = reduce_half_pi(a), qb = reduce_half_pi(b);
  *ra = {qa, sin_poly(qa.r), cos_poly(qa.r)};
  *rb = {qb, sin_poly(qb.r), cos_poly(qb.r)};
#endif
}

/// sin_poly(r) and cos_poly(r) in one pass (point sincos), lane 0 the sine, lane 1 the cosine:
/// the same doubles as the two scalar calls. The tails are the same Estrin scheme with the
/// coefficients of each, the sine's with a last term w * 0 (+0, and adding +0 to its tail,
/// which is never 0, changes nothing in any mode); then the sine is r + r (z P) and the cosine
/// 1 + 1 (z Q), the product by 1 being exact.
inline void sin_cos_poly(double r, double* s, double* c) {
#ifdef IAA_ELEMENTARY_LANES
  const double z = r * r, w = z * z;
  const V2d t = (V2d{0x1.1111111111111p-7, 0x1.5555555555555p-5} -
                 z * V2d{0x1.a01a01a01a01ap-13, 0x1.6c16c16c16c17p-10}) +
                w * (V2d{0x1.71de3a556c734p-19, 0x1.a01a01a01a01ap-16} -
                     z * V2d{0x1.ae64567f544e4p-26, 0x1.27e4fb7789f5cp-22}) +
                (w * w) * ((V2d{0x1.6124613a86d09p-33, 0x1.1eed8eff8d898p-29} -
                            z * V2d{0x1.ae7f3e733b81fp-41, 0x1.93974a8c07c9dp-37}) +
                           w * V2d{0.0, 0x1.ae7f3e733b81fp-45});
  const V2d u = z * (V2d{-0x1.5555555555555p-3, -0.5} + z * t);
  const V2d a = {r, 1.0};
  const V2d v = a + a * u;
  *s = v[0];
  *c = v[1];
#else
  *s = sin_poly(r);
  *c = cos_poly(r);
#endif
}

/// Absolute error term of sin x and cos x from reduce_half_pi(x): kReducedAbsErr after a
/// reduction, a few subnormals (underflow in the polynomials) when r = x.
inline double trig_abs_err(const Quadrant& q) {
  return q.k == 0 ? 0x1p-1070 : kReducedAbsErr;
}

/// Largest |x| of exp_kernel: exp(x) and every factor below are then normal doubles.
inline constexpr double kExpMax = 708.0;

/// 2^(j/32) rounded to nearest, j = 0 .. 31 (relative error <= 0.43 * 2^-52; the MPFR test
/// checks each entry).
inline constexpr double kExp2Table[32] = {
    0x1.0000000000000p+0, 0x1.059b0d3158574p+0, 0x1.0b5586cf9890fp+0, 0x1.11301d0125b51p+0,
    0x1.172b83c7d517bp+0, 0x1.1d4873168b9aap+0, 0x1.2387a6e756238p+0, 0x1.29e9df51fdee1p+0,
    0x1.306fe0a31b715p+0, 0x1.371a7373aa9cbp+0, 0x1.3dea64c123422p+0, 0x1.44e086061892dp+0,
    0x1.4bfdad5362a27p+0, 0x1.5342b569d4f82p+0, 0x1.5ab07dd485429p+0, 0x1.6247eb03a5585p+0,
    0x1.6a09e667f3bcdp+0, 0x1.71f75e8ec5f74p+0, 0x1.7a11473eb0187p+0, 0x1.82589994cce13p+0,
    0x1.8ace5422aa0dbp+0, 0x1.93737b0cdc5e5p+0, 0x1.9c49182a3f090p+0, 0x1.a5503b23e255dp+0,
    0x1.ae89f995ad3adp+0, 0x1.b7f76f2fb5e47p+0, 0x1.c199bdd85529cp+0, 0x1.cb720dcef9069p+0,
    0x1.d5818dcfba487p+0, 0x1.dfc97337b9b5fp+0, 0x1.ea4afa2a490dap+0, 0x1.f50765b6e4540p+0,
};

/// The reduction of exp_kernel: 32/ln2, and ln2/32 = kExpL1 + kExpL2 + d (see exp_kernel).
inline constexpr double kExp32OverLn2 = 0x1.71547652b82fep+5;
inline constexpr double kExpL1 = 0x1.62e42fefap-6, kExpL2 = 0x1.cf79abc9e3b3ap-45;
/// exp r for the reduced argument r, |r| <= 0.010832: 1 + (r + z H) (see exp_kernel).
template <class T>
inline T exp_poly(T r) {
  constexpr auto K = splat<T>;
  const T z = r * r;
  const T h = (K(0.5) + r * K(0x1.5555555555555p-3)) +                      // 1/2, 1/3!
              z * ((K(0x1.5555555555555p-5) + r * K(0x1.1111111111111p-7))  // 1/4!, 1/5!
                   + z * K(0x1.6c16c16c16c17p-10));                         // 1/6!
  return K(1.0) + (r + z * h);
}

/// exp x for |x| <= kExpMax, with |v - exp x| <= kRelErr |v| (no absolute term).
///
/// x = k ln2/32 + r, k = trunc(x 32/ln2 +- 1/2), |r| <= ln2/64 + 2^-40 < 0.010832, and
/// exp x = 2^(k >> 5) 2^((k & 31)/32) exp r. ln2/32 = L1 + L2 + d, |d| < 2^-97: L1 has 36
/// significant bits, so k L1 is exact (|k| < 2^15); x - k L1 is exact (for k != 0, both are
/// multiples of 2^-59 and the difference is below 2^-6); k L2 has error <= 2^-81, k d < 2^-82,
/// and the last subtraction rounds with relative error <= e = 2^-52: |r_computed - r| <= e |r| +
/// 2^-80, which moves exp r by a factor within 1 +- 0.011 e.
/// exp r = 1 + (r + z H), z = r^2, H = (1/2 + r/6) + z ((1/24 + r/120) + z/720): the Taylor
/// polynomial to r^6 (remainder <= e^0.011 r^7 / 7! <= 0.02 e). H (within 0.502 +- 0.002) is
/// computed within 1.1 e; z H (<= 6e-5) adds under 0.001 e absolutely, r + z H (<= 0.011) 0.011 e,
/// and the last add e |v|, v >= 0.989: 1.05 e. The table entry adds 0.43 e and the product by
/// it e; the product by 2^(k >> 5) is exact. In all |v - exp x| <= 2.5 e |v|.
inline double exp_kernel(double x) {
  const double y = x * kExp32OverLn2;
  const auto k = static_cast<std::int64_t>(y + std::copysign(0.5, y));
  const double kd = static_cast<double>(k);
  const double e_r = exp_poly((x - kd * kExpL1) - kd * kExpL2);
  // 2^(k >> 5) (an arithmetic shift: floor(k / 32)) is a normal double for |x| <= kExpMax.
  const double scale = std::bit_cast<double>(static_cast<std::uint64_t>((k >> 5) + 1023) << 52);
  return (scale * kExp2Table[k & 31]) * e_r;
}

#ifdef IAA_ELEMENTARY_LANES
/// exp_kernel over the lanes of a vector V of doubles (I32 and I64 the vectors of as many 32-
/// and 64-bit integers): the same operations in the same order on each lane, so the same doubles
/// in every rounding mode (tests/core/elementary_mpfr_test.cpp checks bit equality). |x| <=
/// kExpMax in the lanes whose result is used; the others give some finite or NaN double (the
/// table index is masked, so nothing is read out of bounds).
template <class V, class I32, class I64>
inline V exp_kernel_lanes(V x) {
  constexpr auto K = splat<V>;
  const V y = x * K(kExp32OverLn2);
  // copysign(0.5, y) by the sign bit; |k| < 2^15, so the truncation to int32 is the scalar one.
  const V half = std::bit_cast<V>((std::bit_cast<I64>(y) & std::int64_t(0x8000000000000000ULL)) |
                                  std::bit_cast<std::int64_t>(0.5));
  const I32 k = __builtin_convertvector(y + half, I32);
  const V kd = __builtin_convertvector(k, V);
  const V e_r = exp_poly((x - kd * K(kExpL1)) - kd * K(kExpL2));
  // floor(k / 32) by the 32-bit arithmetic shift, widened to 64 bits for the exponent field.
  const I64 scale = (__builtin_convertvector((k >> 5) + 1023, I64)) << 52;
  V t;
  for (int j = 0; j < static_cast<int>(sizeof(V) / sizeof(double)); ++j)
    t[j] = kExp2Table[k[j] & 31];
  return (std::bit_cast<V>(scale) * t) * e_r;
}
/// exp_kernel of two arguments, one per lane (the interval rule's two ends).
inline V2d exp_kernel2(V2d x) {
  return exp_kernel_lanes<V2d, V2i, V2l>(x);
}
#endif

/// log(j/64) for j = 48 .. 96 as hi + lo: hi rounded to nearest, lo the rest rounded to nearest,
/// so |hi + lo - log(j/64)| <= 2^-53 |lo| < 2^-107 (the MPFR test checks each pair).
inline constexpr double kLogTable[49][2] = {
    {-0x1.269621134db92p-2, -0x1.e0efadd9db02bp-56},  // log(48/64)
    {-0x1.1178e8227e47cp-2, 0x1.0e63a5f01c691p-57},   // log(49/64)
    {-0x1.f991c6cb3b379p-3, -0x1.f665066f980a2p-57},  // log(50/64)
    {-0x1.d1037f2655e7bp-3, -0x1.60629242471a2p-57},  // log(51/64)
    {-0x1.a93ed3c8ad9e3p-3, -0x1.bcafa9de97203p-57},  // log(52/64)
    {-0x1.823c16551a3c2p-3, 0x1.1232ce70be781p-57},   // log(53/64)
    {-0x1.5bf406b543db2p-3, 0x1.1f5b44c0df7e7p-61},   // log(54/64)
    {-0x1.365fcb0159016p-3, -0x1.7d411a5b944adp-58},  // log(55/64)
    {-0x1.1178e8227e47cp-3, 0x1.0e63a5f01c691p-58},   // log(56/64)
    {-0x1.da727638446a2p-4, -0x1.401fa71733019p-58},  // log(57/64)
    {-0x1.9335e5d594989p-4, 0x1.478a85704ccb7p-58},   // log(58/64)
    {-0x1.4d3115d207eacp-4, -0x1.769f42c7842ccp-58},  // log(59/64)
    {-0x1.08598b59e3a07p-4, 0x1.dd7009902bf32p-58},   // log(60/64)
    {-0x1.894aa149fb343p-5, -0x1.a8be97660a23dp-60},  // log(61/64)
    {-0x1.0415d89e74444p-5, -0x1.c05cf1d753622p-59},  // log(62/64)
    {-0x1.0205658935847p-6, -0x1.27c8e8416e71fp-60},  // log(63/64)
    {0x0p+0, 0x0p+0},                                 // log(64/64)
    {0x1.fc0a8b0fc03e4p-7, -0x1.83092c59642a1p-62},   // log(65/64)
    {0x1.f829b0e7833p-6, 0x1.33e3f04f1ef23p-60},      // log(66/64)
    {0x1.77458f632dcfcp-5, 0x1.18d3ca87b9296p-59},    // log(67/64)
    {0x1.f0a30c01162a6p-5, 0x1.85f325c5bbacdp-59},    // log(68/64)
    {0x1.341d7961bd1d1p-4, -0x1.b599f227becbbp-58},   // log(69/64)
    {0x1.6f0d28ae56b4cp-4, -0x1.906d99184b992p-58},   // log(70/64)
    {0x1.a926d3a4ad563p-4, 0x1.942f48aa70ea9p-58},    // log(71/64)
    {0x1.e27076e2af2e6p-4, -0x1.61578001e0162p-60},   // log(72/64)
    {0x1.0d77e7cd08e59p-3, 0x1.9a5dc5e9030acp-57},    // log(73/64)
    {0x1.29552f81ff523p-3, 0x1.301771c407dbfp-57},    // log(74/64)
    {0x1.44d2b6ccb7d1ep-3, 0x1.9f4f6543e1f88p-57},    // log(75/64)
    {0x1.5ff3070a793d4p-3, -0x1.bc60efafc6f6ep-58},   // log(76/64)
    {0x1.7ab890210d909p-3, 0x1.be36b2d6a0608p-59},    // log(77/64)
    {0x1.9525a9cf456b4p-3, 0x1.d904c1d4e2e26p-57},    // log(78/64)
    {0x1.af3c94e80bff3p-3, -0x1.398cff3641985p-58},   // log(79/64)
    {0x1.c8ff7c79a9a22p-3, -0x1.4f689f8434012p-57},   // log(80/64)
    {0x1.e27076e2af2e6p-3, -0x1.61578001e0162p-59},   // log(81/64)
    {0x1.fb9186d5e3e2bp-3, -0x1.caaae64f21acbp-57},   // log(82/64)
    {0x1.0a324e27390e3p-2, 0x1.7dcfde8061c03p-56},    // log(83/64)
    {0x1.1675cababa60ep-2, 0x1.ce63eab883717p-61},    // log(84/64)
    {0x1.22941fbcf7966p-2, -0x1.76f5eb09628afp-56},   // log(85/64)
    {0x1.2e8e2bae11d31p-2, -0x1.8f4cdb95ebdf9p-56},   // log(86/64)
    {0x1.3a64c556945eap-2, -0x1.c68651945f97cp-57},   // log(87/64)
    {0x1.4618bc21c5ec2p-2, 0x1.f42decdeccf1dp-56},    // log(88/64)
    {0x1.51aad872df82dp-2, 0x1.3927ac19f55e3p-59},    // log(89/64)
    {0x1.5d1bdbf5809cap-2, 0x1.4236383dc7fe1p-56},    // log(90/64)
    {0x1.686c81e9b14afp-2, -0x1.ddea0f7f58e3dp-57},   // log(91/64)
    {0x1.739d7f6bbd007p-2, -0x1.8c76ceb014b04p-56},   // log(92/64)
    {0x1.7eaf83b82afc3p-2, 0x1.92ce979ed295p-56},     // log(93/64)
    {0x1.89a3386c1425bp-2, -0x1.29639dfbbf0fbp-56},   // log(94/64)
    {0x1.947941c2116fbp-2, -0x1.16cc8bae0bbe4p-56},   // log(95/64)
    {0x1.9f323ecbf984cp-2, -0x1.a92e513217f5cp-59},   // log(96/64)
};

/// The smallest and largest x whose log_kernel is exact up to its relative bound alone (no
/// absolute term): x in [127/128, 129/128), where the reduction below is x = 1 * (x / 1).
inline constexpr double kLogNearOneLo = 0x1.fcp-1, kLogNearOneHi = 0x1.02p+0;
/// Absolute error term of log_kernel away from 1 (see log_kernel).
inline constexpr double kLogAbsErr = 0x1p-56;

/// log x for a finite x > 0 (not checked), with |v - log x| <= kRelErr |v| + log_abs_err(x).
///
/// Reduction: x = 2^e m with m in [0.75, 1.5) (subnormals scaled by 2^54 first, exactly), by the
/// bits of x: exact. c = j/64 with j = round(64 m) in 48 .. 96 (from the truncation of 128 m,
/// exact), so |m - c| <= 2^-7 and m - c is exact (Sterbenz). log x = e ln2 + log c + log(m/c),
/// log(m/c) = 2 atanh(u), u = (m - c)/(m + c), |u| <= 2^-7 / 1.49 < 0.00526 (m + c >= 1.49).
/// Bound (e = 2^-52): m + c and the quotient round with relative error e each, so u is within
/// 2.01 e relatively, which moves 2 atanh(u) by at most 2.02 e relatively (its derivative is
/// 2/(1 - u^2), its value >= 2|u|). p = 2u + u (z Q), z = u^2, Q = 2/3 + z (2/5 + z 2/7), the
/// Taylor polynomial of 2 atanh to u^7 (remainder <= 2|u| u^8 / 8 < 10^-19 |p|); |u z Q| <=
/// 2^-15.6 |u|, so its own rounding errors count for under 0.001 e, and the last add e: |p -
/// log(m/c)| <= 3.1 e |p|, |p| <= 0.01053.
/// - e = 0, j = 64 (x in [127/128, 129/128)): the sums below add exact zeros, v = p, and
///   |v - log x| <= 3.1 e |v|.
/// - Else: ln2 = L1 + L2 + d, L1 of 40 bits so that e L1 is exact (|e| <= 1076), |L2| < 2^-42,
///   |d| < 2^-95; the table's error < 2^-107. s2 = e L2 + lo (|s2| < 2^-30, error < 2^-81),
///   s3 = s2 + p (error e |s3|, |s3| <= 0.0106), s1 = e L1 + hi (error e |s1|), v = s1 + s3
///   (error e |v|). With |s1| <= |v| + |s3|: |v - log x| <= e |v| + e |s1| + e |s3| + 3.1 e |p| +
///   2^-80 <= 2 e |v| + 0.055 e, within kRelErr |v| + kLogAbsErr (0.0625 e).
inline double log_kernel(double x) {
  constexpr double kL1 = 0x1.62e42fefa4p-1, kL2 = -0x1.8432a1b0e2634p-43;
  int e = 0;
  if (x < 0x1p-1022) {  // subnormal: scale into the normal range (exact)
    x *= 0x1p54;
    e = -54;
  }
  const auto bits = std::bit_cast<std::uint64_t>(x);
  e += static_cast<int>(bits >> 52) - 1023;
  // m in [1, 2) from the mantissa; m >= 1.5 (its first fraction bit set) becomes m / 2.
  std::uint64_t mb = (bits & 0x000fffffffffffffULL) | (std::uint64_t{1023} << 52);
  if (mb & (std::uint64_t{1} << 51)) {
    mb -= std::uint64_t{1} << 52;
    ++e;
  }
  const double m = std::bit_cast<double>(mb);
  const int j = (static_cast<int>(m * 128.0) + 1) >> 1;  // round(64 m): 48 .. 96
  const double c = j * 0x1p-6;
  const double u = (m - c) / (m + c);
  const double z = u * u;
  const double q = 0x1.5555555555555p-1 + z * (0x1.999999999999ap-2 + z * 0x1.2492492492492p-2);
  const double p = 2.0 * u + u * (z * q);  // 2/3, 2/5, 2/7 above
  const double ed = e;
  const double* t = kLogTable[j - 48];
  return (ed * kL1 + t[0]) + ((ed * kL2 + t[1]) + p);
}

/// Absolute error term of log_kernel(x): 0 near 1, where log x is p alone, else kLogAbsErr.
inline double log_abs_err(double x) {
  return (x >= kLogNearOneLo && x < kLogNearOneHi) ? 0.0 : kLogAbsErr;
}

// Point values (the kernels without widening; libm beyond their ranges and for NaN).

inline double sin(double x) {
  if (!(std::fabs(x) <= kTrigMax)) return std::sin(x);
  const Quadrant q = reduce_half_pi(x);
  return (q.k & 1) ? sin_of(q.k, 0.0, cos_poly(q.r)) : sin_of(q.k, sin_poly(q.r), 0.0);
}
inline double cos(double x) {
  if (!(std::fabs(x) <= kTrigMax)) return std::cos(x);
  const Quadrant q = reduce_half_pi(x);
  return (q.k & 1) ? sin_of(q.k + 1, sin_poly(q.r), 0.0) : sin_of(q.k + 1, 0.0, cos_poly(q.r));
}
inline void sincos(double x, double* s, double* c) {
  if (!(std::fabs(x) <= kTrigMax)) {
    *s = std::sin(x);
    *c = std::cos(x);
    return;
  }
  const Quadrant q = reduce_half_pi(x);
  double sr, cr;
  sin_cos_poly(q.r, &sr, &cr);
  *s = sin_of(q.k, sr, cr);
  *c = sin_of(q.k + 1, sr, cr);
}
inline double exp(double x) {
  return std::fabs(x) <= kExpMax ? exp_kernel(x) : std::exp(x);
}

/// log x: the kernel for finite x > 0, libm otherwise (-inf at 0, NaN below, inf at inf).
inline double log(double x) {
  return (x > 0.0 && x <= 0x1.fffffffffffffp+1023) ? log_kernel(x) : std::log(x);
}

}  // namespace iaa::elementary
