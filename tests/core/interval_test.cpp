// Edge cases of Interval, one per documented rule in interval.h.
#include "core/interval.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <numbers>

namespace iaa {
namespace {

constexpr double kInf = Interval::kInf;

class IntervalTest : public ::testing::Test {
 protected:
  RoundingScope scope_;
  Domain dom_ = Domain::kFull;
};

TEST_F(IntervalTest, IntegerPowersAreTight) {
  EXPECT_EQ(square(Interval(-2, 1)), Interval(0, 4));
  EXPECT_EQ(pow_int(Interval(-2, 1), 2), Interval(0, 4));
  EXPECT_EQ(pow_int(Interval(-2, 1), 3), Interval(-8, 1));
  EXPECT_EQ(pow_int(Interval(-3, -2), 4), Interval(16, 81));
  EXPECT_EQ(pow_int(Interval(-3, 5), 0), Interval(1));
  // Even powers of an interval containing 0 start at 0, whatever side is longer.
  for (int n = 2; n <= 8; n += 2) {
    EXPECT_EQ(pow_int(Interval(-2, 1), n).lo(), 0.0) << n;
    EXPECT_EQ(pow_int(Interval(-1, 2), n), Interval(0, std::ldexp(1.0, n))) << n;
    EXPECT_EQ(pow_int(Interval(0, 2), n), Interval(0, std::ldexp(1.0, n))) << n;
  }
  for (int n = 3; n <= 7; n += 2) {
    EXPECT_EQ(pow_int(Interval(-2, 1), n), Interval(-std::ldexp(1.0, n), 1)) << n;
    EXPECT_EQ(pow_int(Interval(-2, -1), n), Interval(-std::ldexp(1.0, n), -1)) << n;
  }
  // Overflow gives an infinite upper bound and the largest double as lower bound (both sound);
  // underflow gives 0 below and a positive bound above.
  EXPECT_EQ(pow_int(Interval(1e200), 4), Interval(DBL_MAX, kInf));
  EXPECT_EQ(pow_int(Interval(-1e200), 3), Interval(-kInf, -DBL_MAX));
  const Interval tiny = pow_int(Interval(1e-200), 4);
  EXPECT_EQ(tiny.lo(), 0.0);
  EXPECT_GT(tiny.hi(), 0.0);
  EXPECT_EQ(pow_int(Interval(-kInf, 2), 4), Interval(0, kInf));
  EXPECT_EQ(pow_int(Interval(-kInf, -2), 5), Interval(-kInf, -32));
  EXPECT_TRUE(pow_int(Interval::empty(), 6).is_empty());
  // x*x with the same interval is not tight: the dependency problem square() avoids.
  EXPECT_EQ(Interval(-2, 3) * Interval(-2, 3), Interval(-6, 9));
}

TEST_F(IntervalTest, DivisionAcrossZero) {
  EXPECT_EQ(divide(Interval(1, 2), Interval(-1, 1), &dom_), Interval::whole());
  EXPECT_EQ(dom_, Domain::kPartial);
  dom_ = Domain::kFull;
  const Interval half = divide(Interval(1, 2), Interval(0, 4), &dom_);
  EXPECT_EQ(half.lo(), 0.25);
  EXPECT_EQ(half.hi(), kInf);
  EXPECT_EQ(dom_, Domain::kPartial);
  EXPECT_EQ(divide(Interval(-2, -1), Interval(0, 4), &dom_), Interval(-kInf, -0.25));
  EXPECT_EQ(divide(Interval(1, 2), Interval(-4, 0), &dom_), Interval(-kInf, -0.25));
  EXPECT_TRUE(divide(Interval(1, 2), Interval(0, 0), &dom_).is_empty());  // undefined everywhere
  EXPECT_EQ(divide(Interval(0, 0), Interval(-1, 1), &dom_), Interval(0));
  dom_ = Domain::kFull;
  EXPECT_EQ(divide(Interval(1, 2), Interval(2, 4), &dom_), Interval(0.25, 1));
  EXPECT_EQ(dom_, Domain::kFull);
}

TEST_F(IntervalTest, ScalingByAConstant) {
  EXPECT_EQ(scale(Interval(-1, 2), 3), Interval(-3, 6));
  EXPECT_EQ(scale(Interval(-1, 2), -3), Interval(-6, 3));
  EXPECT_EQ(scale(Interval(-kInf, 2), -0.5), Interval(-1, kInf));
  EXPECT_TRUE(scale(Interval::empty(), 2).is_empty());
  EXPECT_TRUE(scale(Interval::empty(), -2).is_empty());
  EXPECT_EQ(scale(Interval(1e300), 1e300), Interval(DBL_MAX, kInf));
}

TEST_F(IntervalTest, DivisionByIntervalsThatExcludeZero) {
  EXPECT_EQ(Interval(-1, 2) / Interval(4), Interval(-0.25, 0.5));
  EXPECT_EQ(Interval(-1, 2) / Interval(-4), Interval(-0.5, 0.25));
  EXPECT_EQ(Interval(1, 2) / Interval(-4, -1), Interval(-2, -0.25));
  EXPECT_EQ(Interval(-2, -1) / Interval(1, 4), Interval(-2, -0.25));
  EXPECT_EQ(Interval(1, kInf) / Interval(2, kInf), Interval(0, kInf));
  EXPECT_TRUE((Interval::empty() / Interval(2)).is_empty());
  const Interval third = Interval(1) / Interval(3);
  EXPECT_LT(third.lo(), third.hi());
}

TEST_F(IntervalTest, DivisionByAConstantIsDivisionByItsPoint) {
  // div_const (the tape's `divc`) gives the very bounds of the general division by [c, c].
  const double cs[] = {3, -3, 0.03, -1e-300, 1e300, DBL_MIN};
  const Interval as[] = {Interval(-1, 2),     Interval(1),
                         Interval(-kInf, 2),  Interval(-2, kInf),
                         Interval::whole(),   Interval(1e-310, 1e308),
                         Interval(-0.0, 0.0), Interval(-DBL_MAX, -1e-300)};
  for (double c : cs) {
    for (const Interval& a : as) {
      const Interval q = div_const(a, c), r = a / Interval(c);
      EXPECT_EQ(q.lo(), r.lo()) << a.lo() << " " << a.hi() << " / " << c;
      EXPECT_EQ(q.hi(), r.hi()) << a.lo() << " " << a.hi() << " / " << c;
    }
    EXPECT_TRUE(div_const(Interval::empty(), c).is_empty());
  }
  const Interval third = div_const(Interval(1), 3);
  EXPECT_LT(third.lo(), third.hi());
}

TEST_F(IntervalTest, DomainErrorsClampAndReport) {
  EXPECT_EQ(sqrt(Interval(-1, 4), &dom_), Interval(0, 2));
  EXPECT_EQ(dom_, Domain::kPartial);
  EXPECT_TRUE(sqrt(Interval(-4, -1), &dom_).is_empty());
  dom_ = Domain::kFull;
  const Interval l = log(Interval(-1, 1), &dom_);
  EXPECT_EQ(l.lo(), -kInf);
  EXPECT_GE(l.hi(), 0.0);
  EXPECT_EQ(dom_, Domain::kPartial);
  EXPECT_TRUE(log(Interval(-2, 0), &dom_).is_empty());
  dom_ = Domain::kFull;
  EXPECT_TRUE(sqrt(Interval(0, 4), &dom_).contains(2.0));
  EXPECT_EQ(dom_, Domain::kFull);
}

TEST_F(IntervalTest, EmptyPropagates) {
  const Interval e = Interval::empty();
  EXPECT_TRUE(e.is_empty());
  EXPECT_TRUE((e + Interval(1)).is_empty());
  EXPECT_TRUE((Interval(1) * e).is_empty());
  EXPECT_TRUE(exp(e).is_empty());
  EXPECT_TRUE(min(e, Interval(0)).is_empty());
  EXPECT_FALSE(e.contains_zero());
  EXPECT_EQ(hull(e, Interval(1, 2)), Interval(1, 2));
}

TEST_F(IntervalTest, NaNNeverEscapes) {
  // inf - inf and NaN inputs become "anything", the sound answer.
  const Interval big(1e308, kInf);
  const Interval d = big - big;
  EXPECT_FALSE(std::isnan(d.lo()));
  EXPECT_FALSE(std::isnan(d.hi()));
  EXPECT_EQ(d, Interval::whole());
  EXPECT_EQ(Interval(std::nan("")), Interval::whole());
  EXPECT_EQ(Interval(0) * Interval::whole(), Interval(0));
  const Interval e = exp(Interval(800, 900));  // overflows: lower bound stays finite
  EXPECT_LE(e.lo(), DBL_MAX);
  EXPECT_EQ(e.hi(), kInf);
}

TEST_F(IntervalTest, TranscendentalsContainTheTrueValues) {
  EXPECT_TRUE(exp(Interval(1)).contains(std::numbers::e));
  EXPECT_LT(exp(Interval(1)).lo(), exp(Interval(1)).hi());
  EXPECT_TRUE(log(Interval(std::numbers::e), &dom_).contains(1.0));
  EXPECT_TRUE(atan(Interval(1)).contains(std::numbers::pi / 4));
  EXPECT_TRUE(sin(Interval(0)).contains(0.0));
  EXPECT_GE(atan(Interval::whole()).hi(), std::numbers::pi / 2);
}

TEST_F(IntervalTest, SinAndCosFindTheirExtrema) {
  const Interval s = sin(Interval(1, 2));  // contains pi/2
  EXPECT_EQ(s.hi(), 1.0);
  EXPECT_LE(s.lo(), std::sin(1.0));
  const Interval c = cos(Interval(3, 3.5));  // contains pi
  EXPECT_EQ(c.lo(), -1.0);
  const Interval small = sin(Interval(0.1, 0.2));  // monotone piece
  EXPECT_LE(small.lo(), std::sin(0.1));
  EXPECT_GE(small.hi(), std::sin(0.2));
  EXPECT_LT(small.hi(), 0.21);
  EXPECT_EQ(sin(Interval(0, 7)), Interval(-1, 1));
  EXPECT_EQ(cos(Interval(-1e300, 1e300)), Interval(-1, 1));
}

TEST_F(IntervalTest, TanPoles) {
  EXPECT_EQ(tan(Interval(1, 2), &dom_), Interval::whole());
  EXPECT_EQ(dom_, Domain::kPartial);
  dom_ = Domain::kFull;
  const Interval t = tan(Interval(-0.5, 0.5), &dom_);
  EXPECT_EQ(dom_, Domain::kFull);
  EXPECT_TRUE(t.contains(std::tan(0.5)));
}

TEST_F(IntervalTest, RealPower) {
  const Interval p = pow_real(Interval(1, 4), Interval(0.5), &dom_);
  EXPECT_TRUE(p.contains(1.0));
  EXPECT_TRUE(p.contains(2.0));
  EXPECT_EQ(dom_, Domain::kFull);
  const Interval q = pow_real(Interval(-1, 4), Interval(2.5), &dom_);
  EXPECT_EQ(dom_, Domain::kPartial);
  EXPECT_EQ(q.lo(), 0.0);
  EXPECT_GE(q.hi(), 32.0);
  EXPECT_TRUE(pow_real(Interval(-2, -1), Interval(0.5), &dom_).is_empty());
  // 0.01^-400 = 1e800 is a real number above DBL_MAX: the lower bound stays finite (it was +inf,
  // found by the MPFR check: [inf, inf] holds no real number).
  const Interval big = pow_real(Interval(1e-3, 1e-2), Interval(-400), &dom_);
  EXPECT_EQ(big.lo(), DBL_MAX);
  EXPECT_EQ(big.hi(), kInf);
}

TEST_F(IntervalTest, AbsMinMax) {
  EXPECT_EQ(abs(Interval(-3, 2)), Interval(0, 3));
  EXPECT_EQ(abs(Interval(-3, -2)), Interval(2, 3));
  EXPECT_EQ(min(Interval(0, 5), Interval(1, 2)), Interval(0, 2));
  EXPECT_EQ(max(Interval(0, 5), Interval(1, 2)), Interval(1, 5));
}

TEST_F(IntervalTest, WideningIsOutward) {
  EXPECT_LT(widen_down(1.0), 1.0);
  EXPECT_GT(widen_up(1.0), 1.0);
  EXPECT_LT(widen_down(0.0), 0.0);
  EXPECT_EQ(widen_up(kInf), kInf);
  EXPECT_LT(widen_down(-1e-310), -1e-310);  // subnormal
  // The last step is one ulp further out, as std::nextafter takes it: zeros of either sign step
  // past the smallest subnormal, the largest finite doubles step to infinity.
  EXPECT_LT(widen_down(-0.0), 0.0);
  EXPECT_GT(widen_up(-0.0), 0.0);
  EXPECT_GT(widen_up(-1e-310), -1e-310);
  EXPECT_EQ(widen_down(-DBL_MAX), -kInf);
  EXPECT_EQ(widen_up(DBL_MAX), kInf);
  EXPECT_EQ(widen_down(-kInf), -kInf);
  for (double v : {1.0, -1.0, 3e-300, -7.5e200, 4.9e-324}) {
    EXPECT_LT(widen_down(v, 1), std::nextafter(v, -kInf)) << v;
    EXPECT_GT(widen_up(v, 1), std::nextafter(v, kInf)) << v;
    EXPECT_EQ(widen_down(v, 0), std::nextafter(v, -kInf)) << v;
    EXPECT_EQ(widen_up(v, 0), std::nextafter(v, kInf)) << v;
  }
}

// The transcendental functions call libm in round-to-nearest (switched around the calls) and
// must hand the thread back rounding upward.
TEST_F(IntervalTest, TranscendentalsLeaveTheModeUpward) {
  Interval s, c;
  (void)sin(Interval(0.5, 1.0));
  EXPECT_TRUE(rounding_is_upward());
  (void)cos(Interval(0.5, 1.0));
  EXPECT_TRUE(rounding_is_upward());
  sincos(Interval(0.5, 1.0), &s, &c);
  EXPECT_TRUE(rounding_is_upward());
  (void)exp(Interval(0.5, 1.0));
  EXPECT_TRUE(rounding_is_upward());
  (void)log(Interval(0.5, 1.0), &dom_);
  EXPECT_TRUE(rounding_is_upward());
  (void)pow_real(Interval(0.5, 1.0), Interval(0.3, 2.5), &dom_);
  EXPECT_TRUE(rounding_is_upward());
  EXPECT_EQ(dom_, Domain::kFull);
}

TEST_F(IntervalTest, MidIsInside) {
  EXPECT_EQ(Interval(1, 3).mid(), 2.0);
  EXPECT_TRUE(Interval(-kInf, 5).contains(Interval(-kInf, 5).mid()));
  EXPECT_TRUE(Interval(5, kInf).contains(Interval(5, kInf).mid()));
  EXPECT_EQ(Interval::whole().mid(), 0.0);
}

}  // namespace
}  // namespace iaa

namespace iaa {
namespace {

// operator* computes both bounds in one vector (interval.h): bit for bit, signs of zero bounds
// included, what the scalar formula gives (the extreme endpoint products, std::max in the same
// order), on endpoint-heavy factors: zeros of both signs, subnormals, huge and tiny bounds.
TEST_F(IntervalTest, ProductsAreTheScalarFormulasBitForBit) {
  const double ends[] = {0.0,   -0.0,   1.0,    -1.0,    0.5,     -3.0,     1e-310, -1e-310,
                         1e300, -1e300, 2.5e-8, 7.0 / 3, DBL_MAX, -DBL_MAX, 1e-5,   -4e7};
  const auto scalar = [](const Interval& a, const Interval& b) {
    const double al = a.lo(), ah = a.hi(), bl = b.lo(), bh = b.hi();
    const double hi = std::max(std::max(al * bl, al * bh), std::max(ah * bl, ah * bh));
    const double lo = -std::max(std::max((-al) * bl, (-al) * bh), std::max((-ah) * bl, (-ah) * bh));
    return Interval::raw(lo, hi);
  };
  int n = 0;
  for (double a0 : ends) {
    for (double a1 : ends) {
      if (!(a0 <= a1)) continue;
      for (double b0 : ends) {
        for (double b1 : ends) {
          if (!(b0 <= b1)) continue;
          const Interval a = Interval::raw(a0, a1), b = Interval::raw(b0, b1);
          const Interval p = a * b, q = scalar(a, b);
          ASSERT_EQ(std::memcmp(&p, &q, sizeof p), 0)
              << "[" << a0 << ", " << a1 << "] * [" << b0 << ", " << b1 << "]: [" << p.lo() << ", "
              << p.hi() << "] against [" << q.lo() << ", " << q.hi() << "]";
          ++n;
        }
      }
    }
  }
  EXPECT_GT(n, 10000);
}

}  // namespace
}  // namespace iaa
