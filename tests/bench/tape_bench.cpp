// Google Benchmark micro-benchmarks of the interval core and the tape evaluators (the same
// figures as `iaa bench tape`, on the chubs scene of data/scenes, in Google Benchmark's format for
// comparisons across commits; the Blobby ones on the blobby scene, whose operations are mostly
// exp's and squares, for the exp kernels in the scalar and the batched evaluators):
//   build/bin/iaa_gbench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "expr/eval_batch.h"
#include "expr/eval_batch_grad.h"
#include "expr/eval_batch_point.h"
#include "expr/eval_interval.h"
#include "expr/eval_interval_grad.h"
#include "expr/eval_point.h"
#include "test_scenes.h"

namespace iaa {
namespace {

/// The chubs scene of the source tree (data/scenes/chubs.toml), read once.
const Scene& chubs() {
  static const Scene scene = test::bundled_scene("chubs");
  return scene;
}

/// The blobby scene of the source tree, read once.
const Scene& blobby() {
  static const Scene scene = test::bundled_scene("blobby");
  return scene;
}

/// n points drawn uniformly in the box b, the same in every run.
std::vector<Vec3> points(const Box3& b, int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(b.lo.x, b.hi.x), uy(b.lo.y, b.hi.y), uz(b.lo.z, b.hi.z);
  std::vector<Vec3> p(static_cast<std::size_t>(n));
  for (Vec3& v : p) v = {ux(rng), uy(rng), uz(rng)};
  return p;
}

// Runs `eval_one(evaluator, point)` over 1024 points per iteration and reports ns per tape op.
template <class Eval, class F>
void run_tape(benchmark::State& state, F eval_one, const Scene& scene = chubs()) {
  const Tape& t = *scene.tape;
  Eval e(t);
  const auto pts = points(scene.bounds, 1024);
  RoundingScope scope;  // point evaluation rounds upward here too; speed is the same
  for (auto _ : state) {
    for (const Vec3& p : pts) benchmark::DoNotOptimize(eval_one(e, p));
  }
  state.counters["ns/op"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1024 * t.op_count(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

IBox box_at(const Vec3& p) {
  return IBox(Interval(p.x, p.x + 0.01), Interval(p.y, p.y + 0.01), Interval(p.z, p.z + 0.01));
}

void BM_PointEval(benchmark::State& state) {
  run_tape<PointEval>(state, [](PointEval& e, const Vec3& p) { return e.eval(p); });
}
BENCHMARK(BM_PointEval);

void BM_IntervalEval(benchmark::State& state) {
  run_tape<IntervalEval>(state, [](IntervalEval& e, const Vec3& p) { return e.eval(box_at(p)); });
}
BENCHMARK(BM_IntervalEval);

// The batched interval evaluator on the same boxes, K per pass; ns per operation per box.
/// A batched evaluator over 1024 boxes of the scene (chubs), K at a time; Out is its result.
template <class Batch, class Out>
void run_batch(benchmark::State& state, const Scene& scene = chubs()) {
  constexpr int K = Batch::kLanes;
  const Tape& t = *scene.tape;
  Batch e(t);
  std::vector<IBox> boxes;
  for (const Vec3& p : points(scene.bounds, 1024)) boxes.push_back(box_at(p));
  RoundingScope scope;
  Out out[K];
  for (auto _ : state) {
    for (std::size_t i = 0; i < boxes.size(); i += K) {
      e.eval(boxes.data() + i, K, out);
      benchmark::DoNotOptimize(out);
    }
  }
  state.counters["ns/op"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1024 * t.op_count(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <int K>
void BM_BatchIntervalEval(benchmark::State& state) {
  run_batch<BatchIntervalEvalK<K>, Interval>(state);
}
BENCHMARK(BM_BatchIntervalEval<4>);
BENCHMARK(BM_BatchIntervalEval<8>);
BENCHMARK(BM_BatchIntervalEval<16>);

void BM_IntervalGradEval(benchmark::State& state) {
  run_tape<IntervalGradEval>(state,
                             [](IntervalGradEval& e, const Vec3& p) { return e.eval(box_at(p)); });
}
BENCHMARK(BM_IntervalGradEval);

// The batched interval + gradient evaluator on the same boxes, K at a time (ns per operation per
// box, as BM_BatchIntervalEval).
template <int K>
void BM_BatchIntervalGradEval(benchmark::State& state) {
  run_batch<BatchIntervalGradEvalK<K>, IGrad>(state);
}
BENCHMARK(BM_BatchIntervalGradEval<4>);
BENCHMARK(BM_BatchIntervalGradEval<8>);
BENCHMARK(BM_BatchIntervalGradEval<16>);

// The batched point evaluator on the same points, K at a time (ns per operation per point).
template <int K>
void run_point_batch(benchmark::State& state, const Scene& scene) {
  const Tape& t = *scene.tape;
  BatchPointEvalK<K> e(t);
  const auto pts = points(scene.bounds, 1024);
  RoundingScope scope;
  double out[K];
  for (auto _ : state) {
    for (std::size_t i = 0; i < pts.size(); i += K) {
      e.eval(pts.data() + i, K, out);
      benchmark::DoNotOptimize(out);
    }
  }
  state.counters["ns/op"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1024 * t.op_count(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
template <int K>
void BM_BatchPointEval(benchmark::State& state) {
  run_point_batch<K>(state, chubs());
}
BENCHMARK(BM_BatchPointEval<4>);
BENCHMARK(BM_BatchPointEval<8>);
BENCHMARK(BM_BatchPointEval<16>);

// The same on blobby (exp in the kernels of elementary.h: two ends in one pass in the scalar
// interval rule, in vectors in the batches).
void BM_BlobbyPointEval(benchmark::State& state) {
  run_tape<PointEval>(
      state, [](PointEval& e, const Vec3& p) { return e.eval(p); }, blobby());
}
BENCHMARK(BM_BlobbyPointEval);
void BM_BlobbyBatchPointEval16(benchmark::State& state) {
  run_point_batch<16>(state, blobby());
}
BENCHMARK(BM_BlobbyBatchPointEval16);
void BM_BlobbyIntervalEval(benchmark::State& state) {
  run_tape<IntervalEval>(
      state, [](IntervalEval& e, const Vec3& p) { return e.eval(box_at(p)); }, blobby());
}
BENCHMARK(BM_BlobbyIntervalEval);
void BM_BlobbyBatchIntervalEval4(benchmark::State& state) {
  run_batch<BatchIntervalEvalK<4>, Interval>(state, blobby());
}
BENCHMARK(BM_BlobbyBatchIntervalEval4);
void BM_BlobbyIntervalGradEval(benchmark::State& state) {
  run_tape<IntervalGradEval>(
      state, [](IntervalGradEval& e, const Vec3& p) { return e.eval(box_at(p)); }, blobby());
}
BENCHMARK(BM_BlobbyIntervalGradEval);
void BM_BlobbyBatchIntervalGradEval4(benchmark::State& state) {
  run_batch<BatchIntervalGradEvalK<4>, IGrad>(state, blobby());
}
BENCHMARK(BM_BlobbyBatchIntervalGradEval4);

// The cost of the per-operation rounding-mode switch that RoundingScope avoids.
void BM_IntervalMulWithModeSwitch(benchmark::State& state) {
  using Protected = boost::numeric::interval<double>;
  Protected a(1.1, 1.2), b(-0.3, 0.7);
  for (auto _ : state) {
    a = a * b + Protected(0.5);
    benchmark::DoNotOptimize(a);
  }
}
BENCHMARK(BM_IntervalMulWithModeSwitch);

void BM_IntervalMulInScope(benchmark::State& state) {
  RoundingScope scope;
  Interval a(1.1, 1.2), b(-0.3, 0.7);
  for (auto _ : state) {
    a = a * b + Interval(0.5);
    benchmark::DoNotOptimize(a);
  }
}
BENCHMARK(BM_IntervalMulInScope);

}  // namespace
}  // namespace iaa

BENCHMARK_MAIN();
