// The override-aware scene loader (scene_loading.h). Application layer: used by tools/ and viz/,
// never by the library modules.
#include "app/scene_loading.h"

#include "app/files.h"

namespace iaa::app {

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::vector<SceneOverride> parsed;
  parsed.reserve(overrides.size());
  for (const std::string& o : overrides) parsed.push_back(parse_override(o));
  return parse_scene(read_file(path), path, parsed);
}

}  // namespace iaa::app
