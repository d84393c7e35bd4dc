// The bundled scenes of data/scenes, loaded for tests exactly as the tools load them
// (app::load_scene: the file read, `key=value` overrides applied to its TOML, then parsed).
#pragma once

#include <string>
#include <vector>

#include "app/scene_loading.h"

namespace iaa::test {

/// The path of data/scenes/NAME.toml in the source tree.
inline std::string bundled_scene_path(const std::string& name) {
  return std::string(IAA_SOURCE_DIR) + "/data/scenes/" + name + ".toml";
}

/// The bundled scene NAME with the overrides ("image.width=40", "render.shadows=true", ...).
inline Scene bundled_scene(const std::string& name,
                           const std::vector<std::string>& overrides = {}) {
  return app::load_scene(bundled_scene_path(name), overrides);
}

/// The overrides that set the image to size x size pixels.
inline std::vector<std::string> image_size(int size) {
  return {"image.width=" + std::to_string(size), "image.height=" + std::to_string(size)};
}

}  // namespace iaa::test
