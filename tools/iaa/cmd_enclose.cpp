// `iaa enclose`: the guaranteed enclosure octree of a surface (libiaa/enclose/octree.h), written
// as a .vtu of voxels (viz/enclosure_vtk.h) and summarised on stdout and in a JSON report.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/balance.h"
#include "app/enclosing.h"
#include "app/files.h"
#include "app/progress_bar.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "dist/world.h"
#include "enclose/octree.h"
#include "expr/tape.h"
#include "iaa/command.h"
#include "iaa/command_spread.h"
#ifdef IAA_HAVE_VIZ
#include "iaa/viz_plugin.h"
#endif

namespace iaa::cli {
namespace {

struct EncloseOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string expr;
  std::string bounds;
  std::vector<std::string> params;
  app::OctreeOptions octree;
  std::string output;
  std::string report;
  int threads = 0;
  bool quiet = false;
};

/// The shortest text that reads back as exactly v.
std::string fmt(double v) {
  char b[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  return b;
}
/// Parses X0:X1,Y0:Y1,Z0:Z1 (command.h's parse_box); an empty range is an error too, since a box
/// to enclose in must have volume.
Box3 parse_bounds(const std::string& text) {
  static const char* kAxis[3] = {"x", "y", "z"};
  const Box3 box = parse_box(text, "--bounds");
  for (int i = 0; i < 3; ++i) {
    if (box.lo[i] == box.hi[i]) {
      throw Error(std::string("--bounds: the ") + kAxis[i] + " range " + fmt(box.lo[i]) + ":" +
                  fmt(box.hi[i]) + " is empty; write LO:HI with LO < HI");
    }
  }
  return box;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Everything that can be checked before the surface is read: which inputs were given, the
/// thread count, and the outputs, so that a command fails before its work rather than after it.
void check_options(const EncloseOptions& o) {
  if (o.scene.empty() && o.expr.empty()) {
    throw Error("no surface: give a SCENE file or --expr EXPR --bounds X0:X1,Y0:Y1,Z0:Z1");
  }
  if (!o.scene.empty() && !o.expr.empty()) {
    throw Error(
        "give either a SCENE file or --expr, not both (use --set surface.expression=... to change "
        "a scene's)");
  }
  if (o.scene.empty() && !o.sets.empty()) throw Error("--set needs a SCENE file");
  if (!o.scene.empty() && !o.params.empty()) {
    throw Error(
        "--param is for --expr; change a scene's parameters with --set surface.params.NAME=VALUE");
  }
  app::check_octree_options(o.octree);
  if (o.scene.empty() && o.bounds.empty()) {
    throw Error("--bounds X0:X1,Y0:Y1,Z0:Z1 is required with --expr");
  }
  if (o.threads < 0) {
    throw SettingError("--threads must be 0 (all) or more, got " + std::to_string(o.threads));
  }
#ifndef IAA_HAVE_VIZ
  if (!o.output.empty()) {
    throw Error("-o: this iaa was built without VTK (IAA_WITH_VTK=OFF); no .vtu output");
  }
#endif
  if (!o.output.empty() && app::extension_of(o.output) != "vtu" &&
      app::extension_of(o.output) != "pvtu") {
    throw Error("-o: the output must be a .vtu or .pvtu file, got '" + o.output + "'");
  }
  for (const std::string* out : {&o.output, &o.report}) {
    if (!out->empty()) app::check_writable(*out);
  }
#ifdef IAA_HAVE_VIZ
  if (!o.output.empty()) viz_plugin("-o");  // a missing plugin is said before the work
#endif
}

/// The surface to enclose and the box to enclose it in.
struct Surface {
  std::string expression;
  std::shared_ptr<const Tape> tape;
  Box3 bounds;
};

/// Reads the surface from the scene file (with its --set overrides) or from --expr and --param;
/// --bounds, when given, replaces a scene's bounds.
Surface load_surface(const EncloseOptions& o) {
  Surface surface;
  if (!o.scene.empty()) {
    const Scene scene = app::load_scene(o.scene, o.sets);
    surface.expression = scene.expression;
    surface.tape = scene.tape;
    surface.bounds = o.bounds.empty() ? scene.bounds : parse_bounds(o.bounds);
  } else {
    surface.expression = o.expr;
    surface.tape = std::make_shared<const Tape>(Tape::parse(o.expr, parse_params(o.params)));
    surface.bounds = parse_bounds(o.bounds);
  }
  // As a scene file's surface is checked, and again when --bounds replaced the scene's bounds.
  validate_surface(*surface.tape, surface.bounds);
  return surface;
}

#ifdef IAA_HAVE_VIZ
/// Writes the boxes to `path` atomically (in `exec`'s threads); returns the seconds it took.
double write_vtu(const std::string& path, const Surface& surface, const EncloseSettings& s,
                 const Enclosure& enc, const Exec& exec, app::ProgressBar* bar) {
  const auto t0 = std::chrono::steady_clock::now();
  app::write_atomically(path, [&](const std::string& tmp) {
    exec.run([&] {
      viz_plugin("-o").write_enclosure_vtu(tmp, enc, viz::EnclosureInfo{surface.expression, s},
                                           bar);
    });
  });
  return seconds_since(t0);
}

/// Writes the boxes as a .pvtu and one .vtu piece per process (viz/enclosure_pvtu.h), in a
/// temporary directory beside `path` that the lead then empties into place, the .pvtu last: a
/// failed run leaves no file, and the .pvtu never names a missing piece. Every process calls it
/// (it agrees with the others twice); returns the seconds it took.
double write_pvtu(const std::string& path, const Surface& surface, const EncloseSettings& s,
                  const Enclosure& enc, dist::World* world) {
  namespace fs = std::filesystem;
  const auto t0 = std::chrono::steady_clock::now();
  const int pieces = world ? world->size() : 1, piece = world ? world->rank() : 0;
  const bool lead = piece == 0;
  const fs::path target(path);
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".parts");
  // Runs step() on this process, then learns whether it went well on every process; an error
  // stops all of them (each one that failed says why, the others say where).
  const auto step = [&](const std::function<void()>& f, const std::string& where) {
    std::string error;
    try {
      f();
    } catch (const Error& e) {
      error = e.what();
    } catch (const fs::filesystem_error& e) {
      error = e.what();
    }
    const bool ok = error.empty();
    const bool all_ok = world ? world->agree(ok).all_ok : ok;
    if (all_ok) return;
    if (lead) {
      std::error_code ec;
      fs::remove_all(tmp, ec);
    }
    throw Error(ok ? "-o: another process failed to write " + where + " of '" + path + "'"
                   : "-o: " + error);
  };
  step(
      [&] {
        if (!lead) return;
        fs::remove_all(tmp);
        fs::create_directory(tmp);
      },
      "the directory for the pieces");
  const std::string tmp_pvtu = (tmp / target.filename()).string();
  step(
      [&] {
        viz_plugin("-o").write_enclosure_pvtu(
            tmp_pvtu, enc, viz::EnclosureInfo{surface.expression, s}, piece, pieces, lead);
      },
      "its piece");
  if (lead) {
    const auto from = viz::pvtu_piece_paths(tmp_pvtu, pieces);
    const auto to = viz::pvtu_piece_paths(path, pieces);
    for (std::size_t k = 0; k < from.size(); ++k) fs::rename(from[k], to[k]);
    fs::rename(tmp_pvtu, path);
    fs::remove(tmp);
  }
  return seconds_since(t0);
}
#endif

/// The summary on stdout: the surface, the settings, the boxes per class (and per depth when
/// possible cells were refined), the evaluations, the time and what was written.
void print_summary(const EncloseOptions& o, const Surface& surface, const EncloseSettings& s,
                   const Enclosure& enc, const app::EncloseTimes& t, int threads) {
  const Vec3 cell = s.bounds.size() / std::ldexp(1.0, s.depth);
  std::printf("expression   %s\n", surface.expression.c_str());
  std::printf("bounds       [%s, %s] x [%s, %s] x [%s, %s]\n", fmt(s.bounds.lo.x).c_str(),
              fmt(s.bounds.hi.x).c_str(), fmt(s.bounds.lo.y).c_str(), fmt(s.bounds.hi.y).c_str(),
              fmt(s.bounds.lo.z).c_str(), fmt(s.bounds.hi.z).c_str());
  std::printf("depth        %d (cells %.4g x %.4g x %.4g)", s.depth, cell.x, cell.y, cell.z);
  if (s.refine_possible)
    std::printf(", possible cells refined up to depth %d", s.depth + s.refine_possible);
  std::printf("\n");
  std::printf("boxes        %llu: %llu crossing (certified surface), %llu possible\n",
              static_cast<unsigned long long>(enc.cells.size()),
              static_cast<unsigned long long>(enc.count(CellClass::kCrossing)),
              static_cast<unsigned long long>(enc.count(CellClass::kPossible)));
  for (std::size_t d = 0; d < enc.counts_by_depth.size(); ++d) {
    const auto& c = enc.counts_by_depth[d];
    if (s.refine_possible && c[0] + c[1] > 0) {
      std::printf("  depth %-3zu  %llu crossing, %llu possible\n", d,
                  static_cast<unsigned long long>(c[0]), static_cast<unsigned long long>(c[1]));
    }
  }
  std::printf(
      "evaluations  %llu cells, %llu points (corners and centres); %llu corner signs from "
      "expansions\n",
      static_cast<unsigned long long>(enc.evaluations),
      static_cast<unsigned long long>(enc.corner_evaluations),
      static_cast<unsigned long long>(enc.expansion_signs));
  std::printf("time         %.3f s enclose", t.enclose);
  if (!o.output.empty()) std::printf(", %.3f s write", t.write);
  std::printf(" (%d threads)\n", threads);
  if (!enc.balance.ranks.empty())
    std::printf("MPI          %s\n", app::balance_summary(enc.balance).c_str());
  if (enc.cells.empty()) {
    std::printf(
        "result       certified empty: 0 is outside F on every cell, so f = 0 has no point "
        "in the bounds\n");
  }
  if (!o.output.empty()) std::printf("wrote        %s\n", o.output.c_str());
}

/// The --report JSON: the same figures as the summary, with the counts of every depth.
void write_report(const EncloseOptions& o, const Surface& surface, const EncloseSettings& s,
                  const Enclosure& enc, const app::EncloseTimes& t, int threads) {
  nlohmann::json j = app::enclose_report_json(surface.expression, s, enc, t, threads);
  if (!o.output.empty()) j["output"] = o.output;
  app::write_text_atomically(o.report, j.dump(2) + "\n");
  std::printf("report       %s\n", o.report.c_str());
}

void run(const EncloseOptions& o) {
  check_options(o);
  const Surface surface = load_surface(o);
  const EncloseSettings s = app::enclose_settings(surface.bounds, o.octree);
  // Under mpirun every process encloses a share of the subtrees and holds the whole enclosure;
  // the lead writes (a .pvtu: every process writes a piece).
  dist::World* world = dist::World::current();
  const bool lead = !world || world->lead();
  if (world) world->agree_input();
  // The bar lives until the end: the .vtu write reports to it as well.
  app::ProgressBar bar(o.quiet || !lead);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const std::unique_ptr<Spread> spread = command_spread(world);
  exec.spread = spread.get();
  app::EncloseTimes t;
  const auto t0 = std::chrono::steady_clock::now();
  const Enclosure enc = app::run_enclose(*surface.tape, s, exec);
  t.enclose = seconds_since(t0);
  // Every process finished its share: only then is anything written.
  if (world) world->agree_done();
#ifdef IAA_HAVE_VIZ
  if (!o.output.empty() && app::extension_of(o.output) == "pvtu") {
    t.write = write_pvtu(o.output, surface, s, enc, world);
  } else if (!o.output.empty() && lead) {
    t.write = write_vtu(o.output, surface, s, enc, exec, &bar);
  }
#endif
  if (!lead) return;
  print_summary(o, surface, s, enc, t, exec.resolved_threads());
  if (!o.report.empty()) write_report(o, surface, s, enc, t, exec.resolved_threads());
}

void setup(CLI::App& app) {
  auto o = std::make_shared<EncloseOptions>();
  app.add_option("scene", o->scene, "a scene file (.toml): its [surface] expression and bounds");
  app.add_option("--set", o->sets,
                 "override a key of the scene, e.g. surface.params.r=0.4 (repeatable)");
  app.add_option("--expr", o->expr,
                 "the surface f(x,y,z) = 0 (instead of a scene), e.g. 'x^2 + y^2 + z^2 - 1'");
  app.add_option("--bounds", o->bounds,
                 "the box X0:X1,Y0:Y1,Z0:Z1 to enclose the surface in (default: the scene's)");
  app.add_option("-p,--param", o->params,
                 "a named parameter NAME=VALUE of the expression (repeatable)");
  CLI::Option* depth = app.add_option("-d,--depth", o->octree.depth,
                                      "leaf depth: cells are the bounds / 2^D per axis (1..21)")
                           ->capture_default_str();
  CLI::Option* cell_size =
      app.add_option("--cell-size", o->octree.cell_size,
                     "choose the depth so that cells are at most this large (instead of --depth)");
  app.add_option(
         "--refine-possible", o->octree.refine_possible,
         "refine possible leaves up to K levels deeper (0..8), to certify or exclude thin features")
      ->capture_default_str();
  app.add_option("--max-boxes", o->octree.max_boxes,
                 "fail (with no output) when more leaves than this are needed")
      ->capture_default_str();
  app.add_option("-o,--output", o->output,
                 "write the boxes as a .vtu (VTK unstructured grid of voxels), or as a .pvtu "
                 "with one .vtu piece per process (BASE_K.vtu beside it)");
  app.add_option("--report", o->report,
                 "write counts per class and depth, evaluations and time as JSON");
  app.add_option("-t,--threads", o->threads,
                 "worker threads (0: all; per process under mpirun); the result does not depend "
                 "on it")
      ->capture_default_str();
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.footer(
      "Every point of f = 0 inside the bounds lies in one of the boxes (outward-rounded interval\n"
      "arithmetic). A 'crossing' box has corners of both strict signs (proved), so the surface\n"
      "certainly passes through it; a 'possible' box could not be decided at that size.\n\n"
      "Examples:\n"
      "  iaa enclose data/scenes/teardrop.toml --depth 7 --refine-possible 3 -o teardrop.vtu\n"
      "  iaa enclose data/scenes/chubs.toml --cell-size 0.01 --report chubs.json -o chubs.vtu\n"
      "  iaa enclose --expr 'x^2 + y^2 + z^2 - r^2' -p r=0.5 --bounds -1:1,-1:1,-1:1 -d 5\n"
      "  mpirun -np 4 iaa enclose data/scenes/chubs.toml -d 9 -t 1 -o chubs.pvtu\n"
      "Under mpirun the processes share the octree's subtrees; the boxes are the same as one\n"
      "process's, the report adds the load balance (docs/distributed.md).");
  app.callback([o, depth, cell_size] {
    o->octree.depth_given = depth->count() > 0;
    o->octree.cell_size_given = cell_size->count() > 0;
    run(*o);
  });
}

CommandRegistrar reg{{"enclose",
                      "boxes that provably contain the whole surface (interval octree, .vtu)", 30,
                      setup, true}};

}  // namespace
}  // namespace iaa::cli
