// What iaa-viz draws: layers (one VTK data set each, with the role that decides its look) and the
// categorical cell arrays by which iaa's writers mark their cells and the viewer colours them.
#pragma once

#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/vec.h"

class vtkDataSet;

namespace iaa::viz {

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

/// Cell array "reason" of the boxes the certified mesher could not certify (viz/box_vtk.h; values
/// of UncertifiedCell::reason).
inline constexpr const char* kReasonArray = "reason";

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

/// Whether `data` (may be null) has a cell array called `name`.
bool has_cell_array(vtkDataSet* data, const char* name);

// ---- Layers ---------------------------------------------------------------------------------

/// The roles a layer can play, which decide its look.
enum class LayerRole {
  kFrusta,      ///< beam pyramids: translucent, outlined
  kSlabs,       ///< hit slabs: solid, coloured by result
  kDepthBoxes,  ///< depth-search boxes: translucent, coloured by verdict
  kPoints,      ///< hit points with normals: spheres and normal arrows
  kEnclosure,   ///< enclosure boxes: coloured by class, edges shown
  kMesh,        ///< a triangle mesh: shaded, light
  /// cells the certified mesher could not certify: red boxes, each also marked at its centre by
  /// a dot of fixed screen size, since such cells are often far smaller than a pixel
  kUncertified,
  kGeneric,  ///< anything else: coloured by a known array if present, else plain
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

}  // namespace iaa::viz
