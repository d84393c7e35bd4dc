// Shared helpers of the render tests: scenes from text or from data/scenes at small sizes.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "io/scene_toml.h"
#include "test_scenes.h"

namespace iaa::test {

/// A sphere of radius r at the origin seen from (0, 0, dist) with the given fov.
inline std::string sphere_scene(double r, double dist, double fov, int size) {
  std::ostringstream s;
  s << "[surface]\nexpression = \"x^2 + y^2 + z^2 - r^2\"\nparams = { r = " << r
    << " }\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
    << "[camera]\neye = [0, 0, " << dist << "]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov = " << fov
    << "\n[image]\nwidth = " << size << "\nheight = " << size << "\n";
  return s.str();
}

inline Scene parse(const std::string& text) {
  return parse_scene(text, "test.toml");
}

/// A bundled scene at a small size.
inline Scene bundled(const std::string& name, int size) {
  return bundled_scene(name, image_size(size));
}

}  // namespace iaa::test
