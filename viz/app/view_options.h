// The options every iaa-viz mode shares (output, size, camera, legend) and the step that turns
// layers into a PNG or a window: find or start an X display, choose the camera, render, write.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "viz/scene_render.h"

namespace iaa::viz {

struct ViewOptions {
  std::string output;  ///< PNG path; empty = interactive window
  std::string size = "800x600";
  std::string camera = "default";  ///< scene | auto | EYE:LOOK:UP | default
  double fov = 0;                  ///< 0 = the camera's own
  std::string scene;               ///< a scene file whose camera `--camera scene` uses
  std::string title;
  bool no_legend = false;
  // Set by the shortcuts, not on the command line:
  int viewports = 1;                  ///< side-by-side views (Layer::viewport)
  std::vector<std::string> captions;  ///< one per view
};

/// Adds -o, --size, --camera, --fov, --scene, --title, --no-legend to `app`.
void add_view_options(CLI::App& app, ViewOptions& o);

/// Parses "WxH" (16..8192 each); throws iaa::Error naming --size.
std::pair<int, int> parse_size(const std::string& text);

/// Parses "ex,ey,ez:lx,ly,lz:ux,uy,uz"; throws iaa::Error naming --camera.
ViewCamera parse_camera(const std::string& text);

/// The camera of a scene as a ViewCamera.
ViewCamera camera_of(const Scene& s);

/// Checks the options that do not depend on the data (size, --fov, -o, the syntax of --camera)
/// and, for a window, that there is a display to open it on, so that a mistake is reported
/// before a file is loaded or an enclosure computed. Throws iaa::Error.
void check_view(const ViewOptions& o);

/// Renders `layers` to o.output (PNG) or opens a window. `recorded` is a camera recorded in the
/// data, `scene` a scene loaded by the caller (either gives `--camera scene` its camera).
void show(const std::vector<Layer>& layers, const ViewOptions& o,
          const std::optional<ViewCamera>& recorded, const Scene* scene);

}  // namespace iaa::viz
