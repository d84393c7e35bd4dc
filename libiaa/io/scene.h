// A scene: the surface, its bounding box, the camera, lights, material and render settings.
// Scenes are written in TOML (docs/scene-format.md). The library parses scene *text*; reading the
// file is the tool's job, so the library stays free of I/O.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec.h"
#include "expr/parser.h"
#include "expr/tape.h"

namespace iaa {

/// Pinhole camera, right-handed; vertical field of view in degrees.
struct Camera {
  Vec3 eye{0, 0, 3};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_deg = 40.0;
};

/// Phong material.
struct Material {
  Vec3 color{0.85, 0.55, 0.3};
  double ambient = 0.12;
  double diffuse = 0.75;
  double specular = 0.35;
  double shininess = 40.0;
};

struct PointLight {
  Vec3 position{3, 4, 5};
  Vec3 color{1, 1, 1};  ///< intensity per channel
};

struct Scene {
  std::string name;         ///< from the file name or the `name` key
  std::string expression;   ///< the surface f(x,y,z), as written
  Params params;            ///< named parameters of the expression
  std::shared_ptr<const Tape> tape;  ///< compiled expression
  Box3 bounds;              ///< nothing outside exists
  Camera camera;
  int width = 500, height = 500;
  Vec3 background{1, 1, 1};
  Material material;
  std::vector<PointLight> lights;
  bool shadows = false;
  // Render settings that a scene may set are kept in the renderer's own settings struct; see
  // render/render.h and docs/scene-format.md.
};

/// Parses a scene from TOML text. `source` names the text in error messages (a path).
/// Throws iaa::Error with the key (and line) of anything wrong; unknown keys are errors.
Scene parse_scene(std::string_view toml_text, std::string_view source);

}  // namespace iaa
