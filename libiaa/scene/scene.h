// A scene: the surface and its bounding box, the camera, the lights, the material and the
// render settings it asks for. Everything that renders, encloses or meshes reads a Scene; io/
// builds one from a TOML file (io/scene_toml.h) and a caller may build one by hand.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/vec.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "scene/camera.h"
#include "scene/settings.h"

namespace iaa {

/// Phong material.
struct Material {
  Vec3 color{0.85, 0.55, 0.3};
  double ambient = 0.12;
  double diffuse = 0.75;
  double specular = 0.35;
  double shininess = 40.0;
};

/// A point light; its contribution does not fall off with distance.
struct PointLight {
  Vec3 position{3, 4, 5};
  Vec3 color{1, 1, 1};  ///< intensity per channel
};

/// A complete scene. `tape` is compiled from `expression` and `params`; `bounds` is the box
/// outside of which nothing exists (docs/design.md, "Conventions").
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

/// Throws iaa::Error when f is proved undefined (NaN) at every point of `bounds`, where it can
/// show nothing (an empty picture). parse_scene calls it on a scene's bounds. Only a proof rejects
/// a surface; one defined anywhere, or one for which no proof is found within a fixed budget of
/// evaluations (a few milliseconds), is accepted. The message names neither file nor key: the
/// caller knows where the surface came from and adds that.
void validate_surface(const Tape& tape, const Box3& bounds);

}  // namespace iaa
