// The iaa command's door to VTK: libiaa_vtk.so (viz/plugin_api.h), loaded with dlopen the first
// time a command needs it. Commands that never write a VTK file start without VTK's libraries.
#pragma once

#ifdef IAA_HAVE_VIZ

#include <string>

#include "viz/plugin_api.h"

namespace iaa::cli {

/// The plugin's table, loading the plugin on the first call (from the file IAA_VIZ_PLUGIN names,
/// else beside the iaa executable, else in the install tree's LIBDIR/iaa/). Throws iaa::Error
/// when it cannot be loaded or comes from another build: the message starts with `what` (the
/// option that needs VTK), names the files tried and why each failed.
const viz::PluginApi& viz_plugin(const std::string& what);

/// VTK's flying edges through the plugin: an app::meshing::VtkMesher that loads it when called.
void run_vtk_mesher(const app::meshing::Surface& s, const app::meshing::MeshParams& p,
                    const Exec& exec, app::meshing::MeshRun& run);

}  // namespace iaa::cli

#endif  // IAA_HAVE_VIZ
