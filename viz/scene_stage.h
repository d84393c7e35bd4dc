// The stage on which layers are shown: side-by-side views sharing one camera, the layers' actors,
// a legend, a title and captions, drawn either into an off-screen image or an interactive window.
//
// VTK on Debian renders through X11/GLX only: every function here needs a reachable X display
// (the caller starts Xvfb when there is none, see viz/app/xserver.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/vec.h"
#include "viz/scene_camera.h"
#include "viz/scene_layer.h"

namespace iaa::viz {

/// How to look at the layers.
struct ViewSettings {
  int width = 800, height = 600;
  /// The camera; none = fit all layers automatically (see auto_camera).
  std::optional<ViewCamera> camera;
  Vec3 background{1, 1, 1};
  bool legend = true;
  std::string title;  ///< drawn at the top left when not empty
  /// Side-by-side views sharing one camera (1..4); Layer::viewport picks the view of a layer.
  int viewports = 1;
  /// Optional caption of each view, drawn at its bottom left.
  std::vector<std::string> captions;
};

/// An 8-bit RGB image, rows from the top.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Renders the layers off-screen. Needs an X display (see the header comment).
RgbImage render_to_image(const std::vector<Layer>& layers, const ViewSettings& settings);

/// Opens an interactive window (trackball camera) and returns when the user closes it.
void show_interactive(const std::vector<Layer>& layers, const ViewSettings& settings);

}  // namespace iaa::viz
