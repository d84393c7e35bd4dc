// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// The render options a user gives on top of a scene (the flags of `iaa render`, `iaa inspect` and
// `iaa bench render`; the keyword arguments of the Python module's render()): method, subdivision
// levels, thresholds, depth tolerance, shadows, pixel window and image size. An option overrides
// the scene's [render] (or [image]) table only when it is given; the scene's own values stay
// otherwise. Errors name the option by its command-line spelling (--window, --max-level, ...).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "scene/settings.h"

namespace iaa::app {

/// The render options as given; an empty one was not given. Every given value, even an impossible
/// one (a negative level), reaches the checks of the settings and the scene loader, which name the
/// limits: none is taken for "not given".
struct RenderFlags {
  std::string method;
  std::optional<int> max_level;
  std::optional<double> threshold, depth_tol, adaptive_threshold;
  std::optional<int> width, height;
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
