// Loose boxes (any sizes, not an enclosure's grid) as a VTK unstructured grid of voxels: the
// cells the certified mesher could not certify, written as a .vtu that iaa-viz shows over a mesh.
#pragma once

#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "core/vec.h"
#include "viz/plugin_api.h"  // LabelledBox

namespace iaa::viz {

/// The boxes as VTK_VOXEL cells with cell arrays `depth` and `reason` and field data
/// `expression` and `format` ("iaa-boxes 1"); iaa-viz shows such a grid as uncertified cells.
vtkSmartPointer<vtkUnstructuredGrid> boxes_to_grid(const std::vector<LabelledBox>& boxes,
                                                   const std::string& expression);

/// Writes boxes_to_grid(boxes, expression) to `path` as a compressed binary .vtu. Writes `path`
/// directly: tools wrap this in write_atomically. Throws iaa::Error when VTK fails to write.
void write_boxes_vtu(const std::string& path, const std::vector<LabelledBox>& boxes,
                     const std::string& expression);

}  // namespace iaa::viz
