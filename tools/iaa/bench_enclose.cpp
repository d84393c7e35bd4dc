// `iaa bench enclose`: boxes and time of the enclosure octree for depths 6-10 on chubs, the
// teardrop and the Barth sextic (their scenes in data/scenes; median of several runs), including
// the .vtu write, with the growth per level (about x4 for a surface) and, as the baseline of the
// same run, the natural interval alone (no mean-value form) at the shallower depths. The machine
// may be shared: the `cpu` column (process CPU time of enclose + convert + write, all threads)
// shows the work when the wall-clock times are inflated by other processes.
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
#include "viz/enclosure_vtk.h"
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

void run(const BenchOptions& o) {
  if (o.min_depth < 1 || o.max_depth > EncloseSettings::kMaxDepth || o.min_depth > o.max_depth) {
    throw SettingError("--depths: need 1 <= MIN <= MAX <= " +
                       std::to_string(EncloseSettings::kMaxDepth));
  }
  if (o.runs < 1 || o.runs > 100) throw SettingError("--runs must be between 1 and 100");
  // All scenes are read before anything is measured, so that a bad name fails at once.
  const std::string dir = find_scene_dir(o.scene_dir);
  std::vector<Scene> scenes;
  for (const std::string& name : o.surfaces) {
    scenes.push_back(app::load_scene(dir + "/" + name + ".toml"));
  }
  bool write = !o.no_write;
#ifndef IAA_HAVE_VIZ
  write = false;
#endif
  const std::string tmp = (std::filesystem::temp_directory_path() /
                           ("iaa-bench-enclose-" + std::to_string(::getpid()) + ".vtu"))
                              .string();
  Exec exec;
  exec.threads = o.threads;
  std::printf("iaa bench enclose: %d threads, median of %d runs%s\n", exec.resolved_threads(),
              o.runs, write ? ", write = .vtu (LZ4) to a temporary file" : ", no write");
  std::printf("baseline: natural interval only (no mean-value form), depths <= %d\n\n",
              o.baseline_max_depth);
  std::printf("%-13s %5s %10s %8s %10s %9s %9s %9s %9s %8s %9s %12s %9s\n", "surface", "depth",
              "boxes", "x/level", "possible", "enclose", "convert", "write", "total", "x/level",
              "cpu", "base boxes", "base time");
  nlohmann::json rows = nlohmann::json::array();
  for (const Scene& scene : scenes) {
    const Tape& tape = *scene.tape;
    double prev_boxes = 0, prev_total = 0;
    for (int depth = o.min_depth; depth <= o.max_depth; ++depth) {
      EncloseSettings s;
      s.bounds = scene.bounds;
      s.depth = depth;
      std::vector<double> t_enc, t_conv, t_write, t_total, t_cpu;
      Enclosure enc;
      std::uintmax_t bytes = 0;
      for (int r = 0; r < o.runs; ++r) {
        const std::clock_t c0 = std::clock();
        const double te = seconds([&] { enc = enclose(tape, s, exec); });
        double tc = 0, tw = 0;
#ifdef IAA_HAVE_VIZ
        if (write) {
          const viz::VtuWriteTimes t = viz::write_enclosure_vtu_timed(
              tmp, enc, viz::EnclosureInfo{scene.expression, s}, exec);
          tc = t.convert_s;
          tw = t.write_s;
          bytes = std::filesystem::file_size(tmp);
          std::filesystem::remove(tmp);
        }
#endif
        t_enc.push_back(te);
        t_conv.push_back(tc);
        t_write.push_back(tw);
        t_total.push_back(te + tc + tw);
        t_cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      }
      double base_boxes = -1, base_time = -1;
      if (depth <= o.baseline_max_depth) {
        EncloseSettings b = s;
        b.centered_form = false;
        std::vector<double> tb;
        for (int r = 0; r < o.runs; ++r) {
          Enclosure e;
          tb.push_back(seconds([&] { e = enclose(tape, b, exec); }));
          base_boxes = static_cast<double>(e.cells.size());
        }
        base_time = median(tb);
      }
      const double boxes = static_cast<double>(enc.cells.size());
      const double total = median(t_total);
      char growth[16] = "-", tgrowth[16] = "-", bb[24] = "-", bt[24] = "-";
      if (prev_boxes > 0) std::snprintf(growth, sizeof growth, "%.2f", boxes / prev_boxes);
      if (prev_total > 0) std::snprintf(tgrowth, sizeof tgrowth, "%.2f", total / prev_total);
      if (base_boxes >= 0) {
        std::snprintf(bb, sizeof bb, "%.0f", base_boxes);
        std::snprintf(bt, sizeof bt, "%.3f s", base_time);
      }
      std::printf(
          "%-13s %5d %10.0f %8s %10llu %7.3f s %7.3f s %7.3f s %7.3f s %8s %7.3f s %12s %9s\n",
          scene.name.c_str(), depth, boxes, growth,
          static_cast<unsigned long long>(enc.count(CellClass::kPossible)), median(t_enc),
          median(t_conv), median(t_write), total, tgrowth, median(t_cpu), bb, bt);
      std::fflush(stdout);
      nlohmann::json row = {{"surface", scene.name},
                            {"depth", depth},
                            {"boxes", enc.cells.size()},
                            {"crossing", enc.count(CellClass::kCrossing)},
                            {"possible", enc.count(CellClass::kPossible)},
                            {"evaluations", enc.evaluations},
                            {"corner_evaluations", enc.corner_evaluations},
                            {"expansion_signs", enc.expansion_signs},
                            {"enclose_s", median(t_enc)},
                            {"convert_s", median(t_conv)},
                            {"write_s", median(t_write)},
                            {"total_s", total},
                            {"cpu_s", median(t_cpu)},
                            {"file_bytes", bytes}};
      if (base_boxes >= 0) {
        row["baseline_boxes"] = base_boxes;
        row["baseline_enclose_s"] = base_time;
      }
      rows.push_back(row);
      prev_boxes = boxes;
      prev_total = total;
    }
  }
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
  app.add_option("--scene-dir", o->scene_dir,
                 "directory of the scene files (default: data/scenes in the working directory, "
                 "else in the source tree above the executable)");
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
