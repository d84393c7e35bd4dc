// The viewer's camera: the one a data set records (so that a viewer sees it from the scene's
// eye), an automatic framing of the layers that matter most, and putting either on a renderer.
#pragma once

#include <optional>
#include <vector>

#include "core/vec.h"
#include "viz/scene_layer.h"

class vtkDataObject;
class vtkRenderer;

namespace iaa::viz {

/// A pinhole camera as a scene's [camera] table defines it (docs/scene-format.md): right-handed,
/// vertical field of view in degrees.
struct ViewCamera {
  Vec3 eye{0, 0, 3};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_deg = 40.0;
};

/// The name of a field-data array (10 doubles: eye, look_at, up, fov) with which iaa's writers
/// record the camera of the scene that produced a data set, so that a viewer can use it.
inline constexpr const char* kCameraArray = "iaa_camera";

/// Attaches `camera` to the field data of `data` under kCameraArray.
void attach_camera(vtkDataObject* data, const ViewCamera& camera);

/// The camera recorded on `data` by attach_camera, if any.
std::optional<ViewCamera> recorded_camera(vtkDataObject* data);

/// An automatic camera: looks at the layers that matter most (hit slabs and hit points when
/// present, else depth boxes, else everything) from an oblique direction, or from the side of
/// `hint`'s viewing direction when a recorded camera is known (a pixel's beam is then seen along
/// its length).
ViewCamera auto_camera(const std::vector<Layer>& layers, const std::optional<ViewCamera>& hint,
                       double aspect);

/// The radius of the part auto_camera frames (1 when it has no extent): the scale of markers
/// that should look the same size whatever the data's units, such as normal arrows.
double focus_radius(const std::vector<Layer>& layers);

/// Puts `camera` on `renderer` and sets its clipping range to hold every layer, so that views
/// sharing the camera but drawing different layers clip alike.
void apply_camera(vtkRenderer* renderer, const ViewCamera& camera,
                  const std::vector<Layer>& layers);

}  // namespace iaa::viz
