// Loading libiaa_vtk.so (tools/iaa/viz_plugin.h).
#ifdef IAA_HAVE_VIZ

#include "iaa/viz_plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"

#ifndef IAA_VIZ_PLUGIN_RELDIR
#error "IAA_VIZ_PLUGIN_RELDIR (the plugin's directory relative to the installed iaa) is not set"
#endif

namespace iaa::cli {
namespace {

namespace fs = std::filesystem;

/// The outcome of the one attempt to load the plugin.
struct Loaded {
  const viz::PluginApi* api = nullptr;
  std::string error;  ///< why it could not be loaded (api null)
};

/// Where to look, in order: $IAA_VIZ_PLUGIN alone when set; else beside the executable (the build
/// tree) and in the install tree's plugin directory, relative to the executable.
std::vector<fs::path> candidates() {
  if (const char* env = std::getenv("IAA_VIZ_PLUGIN"); env && *env) return {fs::path(env)};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  return {dir / viz::kPluginFile,
          (dir / IAA_VIZ_PLUGIN_RELDIR / viz::kPluginFile).lexically_normal()};
}

/// Opens one file and checks its table; returns null and says why in `why` when it does not fit.
const viz::PluginApi* open(const fs::path& path, std::string* why) {
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = ::dlerror();
    *why = e ? e : "dlopen failed";
    return nullptr;
  }
  using Entry = const viz::PluginApi* (*)();
  const auto entry = reinterpret_cast<Entry>(::dlsym(handle, viz::kPluginEntry));
  const viz::PluginApi* api = entry ? entry() : nullptr;
  if (!api) {
    *why = std::string("it has no ") + viz::kPluginEntry + "()";
  } else if (api->abi != viz::kPluginAbi || api->layout != viz::layout_fingerprint()) {
    *why = "it comes from another build of iaa (plugin interface " + std::to_string(api->abi) +
           ", this iaa's " + std::to_string(viz::kPluginAbi) + ")";
  } else {
    return api;  // kept loaded for the life of the process: its functions are in use
  }
  ::dlclose(handle);
  return nullptr;
}

Loaded load() {
  Loaded out;
  std::string tried;
  for (const fs::path& path : candidates()) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      tried += "\n  " + path.string() + ": no such file";
      continue;
    }
    std::string why;
    if ((out.api = open(path, &why))) return out;
    tried += "\n  " + path.string() + ": " + why;
  }
  out.error = std::string("needs VTK, which iaa loads from its plugin ") + viz::kPluginFile +
              ", and that could not be loaded (set IAA_VIZ_PLUGIN to the file's path):" + tried;
  return out;
}

}  // namespace

const viz::PluginApi& viz_plugin(const std::string& what) {
  static const Loaded loaded = load();
  if (!loaded.api) throw Error(what + " " + loaded.error);
  return *loaded.api;
}

void run_vtk_mesher(const app::meshing::Surface& s, const app::meshing::MeshParams& p,
                    const Exec& exec, app::meshing::MeshRun& run) {
  viz_plugin("--method vtk").run_vtk_mesher(s, p, exec, run);
}

}  // namespace iaa::cli

#endif  // IAA_HAVE_VIZ
