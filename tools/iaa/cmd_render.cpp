// `iaa render`: renders a scene with IAA or a point-sampled baseline and writes the image, and on
// request the per-pixel certificate, sample and coverage images and a JSON report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/files.h"
#include "app/png.h"
#include "app/progress_bar.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "iaa/command.h"
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

// ---- AOV images -----------------------------------------------------------------------------

/// The three certificate colours (and grey outside the window).
void certificate_color(PixelCertificate c, std::uint8_t* p) {
  static const std::uint8_t kColors[4][3] = {
      {235, 235, 235},  // empty: light grey
      {30, 150, 60},    // covered: green
      {235, 110, 20},   // uncertain: orange
      {128, 128, 128},  // not rendered
  };
  const auto& k = kColors[static_cast<int>(c)];
  p[0] = k[0];
  p[1] = k[1];
  p[2] = k[2];
}

/// Heat map (black, red, yellow, white) of a count on a log scale up to the image's maximum.
app::Image8 heat_map(const Film& f, const std::vector<std::uint32_t>& v) {
  app::Image8 img(f.width, f.height, 3);
  const std::uint32_t mx = v.empty() ? 0 : *std::max_element(v.begin(), v.end());
  const double scale = mx > 0 ? 1.0 / std::log1p(double(mx)) : 0.0;
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const double t = std::log1p(double(v[f.index(x, y)])) * scale;
      std::uint8_t* p = img.at(x, y);
      p[0] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t, 0.0, 1.0)));
      p[1] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t - 1, 0.0, 1.0)));
      p[2] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t - 2, 0.0, 1.0)));
    }
  }
  return img;
}

app::Image8 color_image(const Film& f) {
  app::Image8 img(f.width, f.height, 3);
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const Rgb& c = f.at(x, y);
      std::uint8_t* p = img.at(x, y);
      p[0] = app::to_byte(c.r);
      p[1] = app::to_byte(c.g);
      p[2] = app::to_byte(c.b);
    }
  }
  return img;
}

nlohmann::json report_json(const Scene& scene, const Film& f, int threads) {
  nlohmann::json j;
  j["scene"] = scene.name;
  j["width"] = f.width;
  j["height"] = f.height;
  j["window"] = {f.window.x0, f.window.y0, f.window.x1, f.window.y1};
  j["settings"] = render_settings_json(f.settings);
  j["threads"] = threads;
  j["seconds"] = f.seconds;
  const double px = f.stats.pixels ? double(f.stats.pixels) : 1.0;
  j["pixels"] = {{"rendered", f.stats.pixels},
                 {"certified_empty", f.stats.empty},
                 {"certified_covered", f.stats.covered},
                 {"uncertain", f.stats.uncertain}};
  j["evaluations"] = {{"total", f.stats.evals},
                      {"screen_blocks", f.stats.block_evals},
                      {"pruned", f.stats.pruned_evals},
                      {"per_pixel", double(f.stats.evals) / px}};
  j["leaves"] = {{"total", f.stats.leaves}, {"per_pixel", double(f.stats.leaves) / px}};
  j["covered_fraction"] = f.stats.covered_area / px;
  return j;
}

/// The certificate, coverage, leaves and evaluations images, written into directory `dir`.
void write_aovs(const Film& film, const std::string& dir) {
  app::Image8 cert(film.width, film.height, 3);
  app::Image8 cov(film.width, film.height, 3);
  for (int y = 0; y < film.height; ++y) {
    for (int x = 0; x < film.width; ++x) {
      certificate_color(film.cert(x, y), cert.at(x, y));
      const std::uint8_t c =
          static_cast<std::uint8_t>(std::lround(255 * film.coverage[film.index(x, y)]));
      std::uint8_t* p = cov.at(x, y);
      p[0] = p[1] = p[2] = c;
    }
  }
  const std::string d = dir + "/";
  app::write_png(d + "certificate.png", cert);
  app::write_png(d + "coverage.png", cov);
  app::write_png(d + "leaves.png", heat_map(film, film.leaves));
  app::write_png(d + "evals.png", heat_map(film, film.evals));
}

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
  if (!o.aov.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.aov, ec);
    if (ec) throw Error("--aov: cannot create directory '" + o.aov + "': " + ec.message());
  }

  app::ProgressBar bar(o.quiet);
  Exec exec;
  exec.threads = o.threads;
  exec.progress = &bar;
  const Film film = render(scene, st, exec);

  app::write_png(o.out, color_image(film));
  if (!o.aov.empty()) write_aovs(film, o.aov);
  const nlohmann::json rep = report_json(scene, film, exec.resolved_threads());
  if (!o.report.empty()) app::write_text_atomically(o.report, rep.dump(2) + "\n");
  if (!o.quiet) print_summary(o, scene, film, exec.resolved_threads());
}

void setup(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  add_scene_options(app, &o->scene, &o->sets);
  app.add_option("-o,--output", o->out, "output image (.png)")->required();
  add_render_flags(app, &o->flags, kMethodFlag | kImageSizeFlags | kWindowFlag);
  app.add_option("--threads", o->threads,
                 "worker threads (0 = all cores); the image does not depend on it");
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
      "Certificate colours: light grey = certified empty, green = certified covered, orange =\n"
      "uncertain (shaded conservatively). See docs/render.md.");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{
    {"render", "render a scene: IAA (certified) or point/grid/adaptive sampling", 20, setup}};

}  // namespace
}  // namespace iaa::cli
