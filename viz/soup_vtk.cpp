// Triangle soups as vtkPolyData (see soup_vtk.h).
#include "viz/soup_vtk.h"

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace iaa::viz {

vtkSmartPointer<vtkPolyData> soup_to_polydata(const TriangleSoup& soup) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(soup.vertices.size()));
  for (std::size_t i = 0; i < soup.vertices.size(); ++i) {
    const Vec3& v = soup.vertices[i];
    pts->SetPoint(static_cast<vtkIdType>(i), v.x, v.y, v.z);
  }
  vtkNew<vtkCellArray> tris;
  tris->AllocateExact(static_cast<vtkIdType>(soup.triangles.size()),
                      3 * static_cast<vtkIdType>(soup.triangles.size()));
  for (const auto& t : soup.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    tris->InsertNextCell(3, ids);
  }
  pd->SetPoints(pts);
  pd->SetPolys(tris);
  return pd;
}

}  // namespace iaa::viz
