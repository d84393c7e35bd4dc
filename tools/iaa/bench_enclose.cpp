// `iaa bench enclose`: boxes and time of the enclosure octree for depths 6-10 on chubs, the
// teardrop and the Barth sextic (their scenes in data/scenes; median of several runs), including
// the .vtu write, with the growth per level (about x4 for a surface) and, as the baseline of the
// same run, the natural interval alone (no mean-value form) at the shallower depths. The machine
// may be shared: the `cpu` column (process CPU time of enclose + convert + write, all threads)
// shows the work when the wall-clock times are inflated by other processes; `peak` is the peak
// resident memory of the process during a run (the largest of the runs; bench.h, PeakMemory).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/files.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "expr/tape.h"
#include "iaa/bench.h"
#include "iaa/bench_scenes.h"
#ifdef IAA_HAVE_VIZ
#include "iaa/viz_plugin.h"
#endif

namespace iaa::cli {
namespace {

struct BenchOptions {
  int min_depth = 6;
  int max_depth = 10;
  int runs = 3;
  int threads = 0;
  int baseline_max_depth = 8;
  std::vector<std::string> surfaces{"chubs", "teardrop", "barth_sextic"};
  std::string scene_dir;
  bool no_write = false;
  std::string json;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <class F>
double seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One row of the table: a surface at one depth, times as medians over the runs.
struct Row {
  std::string surface;
  int depth = 0;
  std::uint64_t boxes = 0, crossing = 0, possible = 0;
  std::uint64_t evaluations = 0, corner_evaluations = 0, expansion_signs = 0;
  double enclose_s = 0, convert_s = 0, write_s = 0, total_s = 0, cpu_s = 0;
  std::uintmax_t file_bytes = 0;
  std::uint64_t peak_bytes = 0;            ///< the largest peak resident memory of the runs
  bool peak_exact = true;                  ///< every run's peak was its own (PeakMemory::exact)
  double base_boxes = -1, base_time = -1;  ///< the baseline's; -1 when not measured
};

/// What the benchmark measures, fixed before the first measurement.
struct Plan {
  std::vector<Scene> scenes;
  bool write = false;  ///< the .vtu conversion and write are measured too
  std::string tmp;     ///< the temporary .vtu file
};

/// Checks the options and reads all scenes before anything is measured, so that a bad name
/// fails at once.
Plan make_plan(const BenchOptions& o) {
  if (o.min_depth < 1 || o.max_depth > EncloseSettings::kMaxDepth || o.min_depth > o.max_depth) {
    throw SettingError("--depths: need 1 <= MIN <= MAX <= " +
                       std::to_string(EncloseSettings::kMaxDepth));
  }
  if (o.runs < 1 || o.runs > 100) throw SettingError("--runs must be between 1 and 100");
  const std::string dir = find_scene_dir(o.scene_dir);
  Plan plan;
  for (const std::string& name : o.surfaces) {
    plan.scenes.push_back(app::load_scene(dir + "/" + name + ".toml"));
  }
  plan.write = !o.no_write;
#ifndef IAA_HAVE_VIZ
  plan.write = false;
#else
  if (plan.write) viz_plugin("iaa bench enclose (without --no-write)");  // said before the runs
#endif
  plan.tmp = (std::filesystem::temp_directory_path() /
              ("iaa-bench-enclose-" + std::to_string(::getpid()) + ".vtu"))
                 .string();
  return plan;
}

void print_header(const BenchOptions& o, const Plan& plan, int threads) {
  std::printf("iaa bench enclose: %d threads, median of %d runs%s\n", threads, o.runs,
              plan.write ? ", write = .vtu (LZ4) to a temporary file" : ", no write");
  std::printf("baseline: natural interval only (no mean-value form), depths <= %d\n\n",
              o.baseline_max_depth);
  std::printf("%-13s %5s %10s %8s %10s %9s %9s %9s %9s %8s %9s %9s %12s %9s\n", "surface", "depth",
              "boxes", "x/level", "possible", "enclose", "convert", "write", "total", "x/level",
              "cpu", "peak MiB", "base boxes", "base time");
}

/// The octree (and, when planned, its .vtu conversion and write) `o.runs` times: the counts of
/// the last run, which every run repeats, and the median times.
void measure_octree(const Scene& scene, const EncloseSettings& s, int runs,
                    [[maybe_unused]] const Plan& plan, const Exec& exec, Row* row) {
  std::vector<double> t_enc, t_conv, t_write, t_total, t_cpu;
  Enclosure enc;
  for (int r = 0; r < runs; ++r) {
    enc = Enclosure{};  // the previous run's octree is not part of this run's peak
    const PeakMemory memory;
    const std::clock_t c0 = std::clock();
    const double te = seconds([&] { enc = enclose(*scene.tape, s, exec); });
    double tc = 0, tw = 0;
#ifdef IAA_HAVE_VIZ
    if (plan.write) {
      const viz::VtuWriteTimes t =
          viz_plugin("iaa bench enclose")
              .write_enclosure_vtu_timed(plan.tmp, enc, viz::EnclosureInfo{scene.expression, s},
                                         exec);
      tc = t.convert_s;
      tw = t.write_s;
      row->file_bytes = std::filesystem::file_size(plan.tmp);
      std::filesystem::remove(plan.tmp);
    }
#endif
    t_enc.push_back(te);
    t_conv.push_back(tc);
    t_write.push_back(tw);
    t_total.push_back(te + tc + tw);
    t_cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    row->peak_bytes = std::max(row->peak_bytes, memory.peak_bytes());
    row->peak_exact = row->peak_exact && memory.exact();
  }
  row->boxes = enc.cells.size();
  row->crossing = enc.count(CellClass::kCrossing);
  row->possible = enc.count(CellClass::kPossible);
  row->evaluations = enc.evaluations;
  row->corner_evaluations = enc.corner_evaluations;
  row->expansion_signs = enc.expansion_signs;
  row->enclose_s = median(t_enc);
  row->convert_s = median(t_conv);
  row->write_s = median(t_write);
  row->total_s = median(t_total);
  row->cpu_s = median(t_cpu);
}

/// The natural interval alone (no mean-value form) on the same settings: its boxes and median
/// time, the baseline the mean-value form is measured against.
void measure_baseline(const Tape& tape, const EncloseSettings& s, int runs, const Exec& exec,
                      Row* row) {
  EncloseSettings b = s;
  b.centered_form = false;
  std::vector<double> tb;
  for (int r = 0; r < runs; ++r) {
    Enclosure e;
    tb.push_back(seconds([&] { e = enclose(tape, b, exec); }));
    row->base_boxes = static_cast<double>(e.cells.size());
  }
  row->base_time = median(tb);
}

/// One line of the table; the growth columns compare with the previous depth's row.
void print_row(const Row& row, const Row* prev) {
  const double boxes = static_cast<double>(row.boxes);
  char growth[16] = "-", tgrowth[16] = "-", bb[24] = "-", bt[24] = "-";
  if (prev && prev->boxes > 0) {
    std::snprintf(growth, sizeof growth, "%.2f", boxes / static_cast<double>(prev->boxes));
  }
  if (prev && prev->total_s > 0) {
    std::snprintf(tgrowth, sizeof tgrowth, "%.2f", row.total_s / prev->total_s);
  }
  if (row.base_boxes >= 0) {
    std::snprintf(bb, sizeof bb, "%.0f", row.base_boxes);
    std::snprintf(bt, sizeof bt, "%.3f s", row.base_time);
  }
  std::printf(
      "%-13s %5d %10.0f %8s %10llu %7.3f s %7.3f s %7.3f s %7.3f s %8s %7.3f s %8.1f%s %12s %9s\n",
      row.surface.c_str(), row.depth, boxes, growth, static_cast<unsigned long long>(row.possible),
      row.enclose_s, row.convert_s, row.write_s, row.total_s, tgrowth, row.cpu_s,
      mib(row.peak_bytes), row.peak_exact ? " " : "*", bb, bt);
  std::fflush(stdout);
}

nlohmann::json row_json(const Row& row) {
  nlohmann::json j = {{"surface", row.surface},
                      {"depth", row.depth},
                      {"boxes", row.boxes},
                      {"crossing", row.crossing},
                      {"possible", row.possible},
                      {"evaluations", row.evaluations},
                      {"corner_evaluations", row.corner_evaluations},
                      {"expansion_signs", row.expansion_signs},
                      {"enclose_s", row.enclose_s},
                      {"convert_s", row.convert_s},
                      {"write_s", row.write_s},
                      {"total_s", row.total_s},
                      {"cpu_s", row.cpu_s},
                      {"file_bytes", row.file_bytes},
                      {"peak_rss_mib", mib(row.peak_bytes)},
                      {"peak_rss_per_run", row.peak_exact}};
  if (row.base_boxes >= 0) {
    j["baseline_boxes"] = row.base_boxes;
    j["baseline_enclose_s"] = row.base_time;
  }
  return j;
}

void run(const BenchOptions& o) {
  const Plan plan = make_plan(o);
  Exec exec;
  exec.threads = o.threads;
  print_header(o, plan, exec.resolved_threads());
  // Each row is printed as soon as it is measured: a long run shows its progress.
  nlohmann::json rows = nlohmann::json::array();
  for (const Scene& scene : plan.scenes) {
    Row prev;
    for (int depth = o.min_depth; depth <= o.max_depth; ++depth) {
      EncloseSettings s;
      s.bounds = scene.bounds;
      s.depth = depth;
      Row row;
      row.surface = scene.name;
      row.depth = depth;
      measure_octree(scene, s, o.runs, plan, exec, &row);
      if (depth <= o.baseline_max_depth) measure_baseline(*scene.tape, s, o.runs, exec, &row);
      print_row(row, depth > o.min_depth ? &prev : nullptr);
      rows.push_back(row_json(row));
      prev = row;
    }
  }
  std::printf("\n%s\n", kPeakNote);
  if (!o.json.empty()) {
    nlohmann::json j = {{"bench", "enclose"},
                        {"threads", exec.resolved_threads()},
                        {"runs", o.runs},
                        {"rows", rows}};
    app::write_text_atomically(o.json, j.dump(2) + "\n");
    std::printf("\nwrote %s\n", o.json.c_str());
  }
}

void setup(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  app.add_option("--min-depth", o->min_depth, "first depth")->capture_default_str();
  app.add_option("--max-depth", o->max_depth, "last depth")->capture_default_str();
  app.add_option("--runs", o->runs, "runs per measurement (the median is reported)")
      ->capture_default_str();
  app.add_option("-t,--threads", o->threads, "worker threads (0: all)")->capture_default_str();
  app.add_option("--baseline-max-depth", o->baseline_max_depth,
                 "deepest depth for the natural-interval baseline (it grows much faster)")
      ->capture_default_str();
  app.add_option("--surface", o->surfaces, "the surfaces: names of scenes in the scene directory")
      ->capture_default_str();
  add_scene_dir_option(app, &o->scene_dir);
  app.add_flag("--no-write", o->no_write,
               "measure the octree only, not the .vtu conversion and write");
  app.add_option("--json", o->json, "also write the table as JSON");
  app.footer(
      "Examples:\n"
      "  iaa bench enclose\n"
      "  iaa bench enclose --surface chubs --min-depth 9 --max-depth 9 --runs 5\n"
      "  iaa bench enclose --no-write --json enclose.json");
  app.callback([o] { run(*o); });
}

BenchRegistrar reg{{"enclose",
                    "enclosure octree: boxes and time per depth (chubs, teardrop, Barth sextic)",
                    setup}};

}  // namespace
}  // namespace iaa::cli
