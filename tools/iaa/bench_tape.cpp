// `iaa bench tape`: nanoseconds per tape operation for each evaluator, on the chubs and Barth
// sextic expressions, next to the same expressions hand-written in plain double arithmetic and
// compiled natively, all measured in the same run. Medians of several runs.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <random>

#include "app/files.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "iaa/bench.h"

namespace iaa::cli {
namespace {

struct Surface {
  const char* name;
  const char* expr;  // as in shared/surfaces.json
  double (*native)(double, double, double);
  double half;  // the bounding box is [-half, half]^3
};

double chubs(double x, double y, double z) {
  return x * x * x * x + y * y * y * y + z * z * z * z - x * x - y * y - z * z + 0.5;
}

double barth(double x, double y, double z) {
  const double p = 2.618033988749895;
  const double r = x * x + y * y + z * z - 1;
  return 4 * (p * x * x - y * y) * (p * y * y - z * z) * (p * z * z - x * x) -
         4.23606797749979 * r * r;
}

const Surface kSurfaces[] = {
    {"chubs", "x^4 + y^4 + z^4 - x^2 - y^2 - z^2 + 0.5", chubs, 1.1},
    {"barth_sextic",
     "4*(2.618033988749895*x^2 - y^2)*(2.618033988749895*y^2 - z^2)*(2.618033988749895*z^2 - "
     "x^2) - 4.23606797749979*(x^2 + y^2 + z^2 - 1)^2",
     barth, 1.8},
};

volatile double g_sink;  // keeps results alive

// The goal for interval evaluation: at most this many times the cost of point evaluation per
// tape operation (the issue "Interval evaluation should cost within 4x of point evaluation").
constexpr double kIntervalOverPointTarget = 4.0;

// Median wall time in seconds of `runs` calls of f.
double median_seconds(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto a = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

struct Options {
  int points = 20000;
  int runs = 7;
  std::string json;
};

void run(const Options& o) {
  nlohmann::json out = nlohmann::json::array();
  std::printf("%-13s %4s  %10s %10s %10s %10s %10s  %9s  %s\n", "surface", "ops", "native", "point",
              "interval", "pt+grad", "iv+grad", "iv/point", "target");
  std::printf("%-13s %4s  %10s %10s %10s %10s %10s  %9s  <= %gx\n", "", "", "ns/op", "ns/op",
              "ns/op", "ns/op", "ns/op", "ratio", kIntervalOverPointTarget);
  for (const Surface& s : kSurfaces) {
    const Tape tape = Tape::parse(s.expr);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-s.half, s.half);
    std::vector<Vec3> pts(static_cast<std::size_t>(o.points));
    for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
    const double ops = static_cast<double>(tape.op_count()) * o.points;

    PointEval pe(tape);
    IntervalEval ie(tape);
    PointGradEval pg(tape);
    IntervalGradEval ig(tape);
    const double t_native = median_seconds(o.runs, [&] {
      double acc = 0;
      for (const Vec3& p : pts) acc += s.native(p.x, p.y, p.z);
      g_sink = acc;
    });
    const double t_point = median_seconds(o.runs, [&] {
      double acc = 0;
      for (const Vec3& p : pts) acc += pe.eval(p);
      g_sink = acc;
    });
    const double t_interval = median_seconds(o.runs, [&] {
      RoundingScope scope;  // once per batch, as the renderer does per tile
      double acc = 0;
      for (const Vec3& p : pts) {
        const IBox b(Interval(p.x, p.x + 1e-2), Interval(p.y, p.y + 1e-2),
                     Interval(p.z, p.z + 1e-2));
        acc += ie.eval(b).hi();
      }
      g_sink = acc;
    });
    const double t_pgrad = median_seconds(o.runs, [&] {
      double acc = 0;
      for (const Vec3& p : pts) acc += pg.eval(p).g.x;
      g_sink = acc;
    });
    const double t_igrad = median_seconds(o.runs, [&] {
      RoundingScope scope;
      double acc = 0;
      for (const Vec3& p : pts) {
        const IBox b(Interval(p.x, p.x + 1e-2), Interval(p.y, p.y + 1e-2),
                     Interval(p.z, p.z + 1e-2));
        acc += ig.eval(b).g[0].hi();
      }
      g_sink = acc;
    });
    const auto ns = [&](double t) { return t * 1e9 / ops; };
    const double ratio = t_interval / t_point;
    const bool within = ratio <= kIntervalOverPointTarget;
    std::printf("%-13s %4d  %10.2f %10.2f %10.2f %10.2f %10.2f  %9.2f  %s\n", s.name,
                tape.op_count(), ns(t_native), ns(t_point), ns(t_interval), ns(t_pgrad),
                ns(t_igrad), ratio, within ? "within" : "MISSED");
    out.push_back({{"surface", s.name},
                   {"tape_ops", tape.op_count()},
                   {"evaluations", o.points},
                   {"runs", o.runs},
                   {"ns_per_op",
                    {{"native_double", ns(t_native)},
                     {"point", ns(t_point)},
                     {"interval", ns(t_interval)},
                     {"point_grad", ns(t_pgrad)},
                     {"interval_grad", ns(t_igrad)}}},
                   {"interval_over_point", ratio},
                   {"interval_over_point_target", kIntervalOverPointTarget},
                   {"within_target", within}});
  }
  std::printf(
      "\nmedians of %d runs of %d evaluations; 'native' is the expression compiled as C++;\n"
      "target: interval within %gx of point evaluation per operation\n",
      o.runs, o.points, kIntervalOverPointTarget);
  if (!o.json.empty()) app::write_text_atomically(o.json, out.dump(2) + "\n");
}

void setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("--points", o->points, "evaluations per run")->check(CLI::Range(100, 10'000'000));
  app.add_option("--runs", o->runs, "runs per measurement (the median is reported)")
      ->check(CLI::Range(1, 101));
  app.add_option("--json", o->json, "also write the figures as JSON to this file");
  app.footer("Examples:\n  iaa bench tape\n  iaa bench tape --points 100000 --json tape.json");
  app.callback([o] { run(*o); });
}

BenchRegistrar reg{
    {"tape", "ns per tape operation of each evaluator vs native double code", setup}};

}  // namespace
}  // namespace iaa::cli
