// load_layers: files written by VTK read back as layers with the right role, arrays and recorded
// camera; bad input gives iaa::Error with a clear message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/error.h"
#include "viz/scene_render.h"

namespace iaa::viz {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("iaa_viz_test_" + name)).string();
}

TEST(SceneRender, VtuReadsBackWithRoleArrayAndCamera) {
  vtkNew<vtkUnstructuredGrid> g;
  vtkNew<vtkPoints> pts;
  for (int i = 0; i < 8; ++i) pts->InsertNextPoint(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  g->SetPoints(pts);
  const vtkIdType ids[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  g->InsertNextCell(VTK_VOXEL, 8, ids);
  vtkNew<vtkIntArray> verdict;
  verdict->SetName(kVerdictArray);
  verdict->InsertNextValue(kVerdictKept);
  g->GetCellData()->AddArray(verdict);
  ViewCamera cam;
  cam.eye = {1, 2, 3};
  cam.fov_deg = 33;
  attach_camera(g, cam);
  const std::string path = temp_path("boxes.vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(g);
  ASSERT_EQ(w->Write(), 1);

  std::optional<ViewCamera> got;
  const std::vector<Layer> layers = load_layers(path, &got);
  ASSERT_EQ(layers.size(), 1u);
  EXPECT_EQ(layers[0].role, LayerRole::kDepthBoxes);
  EXPECT_EQ(layers[0].data->GetNumberOfCells(), 1);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->eye.y, 2);
  EXPECT_EQ(got->fov_deg, 33);
  std::filesystem::remove(path);
}

TEST(SceneRender, BadInputIsAClearError) {
  try {
    load_layers(temp_path("does_not_exist.vtu"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
  const std::string odd = temp_path("a.xyz");
  std::ofstream(odd) << "x";
  try {
    load_layers(odd);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(".vtm, .vtu"), std::string::npos) << e.what();
  }
  const std::string broken = temp_path("broken.vtu");
  std::ofstream(broken) << "<VTKFile garbage";
  EXPECT_THROW(load_layers(broken), Error);
  std::filesystem::remove(odd);
  std::filesystem::remove(broken);
}

}  // namespace
}  // namespace iaa::viz
