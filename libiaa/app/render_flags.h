// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// The render options a user gives on top of a scene (the flags of `iaa render`, `iaa inspect` and
// `iaa bench render`; the keyword arguments of the Python module's render()): method, subdivision
// levels, thresholds, depth tolerance, shadows, pixel window and image size. An option overrides
// the scene's [render] (or [image]) table only when it is given; the scene's own values stay
// otherwise. Errors name the option by its command-line spelling (--window, --max-level, ...).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "scene/settings.h"

namespace iaa::app {

/// The render options as given; unset values mark options that were not given.
struct RenderFlags {
  /// Marks an integer option that was not given.
  static constexpr int kUnset = -2147483647;

  std::string method;
  int max_level = -1;
  double threshold = -1, depth_tol = -1, adaptive_threshold = -1;
  int width = kUnset, height = kUnset;
  std::string window;
  bool no_shadows = false, shadows = false;
};

/// `sets` (the `--set KEY=VALUE` overrides) followed by --width and --height as overrides of
/// image.width and image.height, so that the scene loader checks them like keys of the file.
std::vector<std::string> with_image_size(const RenderFlags& flags, std::vector<std::string> sets);

/// Overrides the settings (a scene's) with the options that were given, then validates them.
/// Throws iaa::Error naming the option (SettingError for a value out of its range).
void apply_render_flags(const RenderFlags& flags, RenderSettings* settings);

/// The settings as the JSON reports of `iaa render` and `iaa inspect` write them.
nlohmann::json render_settings_json(const RenderSettings& settings);

}  // namespace iaa::app
