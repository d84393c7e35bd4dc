#include "iaa/scene_loading.h"

#include "common/files.h"
#include "core/error.h"
#include "io/scene_toml.h"

namespace iaa::cli {

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::vector<SceneOverride> ov;
  ov.reserve(overrides.size());
  for (const std::string& o : overrides) ov.push_back(parse_override(o));
  const std::string text = tools::read_file(path);
  return parse_scene(text, path, ov);
}

void add_scene_options(CLI::App& app, std::string* path, std::vector<std::string>* overrides) {
  app.add_option("scene", *path, "scene file (TOML, see docs/scene-format.md)")->required();
  app.add_option("--set", *overrides,
                 "override a scene key, KEY=VALUE with a dotted key (repeatable), e.g. "
                 "camera.fov=30, image.width=200, surface.params.r=0.4");
}

}  // namespace iaa::cli
