// RayPolynomial and the Bernstein forms (expr/ray_poly.h), as properties: for random polynomial
// expressions, random rays (point directions and direction boxes) and random chains of halvings,
// the hull of a piece's Bernstein coefficients holds f at sampled points of the piece, f computed
// exactly enough with MPFR (4096 bits: the sums and products of doubles here are exact, the
// quotients by constants off by 2^-4000 relative). The samples include the pieces' exact ends.
#include "expr/ray_poly.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/interval.h"
#include "expr/tape.h"
#include "random_expr.h"

namespace iaa {
namespace {

constexpr mpfr_prec_t kBits = 4096;

/// f at the exact point o + t d (t = t0 + s, d doubles), in MPFR.
class ExactPoly {
 public:
  explicit ExactPoly(const Tape& tape)
      : tape_(tape), slots_(static_cast<std::size_t>(tape.size())) {
    for (auto& v : slots_) mpfr_init2(v, kBits);
    mpfr_init2(t_, kBits);
  }
  ~ExactPoly() {
    for (auto& v : slots_) mpfr_clear(v);
    mpfr_clear(t_);
  }
  ExactPoly(const ExactPoly&) = delete;
  ExactPoly& operator=(const ExactPoly&) = delete;

  /// Is f(o + (t0 + s) d) >= lo and <= hi?
  bool within(const Vec3& o, const Vec3& d, double t0, double s, const Interval& range) {
    eval(o, d, t0, s);
    const mpfr_t& r = slots_[static_cast<std::size_t>(tape_.root())];
    return mpfr_cmp_d(r, range.lo()) >= 0 && mpfr_cmp_d(r, range.hi()) <= 0;
  }
  double value(const Vec3& o, const Vec3& d, double t0, double s) {
    eval(o, d, t0, s);
    return mpfr_get_d(slots_[static_cast<std::size_t>(tape_.root())], MPFR_RNDN);
  }

 private:
  void eval(const Vec3& o, const Vec3& d, double t0, double s) {
    mpfr_set_d(t_, t0, MPFR_RNDN);
    mpfr_add_d(t_, t_, s, MPFR_RNDN);
    const double oc[3] = {o.x, o.y, o.z}, dc[3] = {d.x, d.y, d.z};
    for (int v = 0; v < 3; ++v) {
      mpfr_mul_d(slots_[static_cast<std::size_t>(v)], t_, dc[v], MPFR_RNDN);
      mpfr_add_d(slots_[static_cast<std::size_t>(v)], slots_[static_cast<std::size_t>(v)], oc[v],
                 MPFR_RNDN);
    }
    const auto ins = tape_.instrs();
    const auto k = tape_.constants();
    for (int i = 3; i < tape_.first_op(); ++i) {
      mpfr_set_d(slots_[static_cast<std::size_t>(i)], k[static_cast<std::size_t>(i)], MPFR_RNDN);
    }
    for (int i = tape_.first_op(); i < tape_.size(); ++i) {
      const Instr& in = ins[static_cast<std::size_t>(i)];
      mpfr_t& o_ = slots_[static_cast<std::size_t>(i)];
      const mpfr_t& a = slots_[static_cast<std::size_t>(in.a)];
      switch (in.op) {
        case Op::kAdd:
          mpfr_add(o_, a, slots_[static_cast<std::size_t>(in.b)], MPFR_RNDN);
          break;
        case Op::kSub:
          mpfr_sub(o_, a, slots_[static_cast<std::size_t>(in.b)], MPFR_RNDN);
          break;
        case Op::kMul:
          mpfr_mul(o_, a, slots_[static_cast<std::size_t>(in.b)], MPFR_RNDN);
          break;
        case Op::kScale:
          mpfr_mul_d(o_, a, k[static_cast<std::size_t>(in.b)], MPFR_RNDN);
          break;
        case Op::kDivConst:
          mpfr_div_d(o_, a, k[static_cast<std::size_t>(in.b)], MPFR_RNDN);
          break;
        case Op::kNeg:
          mpfr_neg(o_, a, MPFR_RNDN);
          break;
        case Op::kSquare:
          mpfr_sqr(o_, a, MPFR_RNDN);
          break;
        case Op::kPowInt:
          mpfr_pow_si(o_, a, in.power, MPFR_RNDN);
          break;
        default:
          FAIL() << "not a polynomial operation";
      }
    }
  }

  const Tape& tape_;
  std::vector<mpfr_t> slots_;
  mpfr_t t_;
};

/// A random polynomial expression in x, y, z: sums, differences, products, integer powers,
/// squares, negations, products and quotients by constants.
void random_poly(std::mt19937& rng, int depth, std::ostream& os) {
  std::uniform_int_distribution<int> pick(0, depth <= 0 ? 3 : 10);
  std::uniform_real_distribution<double> c(-2.0, 2.0);
  const auto binary = [&](const char* op) {
    os << "(";
    random_poly(rng, depth - 1, os);
    os << op;
    random_poly(rng, depth - 1, os);
    os << ")";
  };
  switch (pick(rng)) {
    case 0:
      os << "x";
      break;
    case 1:
      os << "y";
      break;
    case 2:
      os << "z";
      break;
    case 3:
      os << "(" << c(rng) << ")";
      break;
    case 4:
    case 5:
      binary(" + ");
      break;
    case 6:
      binary(" - ");
      break;
    case 7:
      binary(" * ");
      break;
    case 8:
      os << "(";
      random_poly(rng, depth - 1, os);
      os << ")^" << std::uniform_int_distribution<int>(0, 4)(rng);
      break;
    case 9:
      os << "square(";
      random_poly(rng, depth - 1, os);
      os << ")";
      break;
    default:
      os << "(";
      random_poly(rng, depth - 1, os);
      os << " / " << (c(rng) > 0 ? 1.5 : -3.0) << ")";
      break;
  }
}

std::string random_poly(std::mt19937& rng, int depth) {
  std::ostringstream os;
  os.precision(17);
  random_poly(rng, depth, os);
  return os.str();
}

/// A double in [lo, hi], the ends often.
double sample_in(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = u(rng);
  if (r < 0.15) return lo;
  if (r < 0.3) return hi;
  return std::clamp(lo + (hi - lo) * u(rng), lo, hi);
}

TEST(RayPolynomial, KnowsWhichTapesArePolynomials) {
  const auto degree = [](const char* text) {
    const Tape t = Tape::parse(text);
    const RayPolynomial rp(t);
    return rp.usable() ? rp.degree() : -1;
  };
  EXPECT_EQ(degree("x^4 + y^4 + z^4 - x^2 - y^2 - z^2 + 0.5"), 4);
  EXPECT_EQ(degree("0.5*x^5 + 0.5*x^4 - y^2 - z^2"), 5);
  EXPECT_EQ(degree("(x*y - z) / 3"), 2);
  EXPECT_EQ(degree("2"), 0);
  EXPECT_EQ(degree("(x^2 + y^2)^6"), 12);
  EXPECT_EQ(degree("(x^2 + y^2)^7"), -1);  // above kMaxDegree
  EXPECT_EQ(degree("x^(-2) + y"), -1);
  EXPECT_EQ(degree("x / y"), -1);
  EXPECT_EQ(degree("sqrt(x^2 + 1)"), -1);
  EXPECT_EQ(degree("min(x, y)"), -1);
  EXPECT_EQ(degree("sin(x) + y"), -1);
}

TEST(RayPolynomial, BernsteinFormOfAKnownPolynomial) {
  RoundingScope scope;
  // (s - 1)^2 = 1 - 2 s + s^2 over [0, 2]: Bernstein coefficients 1, -1, 1.
  const Interval c[3] = {Interval(1.0), Interval(-2.0), Interval(1.0)};
  Interval b[3];
  bernstein_from_power(c, 2, 2.0, b);
  EXPECT_EQ(b[0], Interval(1.0));
  EXPECT_EQ(b[1], Interval(-1.0));
  EXPECT_EQ(b[2], Interval(1.0));
  // Halves: over [0, 1] the coefficients 1, 0, 0; over [1, 2] 0, 0, 1.
  Interval l[3], r[3];
  bernstein_halves(b, 2, l, r);
  EXPECT_EQ(l[0], Interval(1.0));
  EXPECT_EQ(l[1], Interval(0.0));
  EXPECT_EQ(l[2], Interval(0.0));
  EXPECT_EQ(r[0], Interval(0.0));
  EXPECT_EQ(r[1], Interval(0.0));
  EXPECT_EQ(r[2], Interval(1.0));
  EXPECT_EQ(bernstein_hull(b, 2), Interval(-1.0, 1.0));
}

// The property: along random rays, every piece of a random chain of halvings holds f at its
// sampled points, for point directions and for points of direction boxes.
TEST(RayPolynomial, BernsteinHullsHoldTheExactValuesAlongRandomRays) {
  std::mt19937 rng(20261204);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int trials = 300 * testing::property_scale();
  int checked = 0, tight = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const std::string text = random_poly(rng, 4);
    const Tape tape = Tape::parse(text);
    RayPolynomial rp(tape);
    if (!rp.usable()) continue;
    ExactPoly exact(tape);
    const int n = rp.degree();
    const Vec3 o{2 * u(rng), 2 * u(rng), 3 + u(rng)};
    const Vec3 d{0.3 * u(rng), 0.3 * u(rng), -1.0};
    // A point direction or a direction box up to 1e-3 wide.
    const double w = trial % 2 ? 0.0 : 1e-3 * (1 + u(rng)) / 2;
    const IBox dir(Interval(d.x - w, d.x + w), Interval(d.y - w, d.y + w),
                   Interval(d.z - w, d.z + w));
    const double t0 = 1.0 + u(rng), len = 2.0 + u(rng);
    RoundingScope scope;
    Interval c[RayPolynomial::kMaxDegree + 1], b[RayPolynomial::kMaxDegree + 1];
    rp.restrict(o, dir, t0, c);
    bernstein_from_power(c, n, len, b);
    double sa = 0, sb = len;
    for (int level = 0; level < 14; ++level) {
      const Interval hull = bernstein_hull(b, n);
      for (int k = 0; k < 6; ++k) {
        const double s = sample_in(rng, sa, sb);
        const Vec3 dd{sample_in(rng, dir.x.lo(), dir.x.hi()),
                      sample_in(rng, dir.y.lo(), dir.y.hi()),
                      sample_in(rng, dir.z.lo(), dir.z.hi())};
        ASSERT_TRUE(exact.within(o, dd, t0, s, hull))
            << "f = " << text << "\nlevel " << level << " piece [" << sa << ", " << sb
            << "] s = " << s << " value " << exact.value(o, dd, t0, s) << " not in [" << hull.lo()
            << ", " << hull.hi() << "]";
        ++checked;
      }
      if (hull.width() < 1e-6 * (1 + hull.mag())) ++tight;
      // Halve: the exact midpoint is (sa + sb) / 2; keep a half whose ends are both exact.
      const double sum = sa + sb, m = 0.5 * sum;
      const bool exact = sum - sa == sb && sum - sb == sa && 2 * m == sum;
      if (!(m > sa && m < sb) || !exact) break;  // midpoint not a double: stop here
      Interval l[RayPolynomial::kMaxDegree + 1], r[RayPolynomial::kMaxDegree + 1];
      bernstein_halves(b, n, l, r);
      if (rng() % 2) {
        sb = m;
        std::copy(l, l + n + 1, b);
      } else {
        sa = m;
        std::copy(r, r + n + 1, b);
      }
    }
  }
  EXPECT_GT(checked, 5000);
  EXPECT_GT(tight, 0);  // the hulls do narrow with the pieces
}

}  // namespace
}  // namespace iaa
