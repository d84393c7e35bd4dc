// A triangle soup (libiaa/mesh/triangle_soup.h) as VTK polygons: the octree mesh in the
// multiblock of `iaa inspect --vtk` and the mesh that `iaa-viz mesh` shows.
#pragma once

#include <vtkSmartPointer.h>

#include "mesh/triangle_soup.h"

class vtkPolyData;

namespace iaa::viz {

/// The triangles of a soup as vtkPolyData polygons, with double-precision points so that nothing
/// is rounded on the way.
vtkSmartPointer<vtkPolyData> soup_to_polydata(const TriangleSoup& soup);

}  // namespace iaa::viz
