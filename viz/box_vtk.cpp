// Loose boxes as a .vtu; see box_vtk.h.
#include "viz/box_vtk.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkUnstructuredGrid.h>

#include "viz/enclosure_vtk.h"

namespace iaa::viz {

namespace {

vtkSmartPointer<vtkTypeInt32Array> int_array(const char* name, vtkIdType n) {
  auto a = vtkSmartPointer<vtkTypeInt32Array>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  return a;
}

vtkSmartPointer<vtkStringArray> string_array(const char* name, const std::string& value) {
  auto a = vtkSmartPointer<vtkStringArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> boxes_to_grid(const std::vector<LabelledBox>& boxes,
                                                   const std::string& expression) {
  const auto n = static_cast<vtkIdType>(boxes.size());
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(8 * n);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  auto depth = int_array("depth", n), reason = int_array("reason", n);
  for (vtkIdType i = 0; i < n; ++i) {
    const LabelledBox& b = boxes[static_cast<std::size_t>(i)];
    vtkIdType ids[8];
    // VTK_VOXEL order: x fastest, then y, then z.
    for (int k = 0; k < 8; ++k) {
      ids[k] = 8 * i + k;
      points->SetPoint(ids[k], (k & 1) ? b.box.hi.x : b.box.lo.x, (k & 2) ? b.box.hi.y : b.box.lo.y,
                       (k & 4) ? b.box.hi.z : b.box.lo.z);
    }
    cells->InsertNextCell(8, ids);
    depth->SetValue(i, b.depth);
    reason->SetValue(i, b.reason);
  }
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_VOXEL, cells);
  grid->GetCellData()->AddArray(depth);
  grid->GetCellData()->AddArray(reason);
  grid->GetFieldData()->AddArray(string_array("expression", expression));
  grid->GetFieldData()->AddArray(string_array("format", "iaa-boxes 1"));
  return grid;
}

void write_boxes_vtu(const std::string& path, const std::vector<LabelledBox>& boxes,
                     const std::string& expression) {
  write_grid_vtu(path, boxes_to_grid(boxes, expression));
}

}  // namespace iaa::viz
