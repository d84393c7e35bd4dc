// Proves that Interval bounds are outward rounded under the flags this target is really built with
// (tools/test.sh runs it in the Release build: CMake's -O3 -DNDEBUG plus iaa_options'
// -frounding-math -fno-fast-math, and -ffp-model=strict with clang). Exact checks use __float128,
// in which the sum and product of two doubles are exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include "core/interval.h"

namespace iaa {
namespace {

using Q = __float128;

double random_double(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> ex(-60, 60);
  std::bernoulli_distribution neg(0.5);
  const double v = std::ldexp(mant(rng), ex(rng));
  return neg(rng) ? -v : v;
}

TEST(Rounding, AddSubMulEncloseTheExactResult) {
  std::mt19937_64 rng(1);
  RoundingScope scope;
  int strict = 0;
  for (int i = 0; i < 200000; ++i) {
    const double a = random_double(rng), b = random_double(rng);
    const Interval s = Interval(a) + Interval(b);
    const Interval d = Interval(a) - Interval(b);
    const Interval p = Interval(a) * Interval(b);
    const Q qs = Q(a) + Q(b), qd = Q(a) - Q(b), qp = Q(a) * Q(b);
    ASSERT_TRUE(Q(s.lo()) <= qs && qs <= Q(s.hi())) << a << " + " << b;
    ASSERT_TRUE(Q(d.lo()) <= qd && qd <= Q(d.hi())) << a << " - " << b;
    ASSERT_TRUE(Q(p.lo()) <= qp && qp <= Q(p.hi())) << a << " * " << b;
    strict += p.lo() < p.hi();
  }
  // Most products of random doubles are not representable: the bounds must then differ, which
  // they would not if the compiler had folded or reordered the rounding away.
  EXPECT_GT(strict, 150000);
}

TEST(Rounding, DivisionAndSqrtEncloseTheExactResult) {
  std::mt19937_64 rng(2);
  RoundingScope scope;
  for (int i = 0; i < 200000; ++i) {
    const double a = random_double(rng), b = random_double(rng);
    const Interval q = Interval(a) / Interval(b);
    // lo <= a/b <= hi  <=>  lo*b <= a <= hi*b for b > 0 (reversed for b < 0); exact in quad.
    if (b > 0) {
      ASSERT_TRUE(Q(q.lo()) * Q(b) <= Q(a) && Q(a) <= Q(q.hi()) * Q(b)) << a << " / " << b;
    } else {
      ASSERT_TRUE(Q(q.lo()) * Q(b) >= Q(a) && Q(a) >= Q(q.hi()) * Q(b)) << a << " / " << b;
    }
    const double m = std::fabs(a);
    Domain dom = Domain::kFull;
    const Interval r = sqrt(Interval(m), &dom);
    ASSERT_TRUE(Q(r.lo()) * Q(r.lo()) <= Q(m) && Q(m) <= Q(r.hi()) * Q(r.hi())) << "sqrt " << m;
    ASSERT_EQ(dom, Domain::kFull);
  }
}

TEST(Rounding, ConstantsAreNotFoldedToAPoint) {
  RoundingScope scope;
  // With -frounding-math the compiler must not fold 1/3 into one double.
  const Interval third = Interval(1.0) / Interval(3.0);
  EXPECT_LT(third.lo(), third.hi());
  EXPECT_TRUE(Q(third.lo()) * 3 <= Q(1) && Q(1) <= Q(third.hi()) * 3);
  const Interval tenth = Interval(1.0) / Interval(10.0);
  EXPECT_LT(tenth.lo(), tenth.hi());
}

TEST(Rounding, ScopeRestoresTheCallersMode) {
  const int before = std::fegetround();
  {
    RoundingScope scope;
    EXPECT_TRUE(rounding_is_upward());
    {
      RoundingScope inner;
      EXPECT_TRUE(rounding_is_upward());
    }
    EXPECT_TRUE(rounding_is_upward());
  }
  EXPECT_EQ(std::fegetround(), before);
}

// A random double with `bits` significant bits and a binary exponent in [-20, 20]: its powers up
// to n = 112 / bits are exact in __float128 (113-bit significand).
double random_bits(std::mt19937_64& rng, int bits) {
  std::uniform_int_distribution<std::int64_t> mant(std::int64_t{1} << (bits - 1),
                                                   (std::int64_t{1} << bits) - 1);
  std::uniform_int_distribution<int> ex(-20, 20);
  return std::ldexp(static_cast<double>(mant(rng)), ex(rng) - bits);
}

Q qpow(double v, int n) {
  Q r = 1;
  for (int i = 0; i < n; ++i) r *= Q(v);  // exact: see random_bits
  return r;
}

// pow_int for n = 2..8 (the inline repeated-squaring path) over intervals that straddle 0, touch
// it, are points or lie on one side, with ends chosen so that the exact range is known in quad.
TEST(Rounding, IntegerPowersEncloseTheExactRange) {
  std::mt19937_64 rng(3);
  RoundingScope scope;
  // Binary powering does at most 6 roundings for n <= 8, each within 1 ulp: the bounds are
  // tight to 8 relative ulps (2^-52 each) of the exact extremes.
  const Q slack = Q(8) * Q(DBL_EPSILON);
  for (int n = 2; n <= 8; ++n) {
    const int bits = std::min(53, 112 / n);
    int strict = 0;
    for (int i = 0; i < 30000; ++i) {
      double a = random_bits(rng, bits), b = random_bits(rng, bits);
      switch (i % 6) {
        case 0:  // straddles 0
          a = -a;
          break;
        case 1:  // touches 0 from above
          a = 0.0;
          break;
        case 2:  // touches 0 from below
          a = -a;
          b = 0.0;
          break;
        case 3:  // a point
          b = (i % 12 == 3) ? -a : a;
          a = b;
          break;
        case 4:  // negative
          a = -a;
          b = -b;
          break;
        default:  // positive
          break;
      }
      if (a > b) std::swap(a, b);
      const Interval p = pow_int(Interval(a, b), n);
      const Q pa = qpow(a, n), pb = qpow(b, n);
      Q lo = std::min(pa, pb), hi = std::max(pa, pb);
      if (n % 2 == 0 && a <= 0 && 0 <= b) lo = 0;
      ASSERT_TRUE(Q(p.lo()) <= lo && hi <= Q(p.hi())) << "[" << a << ", " << b << "]^" << n;
      // Tight: an even power of an interval containing 0 starts exactly at 0, and no bound is
      // further than the rounding error from the exact extreme.
      if (n % 2 == 0 && a <= 0 && 0 <= b) {
        ASSERT_EQ(p.lo(), 0.0) << "[" << a << ", " << b << "]";
      }
      const Q mag = std::max(lo < 0 ? -lo : lo, hi < 0 ? -hi : hi);
      ASSERT_LE(lo - Q(p.lo()), slack * mag) << "[" << a << ", " << b << "]^" << n;
      ASSERT_LE(Q(p.hi()) - hi, slack * mag) << "[" << a << ", " << b << "]^" << n;
      strict += Q(p.hi()) > hi;
    }
    // Where bits * n > 53 most exact powers are not doubles: the upper bound must then be strictly
    // above, which it would not be if the compiler had rounded the products to nearest.
    if (bits * n > 60) {
      EXPECT_GT(strict, 10000) << "n = " << n;
    }
  }
}

// Products with a constant (Tape's `scale`) and divisions by one (the inline path of divide).
TEST(Rounding, ScalingAndDivisionByAConstantEncloseTheExactRange) {
  std::mt19937_64 rng(4);
  RoundingScope scope;
  for (int i = 0; i < 200000; ++i) {
    double a = random_double(rng), b = random_double(rng);
    if (a > b) std::swap(a, b);
    const double c = random_double(rng);
    const Interval x(a, b);
    const Interval s = scale(x, c);
    const Interval m = x * Interval(c);
    const Q qa = Q(a) * Q(c), qb = Q(b) * Q(c);
    ASSERT_TRUE(Q(s.lo()) <= std::min(qa, qb) && std::max(qa, qb) <= Q(s.hi())) << a << " " << c;
    ASSERT_EQ(s, m) << "scale and * differ on [" << a << ", " << b << "] * " << c;
    const Interval q = x / Interval(c);
    // lo <= a/c  <=>  lo*c <= a for c > 0 (reversed for c < 0); exact in quad.
    if (c > 0) {
      ASSERT_TRUE(Q(q.lo()) * Q(c) <= Q(a) && Q(b) <= Q(q.hi()) * Q(c)) << a << " / " << c;
    } else {
      ASSERT_TRUE(Q(q.lo()) * Q(c) >= Q(b) && Q(a) >= Q(q.hi()) * Q(c)) << a << " / " << c;
    }
  }
}

TEST(Rounding, PowersOfNonRepresentableResultsAreStrict) {
  RoundingScope scope;
  const Interval x(1.1);
  const Interval p = pow_int(x, 7);
  const Q exact = Q(1.1) * Q(1.1) * Q(1.1) * Q(1.1) * Q(1.1) * Q(1.1) * Q(1.1);  // within 1e-33
  EXPECT_LT(p.lo(), p.hi());
  EXPECT_TRUE(Q(p.lo()) <= exact && exact <= Q(p.hi()));
}

}  // namespace
}  // namespace iaa
