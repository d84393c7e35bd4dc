#include "scene/settings.h"

#include <cctype>
#include <string>

#include "core/error.h"

namespace iaa {

std::string_view method_name(RenderMethod m) {
  switch (m) {
    case RenderMethod::kIaa:
      return "iaa";
    case RenderMethod::kPoint:
      return "point";
    case RenderMethod::kGrid:
      return "grid";
    case RenderMethod::kAdaptive:
      return "adaptive";
  }
  return "?";
}

RenderMethod parse_method(std::string_view text, int* grid_n) {
  std::string t;
  for (char c : text) {
    if (c != ' ') t.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  if (t == "iaa") return RenderMethod::kIaa;
  if (t == "point") return RenderMethod::kPoint;
  if (t == "adaptive") return RenderMethod::kAdaptive;
  if (t.rfind("grid", 0) == 0) {
    const std::string n = t.substr(4);
    if (!n.empty()) {
      int v = 0;
      for (char c : n) {
        if (!std::isdigit(static_cast<unsigned char>(c)) || v > 1000) {
          throw SettingError("method: 'grid N' needs an integer N in [1, " +
                             std::to_string(RenderSettings::kMaxGrid) + "], got '" +
                             std::string(text) + "'");
        }
        v = v * 10 + (c - '0');
      }
      if (v < 1 || v > RenderSettings::kMaxGrid) {
        throw SettingError("method: grid N must be in [1, " +
                           std::to_string(RenderSettings::kMaxGrid) + "], got " +
                           std::to_string(v));
      }
      if (grid_n) *grid_n = v;
    }
    return RenderMethod::kGrid;
  }
  throw SettingError("method: unknown method '" + std::string(text) +
                     "' (expected iaa, point, grid N or adaptive)");
}

void RenderSettings::validate() const {
  if (grid_n < 1 || grid_n > kMaxGrid) {
    throw SettingError("grid: N must be in [1, " + std::to_string(kMaxGrid) + "], got " +
                       std::to_string(grid_n));
  }
  if (max_level < 0 || max_level > kMaxLevel) {
    throw SettingError("max_level must be in [0, " + std::to_string(kMaxLevel) + "], got " +
                       std::to_string(max_level));
  }
  if (!(estimator_threshold >= 0.0 && estimator_threshold <= 2.0)) {
    throw SettingError("estimator_threshold must be in [0, 2], got " +
                       std::to_string(estimator_threshold));
  }
  if (!(depth_tolerance >= kMinDepthTolerance && depth_tolerance <= kMaxDepthTolerance)) {
    throw SettingError("depth_tolerance must be in [0.001, 1000], got " +
                       std::to_string(depth_tolerance));
  }
  if (!(adaptive_threshold >= 0.0 && adaptive_threshold <= 1.0)) {
    throw SettingError("adaptive_threshold must be in [0, 1], got " +
                       std::to_string(adaptive_threshold));
  }
}

void RenderSettings::validate_window(int width, int height) const {
  if (window.x0 == 0 && window.y0 == 0 && window.x1 == 0 && window.y1 == 0) return;  // all
  const auto w = [&] {
    return std::to_string(window.x0) + "," + std::to_string(window.y0) + "," +
           std::to_string(window.x1) + "," + std::to_string(window.y1);
  };
  if (window.x0 < 0 || window.y0 < 0 || window.x1 > width || window.y1 > height || window.empty()) {
    throw SettingError("window " + w() + " must satisfy 0 <= X0 < X1 <= " + std::to_string(width) +
                       " and 0 <= Y0 < Y1 <= " + std::to_string(height) + " (the image is " +
                       std::to_string(width) + "x" + std::to_string(height) + ")");
  }
}

}  // namespace iaa
