// Loading a scene the same way in every command (render, enclose, mesh, compare, inspect):
// read the file, apply `--set key=value` overrides, parse. Errors name the file and the key.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "scene/scene.h"

namespace iaa::cli {

/// Reads and parses the scene file at `path`, with the overrides ("key=value", e.g.
/// "camera.fov=30", "render.max_level=3", "surface.params.r=0.4") applied to its TOML first.
/// Throws iaa::Error naming the file (and the key) on any problem.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Adds the positional SCENE argument and the repeatable `--set KEY=VALUE` option to a command.
void add_scene_options(CLI::App& app, std::string* path, std::vector<std::string>* overrides);

}  // namespace iaa::cli
