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
#include "render/settings.h"

namespace iaa {

/// Pinhole camera, right-handed; vertical field of view in degrees.
struct Camera {
  /// Limits of the vertical field of view in degrees (docs/scene-format.md): above 0, so that the
  /// image plane has a size, and below 180.
  static constexpr double kMinFovDeg = 1e-3;
  static constexpr double kMaxFovDeg = 179.0;
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
  std::string name;                  ///< from the file name or the `name` key
  std::string expression;            ///< the surface f(x,y,z), as written
  Params params;                     ///< named parameters of the expression
  std::shared_ptr<const Tape> tape;  ///< compiled expression
  Box3 bounds;                       ///< nothing outside exists
  Camera camera;
  int width = 500, height = 500;
  Vec3 background{1, 1, 1};
  Material material;
  std::vector<PointLight> lights;
  /// Render settings the scene asks for ([render] table; `shadows` lives here). Command-line
  /// options override them.
  RenderSettings settings;
};

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
