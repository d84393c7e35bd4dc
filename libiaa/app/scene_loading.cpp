// The override-aware scene loader (scene_loading.h). Application layer: used by tools/ and viz/,
// never by the library modules.
#include "app/scene_loading.h"

#include "app/files.h"

namespace iaa::app {

std::vector<SceneOverride> parse_overrides(const std::vector<std::string>& overrides) {
  std::vector<SceneOverride> parsed;
  parsed.reserve(overrides.size());
  for (const std::string& o : overrides) parsed.push_back(parse_override(o));
  return parsed;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides,
                 std::string* text) {
  const std::vector<SceneOverride> parsed = parse_overrides(overrides);
  const std::string contents = read_file(path);
  if (text) *text = contents;
  return parse_scene(contents, path, parsed);
}

}  // namespace iaa::app
