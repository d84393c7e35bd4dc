// Proves that Interval bounds are outward rounded under the flags this target is really built with
// (the release flags of iaa_options: -O2/-O3 with -frounding-math). Exact checks use __float128,
// in which the sum and product of two doubles are exact.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>

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
