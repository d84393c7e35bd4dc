// Where the benchmarks find the bundled scenes (data/scenes), whose surfaces they measure.
#pragma once

#include <string>

namespace iaa::cli {

/// The directory of the scene files: `given` when not empty (it must be a directory), else
/// data/scenes in the working directory, else data/scenes in an ancestor of the executable's
/// directory (build/bin). Throws iaa::Error when there is none.
std::string find_scene_dir(const std::string& given);

}  // namespace iaa::cli
