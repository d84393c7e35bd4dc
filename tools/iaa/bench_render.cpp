// `iaa bench render`: IAA against the point-sampled baselines on the paper's five scenes (or every
// scene of the directory with --all), in one process: time (median of runs), interval evaluations
// and leaves per pixel, the iaa/adaptive ratios, and quality against a `grid 16` reference (RMSE,
// missed and spurious pixels), and the peak resident memory of a render (bench.h, PeakMemory).
// With --mpi N: `mpirun -np N iaa render` on each scene against one process with N times the
// threads: times, the load balance, and whether the images are the same.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <memory>
#include <thread>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/files.h"
#include "app/png.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "iaa/bench.h"
#include "iaa/bench_scenes.h"
#include "iaa/render_flags.h"
#include "render/render.h"

namespace iaa::cli {
namespace {

struct BenchRenderOptions {
  std::vector<std::string> scenes{"teardrop", "chubs", "tritrumpet", "twist", "blobby"};
  bool all = false;  ///< every NAME.toml of the scene directory instead of `scenes`
  std::string dir;
  int size = 500;
  int runs = 3;
  int threads = 0;
  int ref_grid = 16;
  std::string json;
  std::vector<std::string> sets;
  RenderFlags flags;
  int mpi = 0;  ///< processes of the --mpi comparison (0: the usual benchmark)
};

/// a / b as JSON, null when b is 0 (no baseline to compare with).
nlohmann::json ratio_json(double a, double b) {
  return b > 0 ? nlohmann::json(a / b) : nlohmann::json(nullptr);
}

/// a / b as a table cell ("1.32x"), "-" when b is 0.
std::string ratio_cell(double a, double b) {
  if (!(b > 0)) return "-";
  char c[32];
  std::snprintf(c, sizeof c, "%.2fx", a / b);
  return c;
}

/// Display value (8-bit sRGB-ish) in [0, 1], what a viewer of the PNG sees.
double display(float v) {
  return app::to_byte(v) / 255.0;
}

struct Quality {
  double rmse = 0;
  long missed = 0, spurious = 0;
};

Quality compare(const Film& f, const Film& ref) {
  Quality q;
  double sum = 0;
  for (std::size_t i = 0; i < f.color.size(); ++i) {
    const Rgb& a = f.color[i];
    const Rgb& b = ref.color[i];
    const double dr = display(a.r) - display(b.r), dg = display(a.g) - display(b.g),
                 db = display(a.b) - display(b.b);
    sum += dr * dr + dg * dg + db * db;
    const bool ref_sees = ref.coverage[i] > 0, sees = f.coverage[i] > 0;
    q.missed += ref_sees && !sees;
    q.spurious += !ref_sees && sees;
  }
  q.rmse = std::sqrt(sum / (3.0 * double(f.color.size())));
  return q;
}

struct MethodRow {
  std::string method;
  double median_s = 0;
  double evals_px = 0, leaves_px = 0;
  Quality q;
  std::uint64_t peak_bytes = 0;  ///< the largest peak resident memory of the runs
  bool peak_exact = true;        ///< every run's peak was its own (PeakMemory::exact)
};

/// The methods compared, in the order of the table; adaptive is the one the ratios divide by.
constexpr RenderMethod kMethods[] = {RenderMethod::kIaa, RenderMethod::kAdaptive,
                                     RenderMethod::kPoint};
constexpr std::size_t kN = std::size(kMethods);
constexpr std::size_t kAdaptiveRow = 1;

/// Checks the options, including the render flags' ranges, before any scene is loaded.
void check_options(const BenchRenderOptions& o) {
  if (o.size < 8 || o.size > 4096) throw SettingError("--size must be in [8, 4096]");
  if (o.runs < 1 || o.runs > 100) throw SettingError("--runs must be in [1, 100]");
  if (o.ref_grid < 1 || o.ref_grid > RenderSettings::kMaxGrid)
    throw SettingError("--ref-grid must be in [1, 64]");
  RenderSettings checked;
  apply_render_flags(o.flags, &checked);
}

/// The scene `name` at the benchmark's image size, with the --set overrides.
Scene load_bench_scene(const BenchRenderOptions& o, const std::string& dir,
                       const std::string& name) {
  std::vector<std::string> sets = o.sets;
  sets.push_back("image.width=" + std::to_string(o.size));
  sets.push_back("image.height=" + std::to_string(o.size));
  return app::load_scene(dir + "/" + name + ".toml", sets);
}

/// One scene's measurements: a row per method, in kMethods' order.
struct SceneRows {
  std::vector<MethodRow> rows;
  double reference_seconds = 0;  ///< the time of the reference render
};

/// Renders the reference, then every method `o.runs` times: the median time, evaluations and
/// leaves per pixel, and quality against the reference.
SceneRows measure_scene(const BenchRenderOptions& o, const Scene& scene, const Exec& exec) {
  RenderSettings base = scene.settings;
  apply_render_flags(o.flags, &base);
  RenderSettings ref_st = base;
  ref_st.method = RenderMethod::kGrid;
  ref_st.grid_n = o.ref_grid;
  const Film ref = render(scene, ref_st, exec);
  // The methods take turns, run after run, so that a change of the machine's load during the
  // benchmark weighs on all of them alike (and on their ratios as little as possible).
  std::vector<double> times[kN];
  Film films[kN];
  std::uint64_t peaks[kN] = {};
  bool exact[kN] = {true, true, true};
  for (int r = 0; r < o.runs; ++r) {
    for (std::size_t i = 0; i < kN; ++i) {
      RenderSettings st = base;
      st.method = kMethods[i];
      films[i] = Film{};  // the method's previous image is not part of this run's peak
      const PeakMemory memory;
      films[i] = render(scene, st, exec);
      times[i].push_back(films[i].seconds);
      peaks[i] = std::max(peaks[i], memory.peak_bytes());
      exact[i] = exact[i] && memory.exact();
    }
  }
  SceneRows out;
  out.reference_seconds = ref.seconds;
  for (std::size_t i = 0; i < kN; ++i) {
    std::sort(times[i].begin(), times[i].end());
    const Film& f = films[i];
    MethodRow row;
    row.method = std::string(method_name(kMethods[i]));
    row.median_s = times[i][times[i].size() / 2];
    const double px = double(f.stats.pixels);
    row.evals_px = double(f.stats.evals) / px;
    row.leaves_px = double(f.stats.leaves) / px;
    row.q = compare(f, ref);
    row.peak_bytes = peaks[i];
    row.peak_exact = exact[i];
    out.rows.push_back(row);
  }
  return out;
}

void print_header(const BenchRenderOptions& o, int threads) {
  std::printf("iaa bench render: %dx%d, %d threads, median of %d runs, reference grid %d\n\n",
              o.size, o.size, threads, o.runs, o.ref_grid);
  std::printf("%-11s %-9s %9s %9s %9s %8s %8s %8s %8s %7s %9s %9s\n", "scene", "method", "median s",
              "evals/px", "leaves/px", "time/ad", "evals/ad", "leaves/ad", "RMSE", "missed",
              "spurious", "peak MiB");
}

/// Prints one scene's rows and appends their JSON records to `out`. The table shows the ratios
/// on the iaa row only (the comparison the benchmark is for); the JSON has them for every method.
void print_rows(const BenchRenderOptions& o, const std::string& name, const SceneRows& scene,
                int threads, nlohmann::json* out) {
  const MethodRow& adaptive = scene.rows[kAdaptiveRow];
  for (const MethodRow& r : scene.rows) {
    const bool iaa = r.method == "iaa";
    const std::string t = iaa ? ratio_cell(r.median_s, adaptive.median_s) : "";
    const std::string e = iaa ? ratio_cell(r.evals_px, adaptive.evals_px) : "";
    const std::string l = iaa ? ratio_cell(r.leaves_px, adaptive.leaves_px) : "";
    std::printf("%-11s %-9s %9.3f %9.1f %9.2f %8s %8s %9s %8.4f %7ld %9ld %8.1f%s\n", name.c_str(),
                r.method.c_str(), r.median_s, r.evals_px, r.leaves_px, t.c_str(), e.c_str(),
                l.c_str(), r.q.rmse, r.q.missed, r.q.spurious, mib(r.peak_bytes),
                r.peak_exact ? "" : "*");
    out->push_back({{"scene", name},
                    {"method", r.method},
                    {"median_seconds", r.median_s},
                    {"evals_per_pixel", r.evals_px},
                    {"leaves_per_pixel", r.leaves_px},
                    {"time_ratio_vs_adaptive", ratio_json(r.median_s, adaptive.median_s)},
                    {"evals_ratio_vs_adaptive", ratio_json(r.evals_px, adaptive.evals_px)},
                    {"leaves_ratio_vs_adaptive", ratio_json(r.leaves_px, adaptive.leaves_px)},
                    {"rmse", r.q.rmse},
                    {"missed", r.q.missed},
                    {"spurious", r.q.spurious},
                    {"peak_rss_mib", mib(r.peak_bytes)},
                    {"peak_rss_per_run", r.peak_exact},
                    {"width", o.size},
                    {"height", o.size},
                    {"threads", threads},
                    {"reference", "grid " + std::to_string(o.ref_grid)},
                    {"reference_seconds", scene.reference_seconds}});
  }
  std::fflush(stdout);
}

/// The names of every NAME.toml in `dir`, sorted (the same table whatever the directory order).
std::vector<std::string> all_scene_names(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".toml") names.push_back(e.path().stem());
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) throw SettingError("--all: no .toml scene in " + dir);
  return names;
}

/// The text between single quotes for a POSIX shell.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// What one `iaa render` run of the --mpi comparison gave: wall time of the whole command (MPI's
/// start included), the render's own time from its report, and the report.
struct RenderRun {
  double wall_s = 0;
  double render_s = 0;
  nlohmann::json report;
};

/// Runs `prefix iaa render SCENE ...` through the shell and reads its report back.
RenderRun run_render(const std::string& prefix, const std::string& scene_path,
                     const BenchRenderOptions& o, int threads, const std::string& png,
                     const std::string& report) {
  std::string cmd = prefix + shell_quote(std::filesystem::read_symlink("/proc/self/exe").string()) +
                    " render " + shell_quote(scene_path) + " -q -o " + shell_quote(png) +
                    " --report " + shell_quote(report) + " --threads " + std::to_string(threads) +
                    " --set image.width=" + std::to_string(o.size) +
                    " --set image.height=" + std::to_string(o.size);
  for (const std::string& set : o.sets) cmd += " --set " + shell_quote(set);
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = std::system(cmd.c_str());
  RenderRun r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (rc != 0) throw Error("--mpi: this command failed: " + cmd);
  r.report = nlohmann::json::parse(app::read_file(report));
  r.render_s = r.report.at("seconds").get<double>();
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// --mpi N: each scene rendered (IAA, the scene's settings and --set) by `mpirun -np N` with
/// --threads T (1 when not given) and by one process with N * T threads, taking turns `runs`
/// times; prints the medians, the balance of the last MPI run and whether the images are equal.
void run_mpi(const BenchRenderOptions& o, const std::string& dir,
             const std::vector<std::string>& scenes) {
  if (o.mpi < 2 || o.mpi > 256) throw SettingError("--mpi must be in [2, 256] processes");
  const int threads = o.threads > 0 ? o.threads : 1;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  std::string mpirun = "mpirun -np " + std::to_string(o.mpi) + " ";
  if (unsigned(o.mpi) * unsigned(threads) > cores) mpirun += "--oversubscribe ";
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("iaa-bench-mpi-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  std::printf(
      "iaa bench render --mpi: %dx%d, mpirun -np %d --threads %d against one process with %d "
      "threads, median of %d runs (%u cores)\n\n",
      o.size, o.size, o.mpi, threads, o.mpi * threads, o.runs, cores);
  std::printf("%-11s %10s %10s %8s %10s %10s %9s %11s %6s\n", "scene", "mpi s", "one s", "mpi/one",
              "mpi wall", "one wall", "max/mean", "max idle s", "same");
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : scenes) {
    const std::string path = dir + "/" + name + ".toml";
    std::vector<double> mpi_s, one_s, mpi_wall, one_wall;
    RenderRun last_mpi, last_one;
    for (int r = 0; r < o.runs; ++r) {
      last_mpi = run_render(mpirun, path, o, threads, (tmp / "mpi.png").string(),
                            (tmp / "mpi.json").string());
      last_one = run_render("", path, o, o.mpi * threads, (tmp / "one.png").string(),
                            (tmp / "one.json").string());
      mpi_s.push_back(last_mpi.render_s);
      one_s.push_back(last_one.render_s);
      mpi_wall.push_back(last_mpi.wall_s);
      one_wall.push_back(last_one.wall_s);
    }
    const bool same =
        app::read_file((tmp / "mpi.png").string()) == app::read_file((tmp / "one.png").string());
    const nlohmann::json& bal = last_mpi.report.at("mpi");
    double idle = 0;
    for (const auto& rk : bal.at("ranks"))
      idle = std::max(idle, rk.at("idle_seconds").get<double>());
    const double ratio = bal.at("max_over_mean_evaluations").get<double>();
    std::printf("%-11s %10.3f %10.3f %7.2fx %10.3f %10.3f %9.3f %11.3f %6s\n", name.c_str(),
                median(mpi_s), median(one_s), median(mpi_s) / median(one_s), median(mpi_wall),
                median(one_wall), ratio, idle, same ? "yes" : "NO");
    std::fflush(stdout);
    out.push_back({{"scene", name},
                   {"processes", o.mpi},
                   {"threads_per_process", threads},
                   {"mpi_render_seconds", median(mpi_s)},
                   {"one_process_render_seconds", median(one_s)},
                   {"mpi_wall_seconds", median(mpi_wall)},
                   {"one_process_wall_seconds", median(one_wall)},
                   {"max_over_mean_evaluations", ratio},
                   {"max_idle_seconds", idle},
                   {"balance", bal},
                   {"same_image", same}});
    if (!same) std::fprintf(stderr, "iaa bench render: %s: the images differ\n", name.c_str());
  }
  std::filesystem::remove_all(tmp);
  std::printf(
      "\nmpi s, one s: render() time in the report (rank 0's, the gathering included); wall: the\n"
      "whole command, MPI's start-up included. max/mean: evaluations of the busiest process over\n"
      "the mean; max idle: the longest a process waited for the others. same: the PNGs are "
      "equal.\n");
  if (!o.json.empty()) app::write_text_atomically(o.json, out.dump(2) + "\n");
}

void run(const BenchRenderOptions& o) {
  check_options(o);
  const std::string dir = find_scene_dir(o.dir);
  const std::vector<std::string> scenes = o.all ? all_scene_names(dir) : o.scenes;
  if (o.mpi) return run_mpi(o, dir, scenes);
  Exec exec;
  exec.threads = o.threads;
  nlohmann::json out = nlohmann::json::array();
  print_header(o, exec.resolved_threads());
  // Each scene's rows are printed as soon as they are measured: a long run shows its progress.
  for (const std::string& name : scenes) {
    const Scene scene = load_bench_scene(o, dir, name);
    print_rows(o, name, measure_scene(o, scene, exec), exec.resolved_threads(), &out);
  }
  std::printf(
      "\ntime/ad, evals/ad, leaves/ad: iaa's median time, evaluations and leaves per pixel over\n"
      "adaptive's, measured in this run.\n"
      "RMSE on 8-bit display values in [0, 1]; missed = the reference sees surface, the method\n"
      "shows pure background; spurious = the reference sees none, the method shows some.\n"
      "%s\n",
      kPeakNote);
  if (!o.json.empty()) app::write_text_atomically(o.json, out.dump(2) + "\n");
}

void setup(CLI::App& app) {
  auto o = std::make_shared<BenchRenderOptions>();
  CLI::Option* scenes =
      app.add_option("--scenes", o->scenes,
                     "scene names: NAME.toml in the scene directory (default: the paper's five)");
  app.add_flag("--all", o->all, "every scene of the scene directory (NAME.toml), in name order")
      ->excludes(scenes);
  add_scene_dir_option(app, &o->dir);
  app.add_option("--size", o->size, "image edge in pixels (default 500)");
  app.add_option(
      "--runs", o->runs,
      "runs per method, the methods taking turns; the median time is reported (default 3)");
  app.add_option("--threads", o->threads, "worker threads (0 = all cores)");
  app.add_option("--ref-grid", o->ref_grid, "rays per pixel side of the reference (default 16)");
  app.add_option("--set", o->sets, "override a scene key for every scene, KEY=VALUE (repeatable)");
  add_render_flags(app, &o->flags, 0);
  app.add_option("--json", o->json, "also write the table as JSON");
  app.add_option("--mpi", o->mpi,
                 "instead: mpirun -np N iaa render (IAA, --threads per process, 1 by default) "
                 "against one process with N times the threads: times, load balance, same image");
  app.footer(
      "Examples:\n"
      "  iaa bench render\n"
      "  iaa bench render --all --runs 5 --json all.json\n"
      "  iaa bench render --scenes teardrop --size 250 --runs 5 --json bench.json\n"
      "  iaa bench render --scene-dir my/scenes --scenes a b --size 100\n"
      "  iaa bench render --set render.depth_tolerance=2 --set render.estimator_threshold=0.3\n"
      "  iaa bench render --mpi 2 --threads 1 --runs 5\n"
      "  iaa bench render --mpi 8 --runs 1 --json balance.json   # --oversubscribe on 2 cores\n"
      "With --mpi the render flags are not passed on: use --set render.KEY=VALUE.");
  app.callback([o] { run(*o); });
}

BenchRegistrar reg{
    {"render", "IAA vs adaptive and point sampling on the paper's scenes (time, evals, quality)",
     setup}};

}  // namespace
}  // namespace iaa::cli
