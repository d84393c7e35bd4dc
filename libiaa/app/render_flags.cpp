// The render options shared by render, inspect, bench render and the Python module
// (render_flags.h).
#include "app/render_flags.h"

#include <sstream>

#include "core/error.h"

namespace iaa::app {
namespace {

/// Parses --window X0,Y0,X1,Y1 (X1, Y1 exclusive).
PixelWindow parse_window(const std::string& text) {
  std::stringstream ss(text);
  std::string item;
  std::vector<int> v;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    long x = 0;
    try {
      x = std::stol(item, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != item.size() || x < 0 || x > 1000000) {
      throw Error("--window: '" + item + "' is not a pixel coordinate (expected X0,Y0,X1,Y1)");
    }
    v.push_back(static_cast<int>(x));
  }
  if (v.size() != 4)
    throw Error("--window: expected four integers X0,Y0,X1,Y1, got '" + text + "'");
  return {v[0], v[1], v[2], v[3]};
}

}  // namespace

std::vector<std::string> with_image_size(const RenderFlags& f, std::vector<std::string> sets) {
  if (f.width) sets.push_back("image.width=" + std::to_string(*f.width));
  if (f.height) sets.push_back("image.height=" + std::to_string(*f.height));
  return sets;
}

void apply_render_flags(const RenderFlags& f, RenderSettings* st) {
  if (!f.method.empty()) st->method = parse_method(f.method, &st->grid_n);
  if (f.max_level) st->max_level = *f.max_level;
  if (f.threshold) st->estimator_threshold = *f.threshold;
  if (f.depth_tol) st->depth_tolerance = *f.depth_tol;
  if (f.adaptive_threshold) st->adaptive_threshold = *f.adaptive_threshold;
  if (f.no_shadows) st->shadows = false;
  if (f.shadows) st->shadows = true;
  if (!f.window.empty()) st->window = parse_window(f.window);
  st->validate();
}

nlohmann::json render_settings_json(const RenderSettings& st) {
  return {{"method", std::string(method_name(st.method))},
          {"grid", st.grid_n},
          {"max_level", st.max_level},
          {"estimator_threshold", st.estimator_threshold},
          {"depth_tolerance", st.depth_tolerance},
          {"adaptive_threshold", st.adaptive_threshold},
          {"shadows", st.shadows}};
}

}  // namespace iaa::app
