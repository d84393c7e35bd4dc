// The scene directory of the benchmarks (bench_scenes.h).
#include "iaa/bench_scenes.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace iaa::cli {

std::string find_scene_dir(const std::string& given) {
  namespace fs = std::filesystem;
  if (!given.empty()) {
    if (!fs::is_directory(given)) throw SettingError("--scene-dir " + given + ": not a directory");
    return given;
  }
  if (fs::is_directory("data/scenes")) return "data/scenes";
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path()) {
      if (fs::is_directory(p / "data/scenes")) return (p / "data/scenes").string();
    }
  }
  throw Error("cannot find data/scenes; run from the source tree or pass --scene-dir");
}

void add_scene_dir_option(CLI::App& app, std::string* dir) {
  app.add_option("--scene-dir", *dir,
                 "directory of the scene files (default: data/scenes in the working directory, "
                 "else in the source tree above the executable)");
}

}  // namespace iaa::cli
