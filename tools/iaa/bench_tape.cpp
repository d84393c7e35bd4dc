// `iaa bench tape`: nanoseconds per tape operation for each evaluator, on the chubs and Barth
// sextic expressions (read from their scenes in data/scenes), next to the same expressions
// hand-written in plain double arithmetic and compiled natively, all measured in the same run,
// and the throughput (tape operations per second on one core). Medians of several runs; the peak
// resident memory of the measurement (bench.h, PeakMemory). The batched interval and interval +
// gradient evaluators (expr/eval_batch.h, expr/eval_batch_grad.h) evaluate the same boxes K at a
// time; their times are per operation per box.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "app/files.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_batch_point.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "expr/eval_point_grad.h"
#include "iaa/bench.h"
#include "iaa/bench_scenes.h"

namespace iaa::cli {
namespace {

/// A scene whose expression is also written below as native code.
struct Surface {
  const char* scene;  ///< the scene file's name in the scene directory, without .toml
  double (*native)(double, double, double);
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

const Surface kSurfaces[] = {{"chubs", chubs}, {"barth_sextic", barth}};

volatile double g_sink;  // keeps results alive

// The goal for interval evaluation: at most this many times the cost of point evaluation per
// tape operation (the issue "Interval evaluation should cost within 4x of point evaluation").
constexpr double kIntervalOverPointTarget = 4.0;
// Issue 16's goal for the batched interval evaluator: within 1.5x of point evaluation per tape
// operation (per box).
constexpr double kBatchOverPointTarget = 1.5;

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
  int lanes = 8;      ///< boxes per batch of the batched evaluators: 4, 8 or 16
  bool sse2 = false;  ///< the batched evaluator runs its baseline code even where AVX2 is there
  std::string scene_dir;
  std::string json;
};

/// Points drawn uniformly in the scene's bounding box, the same for every run.
std::vector<Vec3> sample_points(const Box3& bounds, int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(bounds.lo.x, bounds.hi.x), uy(bounds.lo.y, bounds.hi.y),
      uz(bounds.lo.z, bounds.hi.z);
  std::vector<Vec3> pts(static_cast<std::size_t>(n));
  for (Vec3& p : pts) p = {ux(rng), uy(rng), uz(rng)};
  return pts;
}

/// Throws iaa::Error when the native code of `s` does not compute the scene's expression (the
/// scene file was changed, not the code below it).
void check_native(const Surface& s, const Scene& scene) {
  PointEval pe(*scene.tape);
  for (const Vec3& p : sample_points(scene.bounds, 100)) {
    const double a = s.native(p.x, p.y, p.z), b = pe.eval(p);
    if (!(std::abs(a - b) <= 1e-9 * (1 + std::abs(b)))) {
      throw Error("the native code of '" + std::string(s.scene) +
                  "' does not match the expression of its scene: " + scene.expression);
    }
  }
}

/// Reads the scenes of kSurfaces and checks their native code, before anything is measured.
std::vector<Scene> load_scenes(const Options& o) {
  const std::string dir = find_scene_dir(o.scene_dir);
  std::vector<Scene> scenes;
  for (const Surface& s : kSurfaces) {
    scenes.push_back(app::load_scene(dir + "/" + s.scene + ".toml"));
    check_native(s, scenes.back());
  }
  return scenes;
}

/// Median seconds of one batch of evaluations, per evaluator.
struct Times {
  double native = 0, point = 0, interval = 0, point_grad = 0, interval_grad = 0, batch = 0,
         batch_grad = 0, batch_point = 0;
  const char* batch_isa = "";    ///< the batched evaluators' instruction set
  std::uint64_t peak_bytes = 0;  ///< the peak resident memory of all the evaluators' runs
  bool peak_exact = true;        ///< the peak was this surface's (PeakMemory::exact)
};

/// A box of edge 1e-2 at each point, as the interval evaluators see one.
IBox box_at(const Vec3& p) {
  return IBox(Interval(p.x, p.x + 1e-2), Interval(p.y, p.y + 1e-2), Interval(p.z, p.z + 1e-2));
}

/// Times every evaluator on the same points; each sums its results into g_sink so that the
/// compiler cannot drop the work.
/// What the timed loops sum: the upper bound of an interval, or of the first partial.
double sink_of(const Interval& v) {
  return v.hi();
}
double sink_of(const IGrad& r) {
  return r.g[0].hi();
}

/// Median seconds of a batched evaluator (BatchIntervalEvalK, BatchIntervalGradEvalK) over the
/// boxes of `pts`, K at a time; Out is its result (Interval, IGrad).
template <class Batch, class Out>
double measure_batch(const Tape& tape, const std::vector<Vec3>& pts, int runs, bool sse2,
                     const char** isa) {
  constexpr int K = Batch::kLanes;
  Batch be(tape);
  be.use_baseline(sse2);
  *isa = be.isa();
  std::vector<IBox> boxes;
  for (const Vec3& p : pts) boxes.push_back(box_at(p));
  const int n = static_cast<int>(boxes.size());
  return median_seconds(runs, [&] {
    RoundingScope scope;
    double acc = 0;
    Out out[K];
    for (int i = 0; i < n; i += K) {
      const int m = std::min(K, n - i);
      be.eval(boxes.data() + i, m, out);
      for (int j = 0; j < m; ++j) acc += sink_of(out[j]);
    }
    g_sink = acc;
  });
}

/// Median seconds of the batched point evaluator over `pts`, K at a time.
template <int K>
double measure_point_batch(const Tape& tape, const std::vector<Vec3>& pts, int runs, bool sse2) {
  BatchPointEvalK<K> be(tape);
  be.use_baseline(sse2);
  const int n = static_cast<int>(pts.size());
  return median_seconds(runs, [&] {
    double acc = 0;
    double out[K];
    for (int i = 0; i < n; i += K) {
      const int m = std::min(K, n - i);
      be.eval(pts.data() + i, m, out);
      for (int j = 0; j < m; ++j) acc += out[j];
    }
    g_sink = acc;
  });
}

/// measure_batch for the lane count of --lanes.
template <template <int> class Batch, class Out>
double measure_lanes(const Tape& tape, const std::vector<Vec3>& pts, int runs, const Options& o,
                     const char** isa) {
  return o.lanes == 4    ? measure_batch<Batch<4>, Out>(tape, pts, runs, o.sse2, isa)
         : o.lanes == 16 ? measure_batch<Batch<16>, Out>(tape, pts, runs, o.sse2, isa)
                         : measure_batch<Batch<8>, Out>(tape, pts, runs, o.sse2, isa);
}

Times measure(const Surface& s, const Tape& tape, const std::vector<Vec3>& pts, int runs,
              const Options& o) {
  const PeakMemory memory;
  PointEval pe(tape);
  IntervalEval ie(tape);
  PointGradEval pg(tape);
  IntervalGradEval ig(tape);
  Times t;
  t.native = median_seconds(runs, [&] {
    double acc = 0;
    for (const Vec3& p : pts) acc += s.native(p.x, p.y, p.z);
    g_sink = acc;
  });
  t.point = median_seconds(runs, [&] {
    double acc = 0;
    for (const Vec3& p : pts) acc += pe.eval(p);
    g_sink = acc;
  });
  t.interval = median_seconds(runs, [&] {
    RoundingScope scope;  // once per batch, as the renderer does per tile
    double acc = 0;
    for (const Vec3& p : pts) acc += ie.eval(box_at(p)).hi();
    g_sink = acc;
  });
  t.point_grad = median_seconds(runs, [&] {
    double acc = 0;
    for (const Vec3& p : pts) acc += pg.eval(p).g.x;
    g_sink = acc;
  });
  t.interval_grad = median_seconds(runs, [&] {
    RoundingScope scope;
    double acc = 0;
    for (const Vec3& p : pts) acc += ig.eval(box_at(p)).g[0].hi();
    g_sink = acc;
  });
  t.batch = measure_lanes<BatchIntervalEvalK, Interval>(tape, pts, runs, o, &t.batch_isa);
  t.batch_grad = measure_lanes<BatchIntervalGradEvalK, IGrad>(tape, pts, runs, o, &t.batch_isa);
  t.batch_point = o.lanes == 4    ? measure_point_batch<4>(tape, pts, runs, o.sse2)
                  : o.lanes == 16 ? measure_point_batch<16>(tape, pts, runs, o.sse2)
                                  : measure_point_batch<8>(tape, pts, runs, o.sse2);
  t.peak_bytes = memory.peak_bytes();
  t.peak_exact = memory.exact();
  return t;
}

void print_header(int lanes) {
  char target[16], btarget[16], batch[16], bgrad[16], bpoint[16];
  std::snprintf(target, sizeof target, "<= %gx", kIntervalOverPointTarget);
  std::snprintf(btarget, sizeof btarget, "<= %gx", kBatchOverPointTarget);
  std::snprintf(batch, sizeof batch, "batch %d", lanes);
  std::snprintf(bgrad, sizeof bgrad, "bgrad %d", lanes);
  std::snprintf(bpoint, sizeof bpoint, "bpoint %d", lanes);
  std::printf(
      "%-13s %4s  %10s %10s %10s %10s %10s  %9s  %-7s %9s %9s  %-7s %9s %9s %9s %9s %9s %9s\n",
      "surface", "ops", "native", "point", "interval", "pt+grad", "iv+grad", "iv/point", "target",
      batch, "bt/point", "target", bgrad, "bg/ivgrad", "bg/point", bpoint, "bp/point", "peak MiB");
  std::printf("%-13s %4s  %10s %10s %10s %10s %10s  %9s  %-7s %9s %9s  %-7s %9s %9s %9s %9s %9s\n",
              "", "", "ns/op", "ns/op", "ns/op", "ns/op", "ns/op", "ratio", target, "ns/op",
              "ratio", btarget, "ns/op", "ratio", "ratio", "ns/op", "ratio");
}

/// Prints the line of one surface and returns its JSON record; times become ns per operation.
nlohmann::json report(const Surface& s, const Tape& tape, const Times& t, const Options& o) {
  const double ops = static_cast<double>(tape.op_count()) * o.points;
  const auto ns = [&](double sec) { return sec * 1e9 / ops; };
  const double ratio = t.interval / t.point;
  const bool within = ratio <= kIntervalOverPointTarget;
  const double bratio = t.batch / t.point;
  const bool bwithin = bratio <= kBatchOverPointTarget;
  const double bg_ratio = t.batch_grad / t.interval_grad, bg_point = t.batch_grad / t.point;
  const double bp_ratio = t.batch_point / t.point;
  std::printf(
      "%-13s %4d  %10.2f %10.2f %10.2f %10.2f %10.2f  %9.2f  %-7s %9.2f %9.2f  %-7s %9.2f %9.2f "
      "%9.2f %9.2f %9.2f %8.1f%s\n",
      s.scene, tape.op_count(), ns(t.native), ns(t.point), ns(t.interval), ns(t.point_grad),
      ns(t.interval_grad), ratio, within ? "within" : "MISSED", ns(t.batch), bratio,
      bwithin ? "within" : "MISSED", ns(t.batch_grad), bg_ratio, bg_point, ns(t.batch_point),
      bp_ratio, mib(t.peak_bytes), t.peak_exact ? "" : "*");
  return {{"surface", s.scene},
          {"tape_ops", tape.op_count()},
          {"evaluations", o.points},
          {"runs", o.runs},
          {"ns_per_op",
           {{"native_double", ns(t.native)},
            {"point", ns(t.point)},
            {"interval", ns(t.interval)},
            {"point_grad", ns(t.point_grad)},
            {"interval_grad", ns(t.interval_grad)},
            {"interval_batch", ns(t.batch)},
            {"interval_grad_batch", ns(t.batch_grad)},
            {"point_batch", ns(t.batch_point)}}},
          {"ops_per_second_per_core",
           {{"point", 1e9 / ns(t.point)},
            {"interval", 1e9 / ns(t.interval)},
            {"point_grad", 1e9 / ns(t.point_grad)},
            {"interval_grad", 1e9 / ns(t.interval_grad)},
            {"interval_batch", 1e9 / ns(t.batch)},
            {"interval_grad_batch", 1e9 / ns(t.batch_grad)},
            {"point_batch", 1e9 / ns(t.batch_point)}}},
          {"interval_over_point", ratio},
          {"interval_over_point_target", kIntervalOverPointTarget},
          {"within_target", within},
          {"batch_lanes", o.lanes},
          {"batch_isa", t.batch_isa},
          {"batch_over_point", bratio},
          {"batch_over_point_target", kBatchOverPointTarget},
          {"batch_within_target", bwithin},
          {"batch_grad_over_interval_grad", bg_ratio},
          {"batch_grad_over_point", bg_point},
          {"point_batch_over_point", bp_ratio},
          {"peak_rss_mib", mib(t.peak_bytes)},
          {"peak_rss_per_run", t.peak_exact}};
}

void run(const Options& o) {
  const std::vector<Scene> scenes = load_scenes(o);
  nlohmann::json out = nlohmann::json::array();
  print_header(o.lanes);
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const Tape& tape = *scenes[i].tape;
    const std::vector<Vec3> pts = sample_points(scenes[i].bounds, o.points);
    const Times t = measure(kSurfaces[i], tape, pts, o.runs, o);
    out.push_back(report(kSurfaces[i], tape, t, o));
  }
  // Throughput: tape operations per second on one core (the runs are single-threaded).
  std::printf("\n%-13s %12s %12s %12s %12s %12s %12s %12s\n", "throughput", "point", "interval",
              "pt+grad", "iv+grad", "batch", "bgrad", "bpoint");
  std::printf("%-13s %12s %12s %12s %12s %12s %12s %12s\n", "", "Mop/s/core", "Mop/s/core",
              "Mop/s/core", "Mop/s/core", "Mop/s/core", "Mop/s/core", "Mop/s/core");
  for (const nlohmann::json& r : out) {
    const auto mops = [&](const char* k) { return 1e3 / r["ns_per_op"][k].get<double>(); };
    std::printf("%-13s %12.0f %12.0f %12.0f %12.0f %12.0f %12.0f %12.0f\n",
                r["surface"].get<std::string>().c_str(), mops("point"), mops("interval"),
                mops("point_grad"), mops("interval_grad"), mops("interval_batch"),
                mops("interval_grad_batch"), mops("point_batch"));
  }
  std::printf(
      "\nmedians of %d runs of %d evaluations; 'native' is the expression compiled as C++;\n"
      "'batch %d': the batched interval evaluator (%s), %d boxes per pass, ns per operation per "
      "box\n"
      "'bgrad %d': the batched interval + gradient evaluator, the same way (bg/ivgrad: over "
      "iv+grad)\n"
      "'bpoint %d': the batched point evaluator, %d points per pass (bp/point: over point)\n"
      "target: interval within %gx of point evaluation per operation, batch within %gx\n%s\n",
      o.runs, o.points, o.lanes, out.empty() ? "" : out[0]["batch_isa"].get<std::string>().c_str(),
      o.lanes, o.lanes, o.lanes, o.lanes, kIntervalOverPointTarget, kBatchOverPointTarget,
      kPeakNote);
  if (!o.json.empty()) app::write_text_atomically(o.json, out.dump(2) + "\n");
}

void setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("--points", o->points, "evaluations per run")->check(CLI::Range(100, 10'000'000));
  app.add_option("--runs", o->runs, "runs per measurement (the median is reported)")
      ->check(CLI::Range(1, 101));
  app.add_option("--lanes", o->lanes, "boxes (points) per pass of the batched evaluators")
      ->check(CLI::IsMember({4, 8, 16}));
  app.add_flag("--sse2", o->sse2,
               "run the batched evaluators' baseline (SSE2) code even where AVX2 is there");
  add_scene_dir_option(app, &o->scene_dir);
  app.add_option("--json", o->json, "also write the figures as JSON to this file");
  app.footer("Examples:\n  iaa bench tape\n  iaa bench tape --points 100000 --json tape.json");
  app.callback([o] { run(*o); });
}

BenchRegistrar reg{
    {"tape", "ns per tape operation of each evaluator vs native double code", setup}};

}  // namespace
}  // namespace iaa::cli
