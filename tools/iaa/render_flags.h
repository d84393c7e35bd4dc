// The render flags that `iaa render`, `iaa inspect` and `iaa bench render` share: the options that
// map to RenderSettings (method, subdivision levels, thresholds, depth tolerance, shadows, pixel
// window) and the image size. A flag overrides the scene's [render] (or [image]) table only when
// it is given; the scene's own values stay otherwise.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "scene/settings.h"

namespace iaa::cli {

/// The render flags as given on the command line; unset values mark flags that were not given.
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

/// Flags a command may leave out of the group; the levels, thresholds and shadows are always in.
/// `iaa bench render` chooses the methods and the image size itself and renders whole images.
enum RenderFlagParts : unsigned {
  kMethodFlag = 1u << 0,      ///< --method
  kImageSizeFlags = 1u << 1,  ///< --width, --height
  kWindowFlag = 1u << 2,      ///< --window
};

/// Adds the render flags (those of `parts` and the ones always in) to a command or subcommand.
void add_render_flags(CLI::App& app, RenderFlags* flags, unsigned parts);

/// `sets` (the `--set KEY=VALUE` overrides) followed by --width and --height as overrides of
/// image.width and image.height, so that the scene loader checks them like keys of the file.
std::vector<std::string> with_image_size(const RenderFlags& flags, std::vector<std::string> sets);

/// Overrides the settings (a scene's) with the flags that were given, then validates them.
/// Throws iaa::Error naming the flag (SettingError for a value out of its range).
void apply_render_flags(const RenderFlags& flags, RenderSettings* settings);

/// The settings as the JSON reports of `iaa render` and `iaa inspect` write them.
nlohmann::json render_settings_json(const RenderSettings& settings);

}  // namespace iaa::cli
