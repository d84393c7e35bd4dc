// Loading libiaa_vtk.so (tools/iaa/viz_plugin.h).
#ifdef IAA_HAVE_VIZ

#include "iaa/viz_plugin.h"

#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
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

/// The value of IAA_VIZ_PLUGIN, empty when unset.
std::string plugin_variable() {
  const char* env = std::getenv("IAA_VIZ_PLUGIN");
  return env ? env : "";
}

/// Where to look, in order: $IAA_VIZ_PLUGIN alone when set; else beside the executable (the build
/// tree) and in the install tree's plugin directory, relative to the executable. Absolute paths:
/// dlopen searches the library path for a bare name, which is not what was asked for. Empty, with
/// `why` set, when the executable's own path cannot be read.
std::vector<fs::path> candidates(std::string* why) {
  std::error_code ec;
  if (const std::string env = plugin_variable(); !env.empty()) {
    const fs::path p = fs::absolute(env, ec);
    return {ec ? fs::path(env) : p};
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    *why = "\n  /proc/self/exe: " + ec.message() + " (the executable's directory is unknown)";
    return {};
  }
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
  const auto hex = [](std::uint64_t v) {
    char s[19];
    std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(v));
    return std::string(s);
  };
  if (!api) {
    *why = std::string("it has no ") + viz::kPluginEntry + "()";
  } else if (api->abi != viz::kPluginAbi) {
    *why = "it comes from another build of iaa (plugin interface " + std::to_string(api->abi) +
           ", this iaa's " + std::to_string(viz::kPluginAbi) + ")";
  } else if (!api->version || std::string(api->version) != IAA_PLUGIN_VERSION) {
    *why = "it comes from another version of iaa (" +
           std::string(api->version ? api->version : "none") + ", this iaa is " +
           IAA_PLUGIN_VERSION + ")";
  } else if (api->layout != viz::layout_fingerprint()) {
    *why = "it comes from another build of iaa (the types it is passed differ: layout " +
           hex(api->layout) + ", this iaa's " + hex(viz::layout_fingerprint()) + ")";
  } else {
    return api;  // kept loaded for the life of the process: its functions are in use
  }
  ::dlclose(handle);
  return nullptr;
}

Loaded load() {
  Loaded out;
  std::string tried;
  for (const fs::path& path : candidates(&tried)) {
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
              ", and that could not be loaded" +
              (plugin_variable().empty() ? " (set IAA_VIZ_PLUGIN to the file's path):"
                                         : " (from IAA_VIZ_PLUGIN):") +
              tried;
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
