// Shared by `iaa mesh`, `iaa compare` and `iaa bench mesh`: the meshers of the application layer
// (app/meshing.h, which the Python module shares) with this build's VTK mesher plugged in, and
// loading the surface from a scene file or --expr/--bounds. Header-only so that the subcommand
// files stay independent.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "app/meshing.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "iaa/command.h"
#ifdef IAA_HAVE_VIZ
#include "iaa/viz_plugin.h"
#endif

namespace iaa::cli::meshing {

using app::meshing::MeshParams;
using app::meshing::MeshRun;
using app::meshing::Method;
using app::meshing::method_label;
using app::meshing::seconds_since;
using app::meshing::Surface;
using app::meshing::surface_of;

/// VTK's flying edges (through the plugin, iaa/viz_plugin.h) when this build has viz/, else none.
#ifdef IAA_HAVE_VIZ
inline constexpr app::meshing::VtkMesher kVtkMesher = run_vtk_mesher;
#else
inline constexpr app::meshing::VtkMesher kVtkMesher = nullptr;
#endif

/// Parses a method name; a method whose library was left out of this build is a clear error.
inline Method parse_mesh_method(const std::string& text) {
  const Method m = app::meshing::parse_mesh_method(text, kVtkMesher);
#ifdef IAA_HAVE_VIZ
  if (m == Method::kVtk) viz_plugin("--method vtk");  // a missing plugin is said before the work
#endif
  return m;
}

/// Runs one mesher (parameters validated first).
inline MeshRun run_mesher(Method m, const Surface& s, const MeshParams& p, const Exec& exec) {
  return app::meshing::run_mesher(m, s, p, exec, kVtkMesher);
}

/// A scene path, or --expr with --bounds (and --param); exactly one of the two.
inline Surface load_surface(const std::string& scene_path, const std::string& expr,
                            const std::string& bounds, const std::vector<std::string>& params,
                            const std::vector<std::string>& sets = {}) {
  if (!scene_path.empty()) {
    if (!expr.empty()) throw Error("give either a SCENE or --expr, not both");
    return surface_of(app::load_scene(scene_path, sets));
  }
  if (!sets.empty()) throw Error("--set changes a scene file; it needs a SCENE");
  if (expr.empty())
    throw Error("no surface: give a SCENE file or --expr EXPR --bounds X0:X1,Y0:Y1,Z0:Z1");
  if (bounds.empty()) throw Error("--bounds X0:X1,Y0:Y1,Z0:Z1 is required with --expr");
  Surface s;
  s.name = "expr";
  s.expression = expr;
  s.tape = std::make_shared<const Tape>(Tape::parse(expr, parse_params(params)));
  s.bounds = parse_box(bounds, "--bounds");
  for (int a = 0; a < 3; ++a) {
    if (!(s.bounds.lo[a] < s.bounds.hi[a])) throw Error("--bounds: every range must have LO < HI");
  }
  validate_surface(*s.tape, s.bounds);  // as a scene file's surface is checked
  return s;
}

}  // namespace iaa::cli::meshing
