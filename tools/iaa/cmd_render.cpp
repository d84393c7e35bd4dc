// `iaa render`: renders a scene with IAA or a point-sampled baseline and writes the image, and on
// request the per-pixel certificate, sample and coverage images and a JSON report.
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/balance.h"
#include "app/files.h"
#include "app/png.h"
#include "app/progress_bar.h"
#include "app/render_output.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "dist/world.h"
#include "iaa/command.h"
#include "iaa/command_spread.h"
#include "iaa/render_flags.h"
#include "render/render.h"

namespace iaa::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string out;
  RenderFlags flags;
  int threads = 0;
  std::string aov;
  std::string report;
  bool quiet = false;
};

/// The summary on stdout: time, certificates, evaluations and what was written.
void print_summary(const RenderOptions& o, const Scene& scene, const Film& film, int threads) {
  const FilmStats& s = film.stats;
  const double px = s.pixels ? double(s.pixels) : 1.0;
  std::printf("%s: %dx%d, method %s, %.3f s on %d threads\n", scene.name.c_str(), film.width,
              film.height, std::string(method_name(film.settings.method)).c_str(), film.seconds,
              threads);
  std::printf(
      "  pixels: %llu certified empty, %llu certified covered, %llu uncertain; covered fraction "
      "%.4f\n",
      (unsigned long long)s.empty, (unsigned long long)s.covered, (unsigned long long)s.uncertain,
      s.covered_area / px);
  std::printf(
      "  interval evaluations: %.1f per pixel (%llu on screen blocks); leaves: %.2f per pixel\n",
      double(s.evals) / px, (unsigned long long)s.block_evals, double(s.leaves) / px);
  if (!film.balance.ranks.empty())
    std::printf("  MPI: %s\n", app::balance_summary(film.balance).c_str());
  std::printf("  wrote %s%s%s\n", o.out.c_str(),
              o.aov.empty() ? "" : (", AOVs in " + o.aov).c_str(),
              o.report.empty() ? "" : (", report " + o.report).c_str());
}

void run(const RenderOptions& o) {
  const Scene scene = app::load_scene(o.scene, with_image_size(o.flags, o.sets));
  RenderSettings st = scene.settings;
  apply_render_flags(o.flags, &st);
  st.validate_window(scene.width, scene.height);
  if (o.threads < 0 || o.threads > 1024)
    throw SettingError("--threads must be in [0, 1024] (0 = all cores)");
  if (app::extension_of(o.out) != "png")
    throw Error("-o: the image must be a .png file, got '" + o.out + "'");
  // Under mpirun every process renders a share and holds the whole film; the lead writes.
  dist::World* world = dist::World::current();
  const bool lead = !world || world->lead();
  if (lead && !o.aov.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.aov, ec);
    if (ec) throw Error("--aov: cannot create directory '" + o.aov + "': " + ec.message());
  }
  if (world) {
    // Under mpirun the outputs are checked before the work, so that every process learns of a
    // bad one at the agreement rather than wait for the lead to fail after it.
    if (lead) {
      app::check_writable(o.out, "-o: ");
      if (!o.report.empty()) app::check_writable(o.report, "--report: ");
    }
    world->agree_input();
  }

  app::ProgressBar bar(o.quiet || !lead);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const std::unique_ptr<Spread> spread = command_spread(world);
  exec.spread = spread.get();
  const Film film = render(scene, st, exec);
  // Every process finished its share: only then does the lead write.
  if (world) world->agree_done();
  if (!lead) return;

  exec.run([&] {  // the image's conversion and compression in --threads threads too
    app::write_png(o.out, app::color_image(film));
    if (!o.aov.empty()) app::write_aovs(film, o.aov);
  });
  const nlohmann::json rep = app::render_report_json(scene, film, exec.resolved_threads());
  if (!o.report.empty()) app::write_text_atomically(o.report, rep.dump(2) + "\n");
  if (!o.quiet) print_summary(o, scene, film, exec.resolved_threads());
}

void setup(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  add_scene_options(app, &o->scene, &o->sets);
  app.add_option("-o,--output", o->out, "output image (.png)")->required();
  add_render_flags(app, &o->flags, kMethodFlag | kImageSizeFlags | kWindowFlag);
  app.add_option("--threads", o->threads,
                 "worker threads (0 = all cores; per process under mpirun); the image does not "
                 "depend on it");
  app.add_option(
      "--aov", o->aov,
      "write certificate.png, coverage.png, leaves.png and evals.png into this directory");
  app.add_option("--report", o->report, "write a JSON report (settings, time, counts)");
  app.add_flag("-q,--quiet", o->quiet, "print nothing, draw no progress bar");
  app.footer(
      "Examples:\n"
      "  iaa render data/scenes/teardrop.toml -o teardrop.png\n"
      "  iaa render data/scenes/teardrop.toml -o point.png --method point\n"
      "  iaa render data/scenes/chubs.toml -o chubs.png --aov chubs-aov --report chubs.json\n"
      "  iaa render data/scenes/twist.toml -o twist.png --no-shadows --width 200 --height 200\n"
      "  iaa render data/scenes/teardrop.toml -o neck.png --window 200,200,300,260 --method 'grid "
      "16'\n"
      "  iaa render data/scenes/blobby.toml -o b.png --set camera.fov=30 --set render.max_level=3\n"
      "  mpirun -np 4 iaa render data/scenes/chubs.toml -o chubs.png --threads 1 --report r.json\n"
      "Under mpirun the processes share the image's 32x32 blocks; the outputs are the same bytes\n"
      "as one process's, the report adds the load balance (docs/distributed.md).\n"
      "Certificate colours: light grey = certified empty, green = certified covered, orange =\n"
      "uncertain (shaded conservatively). See docs/render.md.");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{
    {"render", "render a scene: IAA (certified) or point/grid/adaptive sampling", 20, setup, true}};

}  // namespace
}  // namespace iaa::cli
