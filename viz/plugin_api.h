// The VTK half of the `iaa` command as a plugin: what `iaa` calls in viz/ when a command writes a
// VTK file (`iaa enclose -o X.vtu|X.pvtu`, `iaa inspect --vtk`, `iaa mesh --uncertified`) or runs
// VTK's flying edges (`--method vtk`). The command does not link VTK: it loads the module
// libiaa_vtk.so (viz/plugin/vtk_plugin.cpp) with dlopen the first time one of those is asked for
// (tools/iaa/viz_plugin.h), so that every other command starts without mapping and relocating
// some sixty VTK, OpenGL and X11 libraries (about 30 ms of each run's start) and runs on a machine
// without them.
//
// This header includes no VTK header: the types that cross the boundary are iaa's own, declared
// here, and the headers of viz/ that convert them to VTK data sets include this one. Both sides
// come from the same build; `kPluginAbi` and `layout_fingerprint()` catch a plugin of another
// build or version.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "app/meshing.h"
#include "core/exec.h"
#include "core/vec.h"
#include "enclose/octree.h"
#include "mesh/triangle_soup.h"
#include "render/trace.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace iaa::viz {

/// What an enclosure file records besides the boxes.
struct EnclosureInfo {
  std::string expression;    ///< the surface f(x,y,z), as the user wrote it
  EncloseSettings settings;  ///< the settings that produced the enclosure
};

/// Seconds spent in the two parts of writing an enclosure as .vtu.
struct VtuWriteTimes {
  double convert_s = 0;  ///< building the grid (enclosure_to_grid)
  double write_s = 0;    ///< writing it (write_grid_vtu)
};

/// One box and the two numbers stored with it as cell arrays (viz/box_vtk.h).
struct LabelledBox {
  Box3 box;
  int depth = 0;   ///< cell array `depth`
  int reason = 0;  ///< cell array `reason`
};

/// What goes into an inspection multiblock (viz/inspect_vtk.h). `enclosure` and `mesh` are
/// optional (null: no block).
struct InspectionInput {
  const Scene* scene = nullptr;
  RenderSettings settings;
  const PixelTrace* trace = nullptr;
  const Enclosure* enclosure = nullptr;  ///< boxes near the pixel
  EncloseSettings enclose_settings;      ///< the settings that produced them
  const TriangleSoup* mesh = nullptr;    ///< triangles near the pixel
};

/// The piece files of a .pvtu (viz/enclosure_pvtu.h): `dir/stem_K.vtu` beside `dir/stem.pvtu`
/// for K = 0 .. pieces - 1.
inline std::vector<std::string> pvtu_piece_paths(const std::string& path, int pieces) {
  const std::filesystem::path p(path);
  std::vector<std::string> out;
  for (int k = 0; k < pieces; ++k) {
    out.push_back(
        (p.parent_path() / (p.stem().string() + "_" + std::to_string(k) + ".vtu")).string());
  }
  return out;
}

/// Raised whenever PluginApi or the meaning of one of its functions changes.
inline constexpr int kPluginAbi = 1;

#ifndef IAA_PLUGIN_VERSION
#error "IAA_PLUGIN_VERSION (the project's version, set by CMake on both sides) is not defined"
#endif

/// The plugin's file name and the C symbol that hands out its table.
inline constexpr const char* kPluginFile = "libiaa_vtk.so";
inline constexpr const char* kPluginEntry = "iaa_viz_plugin_api";

/// The sizes of the types passed to the plugin, folded into one number: the two sides agree on it
/// unless they were built from different sources or with different settings.
constexpr std::uint64_t layout_fingerprint() {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the sizes
  for (const std::size_t s :
       {sizeof(Enclosure), sizeof(EncloseSettings), sizeof(EnclosureInfo), sizeof(Progress),
        sizeof(Exec), sizeof(InspectionInput), sizeof(Scene), sizeof(RenderSettings),
        sizeof(PixelTrace), sizeof(TriangleSoup), sizeof(LabelledBox),
        sizeof(app::meshing::Surface), sizeof(app::meshing::MeshParams),
        sizeof(app::meshing::MeshRun), sizeof(std::string)}) {
    h = (h ^ s) * 1099511628211ull;
  }
  return h;
}

/// The plugin's functions. Each one throws iaa::Error as its namesake in viz/ does; none of them
/// prints (VTK's own error messages may still reach stderr, as they did when iaa linked VTK).
/// `abi`, `version` and `layout` identify the build: the same sources give the same three, and
/// a plugin whose fields were reordered without a change of size or version is not caught, so
/// the plugin is built with the command (the build's bin/, the same package).
struct PluginApi {
  int abi = kPluginAbi;
  const char* version = IAA_PLUGIN_VERSION;
  std::uint64_t layout = layout_fingerprint();

  /// viz/enclosure_vtk.h: write_enclosure_vtu and write_enclosure_vtu_timed.
  void (*write_enclosure_vtu)(const std::string& path, const Enclosure& enc,
                              const EnclosureInfo& info, Progress* progress) = nullptr;
  VtuWriteTimes (*write_enclosure_vtu_timed)(const std::string& path, const Enclosure& enc,
                                             const EnclosureInfo& info, const Exec& exec) = nullptr;
  /// viz/enclosure_pvtu.h: write_enclosure_pvtu.
  void (*write_enclosure_pvtu)(const std::string& path, const Enclosure& enc,
                               const EnclosureInfo& info, int piece, int pieces,
                               bool summary) = nullptr;
  /// viz/inspect_vtk.h: write_vtm_atomically(path, inspection_to_multiblock(in)).
  void (*write_inspection_vtm)(const std::string& path, const InspectionInput& in) = nullptr;
  /// viz/box_vtk.h: write_boxes_vtu.
  void (*write_boxes_vtu)(const std::string& path, const std::vector<LabelledBox>& boxes,
                          const std::string& expression) = nullptr;
  /// viz/vtk_mesher.h: run_vtk_mesher (an app::meshing::VtkMesher).
  app::meshing::VtkMesher run_vtk_mesher = nullptr;
};

}  // namespace iaa::viz
