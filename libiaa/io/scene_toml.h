// Reading a scene from TOML text (docs/scene-format.md) into a Scene (scene/scene.h), with
// `--set key=value` overrides applied before the text is interpreted. The library parses scene
// *text*; reading the file is the caller's job, so the library stays free of I/O.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace iaa {

/// One `--set key=value` override: a dotted key of the scene file (`camera.fov`,
/// `render.max_level`, `surface.params.r`) and a TOML value (`30`, `[0, 1, 2]`, `"iaa"`; a bare
/// word that is not valid TOML is taken as a string).
struct SceneOverride {
  std::string key;
  std::string value;
};

/// Parses "key=value" into a SceneOverride; throws iaa::Error when there is no '='.
SceneOverride parse_override(std::string_view text);

/// Parses a scene from TOML text. `source` names the text in error messages (a path).
/// Throws iaa::Error with the key (and line) of anything wrong; unknown keys are errors.
/// The overrides are applied to the TOML before it is interpreted, so they are checked exactly
/// like keys of the file.
Scene parse_scene(std::string_view toml_text, std::string_view source,
                  const std::vector<SceneOverride>& overrides = {});

}  // namespace iaa
