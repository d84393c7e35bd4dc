// Random expressions, boxes and endpoint-heavy sample points for the property tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/vec.h"
#include "expr/tape.h"

namespace iaa::testing {

/// Scales the number of trials of the property suites: IAA_PROPERTY_SCALE (default 1;
/// tools/soak.sh runs 30; the seeds change with it too).
inline int property_scale() {
  const char* s = std::getenv("IAA_PROPERTY_SCALE");
  return s ? std::max(1, std::atoi(s)) : 1;
}

/// Generates random expression text over every operation of the language.
class RandomExpr {
 public:
  explicit RandomExpr(std::uint64_t seed) : rng_(seed) {}

  /// An expression of at most `depth` levels. With `smooth`, only operations that are
  /// differentiable everywhere on their domain (no abs/min/max) are used.
  std::string make(int depth, bool smooth = false) {
    if (depth <= 0 || pick(4) == 0) return leaf();
    const int n = smooth ? 12 : 15;
    const std::string a = make(depth - 1, smooth);
    switch (pick(n)) {
      case 0:
        return "(" + a + " + " + make(depth - 1, smooth) + ")";
      case 1:
        return "(" + a + " - " + make(depth - 1, smooth) + ")";
      case 2:
        return "(" + a + " * " + make(depth - 1, smooth) + ")";
      case 3:
        return "(" + a + " / " + make(depth - 1, smooth) + ")";
      case 4:
        return "(-" + a + ")";
      case 5:
        return "(" + a + ")^" + std::to_string(pick(8));
      case 6:
        return "sqrt(" + a + ")";
      case 7:
        return "exp(" + a + ")";
      case 8:
        return "log(" + a + ")";
      case 9:
        // Both of one argument are compiled to one sincos pair (tape.cpp).
        switch (pick(3)) {
          case 0:
            return "sin(" + a + ")";
          case 1:
            return "cos(" + a + ")";
          default:
            return "(sin(" + a + ") * cos(" + a + "))";
        }
      case 10:
        return (pick(2) ? "tan(" : "atan(") + a + ")";
      case 11:
        return pick(2) ? "pow(" + a + ", " + make(depth - 1, smooth) + ")"
                       : "pow(" + a + ", " + std::to_string(0.5 + pick(5) * 0.7) + ")";
      case 12:
        return "abs(" + a + ")";
      case 13:
        return "min(" + a + ", " + make(depth - 1, smooth) + ")";
      default:
        return "max(" + a + ", " + make(depth - 1, smooth) + ", " + leaf() + ")";
    }
  }

  /// A random box: centres in [-3, 3], widths from 0 to 6, some straddling or touching 0.
  IBox box() {
    IBox b;
    static const double kWidths[] = {0.0, 1e-12, 1e-6, 1e-3, 0.1, 0.5, 1.0, 2.0, 6.0};
    for (int i = 0; i < 3; ++i) {
      const double w = kWidths[pick(9)];
      double c = uniform(-3, 3);
      if (pick(5) == 0) c = 0.0;    // centred on 0
      if (pick(6) == 0) c = w / 2;  // touching 0
      b[i] = Interval(c - w / 2, c + w / 2);
    }
    return b;
  }

  /// A point of `b`, chosen endpoint-heavy: ends, just inside the ends, 0, the middle, or uniform.
  Vec3 point(const IBox& b) {
    Vec3 p;
    for (int i = 0; i < 3; ++i) {
      const double lo = b[i].lo(), hi = b[i].hi();
      double v;
      switch (pick(7)) {
        case 0:
          v = lo;
          break;
        case 1:
          v = hi;
          break;
        case 2:
          v = std::nextafter(lo, hi);
          break;
        case 3:
          v = std::nextafter(hi, lo);
          break;
        case 4:
          v = (lo <= 0 && 0 <= hi) ? 0.0 : lo;
          break;
        case 5:
          v = lo + 0.5 * (hi - lo);
          break;
        default:
          v = uniform(lo, hi);
      }
      p[i] = std::fmin(std::fmax(v, lo), hi);
    }
    return p;
  }

  /// False for the rare generated text the language rejects (an integer power above the limit).
  static bool parses(const std::string& text) {
    try {
      Tape::parse(text);
      return true;
    } catch (const ParseError&) {
      return false;
    }
  }

  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  double uniform(double a, double b) {
    return a == b ? a : std::uniform_real_distribution<double>(a, b)(rng_);
  }

 private:
  std::string leaf() {
    static const char* kConsts[] = {"0", "1", "2", "0.5", "3", "pi", "1e-3", "1000", "0.1", "7.25"};
    switch (pick(5)) {
      case 0:
        return "x";
      case 1:
        return "y";
      case 2:
        return "z";
      case 3:
        return kConsts[pick(10)];
      default:
        return std::to_string(uniform(-4, 4));
    }
  }

  std::mt19937_64 rng_;
};

/// Calls `f(box)` for each box of the hard-box suites: [a, b] x [min(b, 1), max(b, 1)] x {0} for
/// every pair a <= b of hand-picked ends (huge, poles of tan, domain edges of sqrt and log, tiny
/// and zero widths, exp's overflow).
template <class F>
void for_each_hard_box(F&& f) {
  static constexpr double kEnds[] = {-1e300,
                                     -1e9,
                                     -3.2,
                                     -1.5707963267948966,
                                     -1,
                                     -1e-300,
                                     0,
                                     1e-300,
                                     0.5,
                                     1,
                                     1.5707963267948966,
                                     3.141592653589793,
                                     709,
                                     1e9};
  for (double a : kEnds) {
    for (double b : kEnds) {
      if (a > b) continue;
      f(IBox(Interval(a, b), Interval(b > 1 ? 1.0 : b, std::fmax(b, 1.0)), Interval(0.0)));
    }
  }
}

}  // namespace iaa::testing
