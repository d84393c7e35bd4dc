// Where the benchmarks find the bundled scenes (data/scenes), whose surfaces they measure.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace iaa::cli {

/// The directory of the scene files: `given` when not empty (it must be a directory), else
/// data/scenes in the working directory, else data/scenes in an ancestor of the executable's
/// directory (build/bin). Throws iaa::Error when there is none.
std::string find_scene_dir(const std::string& given);

/// Adds the `--scene-dir DIR` option that find_scene_dir reads, with its help text.
void add_scene_dir_option(CLI::App& app, std::string* dir);

}  // namespace iaa::cli
