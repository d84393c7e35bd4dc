// Shared VTK rendering of iaa overlays: loading .vtm/.vtu/.vtp/.vtk/.ply/.obj files into layers,
// choosing colours from the iaa arrays they carry (hit results, depth-box verdicts, enclosure
// classes), a legend, the camera (the scene's, an automatic fit, or an explicit one), and drawing
// them either into an off-screen image or an interactive window. Used by `iaa-viz`.
//
// VTK on Debian renders through X11/GLX only: every function that renders needs a reachable X
// display (the caller starts Xvfb when there is none, see viz/app/xserver.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/vec.h"

class vtkDataObject;
class vtkDataSet;

namespace iaa::viz {

/// A pinhole camera as iaa defines it (DESIGN.md): right-handed, vertical field of view.
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

// ---- Categorical arrays ---------------------------------------------------------------------
// iaa data sets mark their cells with small integer codes in these cell arrays; the viewer
// colours by them and draws a legend. The writers (viz/inspect_vtk.h, viz/enclosure_vtk.h) and
// the viewer share these names and codes.

/// Cell array "result" of beam frusta and hit slabs: the outcome of EvalRaySet for a sub-beam.
inline constexpr const char* kResultArray = "result";
enum ResultCode : int { kResultMiss = 0, kResultFull = 1, kResultPartial = 2 };

/// Cell array "verdict" of the depth boxes tested by the depth search.
inline constexpr const char* kVerdictArray = "verdict";
enum VerdictCode : int {
  kVerdictExcluded = 0,  ///< 0 is not in F(box): certified empty, discarded
  kVerdictKept = 1,      ///< 0 may be in F(box): split further or kept as t_near
};

/// Cell array "class" of enclosure boxes (values of iaa::CellClass).
inline constexpr const char* kClassArray = "class";
enum ClassCode : int { kClassCrossing = 1, kClassPossible = 2 };

/// One category of a categorical array: its code, legend label and colour (linear RGB in [0,1]).
struct Category {
  int code;
  const char* label;
  Vec3 color;
};

/// The categories of one of the arrays above (empty for any other name).
const std::vector<Category>& categories_of(const std::string& array_name);

/// The roles a layer can play, which decide its look.
enum class LayerRole {
  kFrusta,      ///< beam pyramids: translucent, outlined
  kSlabs,       ///< hit slabs: solid, coloured by result
  kDepthBoxes,  ///< depth-search boxes: translucent, coloured by verdict
  kPoints,      ///< hit points with normals: spheres and normal arrows
  kEnclosure,   ///< enclosure boxes: coloured by class, edges shown
  kMesh,        ///< a triangle mesh: shaded, light
  kGeneric,     ///< anything else: coloured by a known array if present, else plain
};

/// One data set to draw.
struct Layer {
  std::string name;  ///< block name in a .vtm, or the file name
  vtkSmartPointer<vtkDataSet> data;
  LayerRole role = LayerRole::kGeneric;
  double opacity = -1;  ///< < 0: the role's default
  int viewport = 0;     ///< which side-by-side view it is drawn in (see ViewSettings::viewports)
  /// Draw only the cells' edges, in the colours of their categories: context that would hide the
  /// focus if filled (a pixel inspection's coarse depth boxes and the enclosure boxes around it).
  bool outline = false;
};

/// Guesses a layer's role from its name and arrays.
LayerRole guess_role(const std::string& name, vtkDataSet* data);

/// Reads one file into layers (a multiblock gives one layer per non-empty leaf, named by its
/// block name). In a pixel inspection (a file with hit slabs or hit points), blocks whose name
/// says "coarse" and enclosure boxes are outlined (Layer::outline). Throws iaa::Error for a missing
/// or unreadable file or an unknown extension (the message lists the known ones). `camera`, when
/// not null, receives a camera recorded in the file.
std::vector<Layer> load_layers(const std::string& path,
                               std::optional<ViewCamera>* camera = nullptr);

/// The file extensions load_layers reads, for messages ("vtm, vtu, ...").
std::string known_extensions();

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

/// An automatic camera: looks at the layers that matter most (hit slabs and hit points when
/// present, else depth boxes, else everything) from an oblique direction, or from the side of
/// `hint`'s viewing direction when a recorded camera is known (a pixel's beam is then seen along
/// its length).
ViewCamera auto_camera(const std::vector<Layer>& layers, const std::optional<ViewCamera>& hint,
                       double aspect);

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
