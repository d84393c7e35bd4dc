// The image, AOVs and report of a render (render_output.h).
#include "app/render_output.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "app/balance.h"
#include "app/render_flags.h"

namespace iaa::app {
namespace {

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
Image8 heat_map(const Film& f, const std::vector<std::uint32_t>& v) {
  Image8 img(f.width, f.height, 3);
  const std::uint32_t mx = v.empty() ? 0 : *std::max_element(v.begin(), v.end());
  const double scale = mx > 0 ? 1.0 / std::log1p(double(mx)) : 0.0;
  tbb::parallel_for(0, f.height, [&](int y) {
    for (int x = 0; x < f.width; ++x) {
      const double t = std::log1p(double(v[f.index(x, y)])) * scale;
      std::uint8_t* p = img.at(x, y);
      p[0] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t, 0.0, 1.0)));
      p[1] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t - 1, 0.0, 1.0)));
      p[2] = static_cast<std::uint8_t>(std::lround(255 * std::clamp(3 * t - 2, 0.0, 1.0)));
    }
  });
  return img;
}

}  // namespace

Image8 color_image(const Film& f) {
  Image8 img(f.width, f.height, 3);
  tbb::parallel_for(0, f.height, [&](int y) {  // rows apart: the same bytes in any order
    for (int x = 0; x < f.width; ++x) {
      const Rgb& c = f.at(x, y);
      std::uint8_t* p = img.at(x, y);
      p[0] = to_byte(c.r);
      p[1] = to_byte(c.g);
      p[2] = to_byte(c.b);
    }
  });
  return img;
}

std::vector<std::pair<std::string, Image8>> aov_images(const Film& film) {
  Image8 cert(film.width, film.height, 3);
  Image8 cov(film.width, film.height, 3);
  for (int y = 0; y < film.height; ++y) {
    for (int x = 0; x < film.width; ++x) {
      certificate_color(film.cert(x, y), cert.at(x, y));
      const std::uint8_t c =
          static_cast<std::uint8_t>(std::lround(255 * film.coverage[film.index(x, y)]));
      std::uint8_t* p = cov.at(x, y);
      p[0] = p[1] = p[2] = c;
    }
  }
  std::vector<std::pair<std::string, Image8>> out;
  out.emplace_back("certificate.png", std::move(cert));
  out.emplace_back("coverage.png", std::move(cov));
  out.emplace_back("leaves.png", heat_map(film, film.leaves));
  out.emplace_back("evals.png", heat_map(film, film.evals));
  return out;
}

void write_aovs(const Film& film, const std::string& dir) {
  for (const auto& [name, image] : aov_images(film)) write_png(dir + "/" + name, image);
}

nlohmann::json render_report_json(const Scene& scene, const Film& f, int threads) {
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
  if (!f.balance.ranks.empty()) j["mpi"] = balance_json(f.balance);
  return j;
}

}  // namespace iaa::app
