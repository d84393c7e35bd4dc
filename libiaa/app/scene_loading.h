// Application layer: used by tools/ and viz/, never by the library modules.
// Loading a scene file the same way in every command of iaa and iaa-viz: read the file, apply the
// `--set key=value` overrides to its TOML, parse. Errors name the file and the key.
#pragma once

#include <string>
#include <vector>

#include "io/scene_toml.h"

namespace iaa::app {

/// Reads and parses the scene file at `path`, with the overrides ("key=value", e.g.
/// "camera.fov=30", "render.max_level=3", "surface.params.r=0.4") applied to its TOML first.
/// Throws iaa::Error naming the file (and the key) on any problem; a malformed override is
/// reported before the file is read. When `text` is not null it receives the file's contents
/// (the Python module keeps them, to apply more overrides later).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                 std::string* text = nullptr);

/// Parses "key=value" overrides (parse_override); throws iaa::Error for a malformed one.
std::vector<SceneOverride> parse_overrides(const std::vector<std::string>& overrides);

}  // namespace iaa::app
