// load_layers: files written by VTK read back as layers with the right role, arrays and recorded
// camera; bad input gives iaa::Error with a clear message. The camera: a recorded camera reads
// back only when well formed; auto_camera frames the subject of an inspection, not its context.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
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

/// A layer of the given role holding two points, the corners of the box [lo, hi]^3.
Layer box_layer(LayerRole role, double lo, double hi, bool outline = false) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(lo, lo, lo);
  pts->InsertNextPoint(hi, hi, hi);
  pd->SetPoints(pts);
  Layer l;
  l.data = pd;
  l.role = role;
  l.outline = outline;
  return l;
}

TEST(SceneCamera, RecordedCameraReadsBackOnlyWhenWellFormed) {
  vtkNew<vtkPolyData> d;
  EXPECT_FALSE(recorded_camera(d).has_value());
  ViewCamera cam;
  cam.look_at = {0.5, 0, 0};
  cam.fov_deg = 25;
  attach_camera(d, cam);
  const std::optional<ViewCamera> got = recorded_camera(d);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->look_at.x, 0.5);
  EXPECT_EQ(got->fov_deg, 25);

  vtkNew<vtkPolyData> nan;
  attach_camera(nan, cam);
  nan->GetFieldData()->GetArray(kCameraArray)->SetTuple1(9, std::nan(""));
  EXPECT_FALSE(recorded_camera(nan).has_value());
  vtkNew<vtkPolyData> short_array;
  vtkNew<vtkDoubleArray> a;
  a->SetName(kCameraArray);
  a->SetNumberOfTuples(9);
  short_array->GetFieldData()->AddArray(a);
  EXPECT_FALSE(recorded_camera(short_array).has_value());
  EXPECT_FALSE(recorded_camera(nullptr).has_value());
}

TEST(SceneCamera, AutoCameraFramesTheSubjectFromTheBeamsSide) {
  // Hit slabs in [0, 1]^3 are the subject; outlined enclosure boxes around them are context.
  const std::vector<Layer> layers = {box_layer(LayerRole::kSlabs, 0, 1),
                                     box_layer(LayerRole::kEnclosure, -10, 10, true)};
  EXPECT_NEAR(focus_radius(layers), 0.5 * std::sqrt(3.0), 1e-12);
  ViewCamera hint;  // looks along -z
  const ViewCamera c = auto_camera(layers, hint, 1.0);
  EXPECT_EQ(c.look_at.x, 0.5);
  EXPECT_EQ(c.look_at.y, 0.5);
  EXPECT_EQ(c.look_at.z, 0.5);
  // Seen from the side, turned 35 degrees towards the hint's eye.
  const Vec3 view = normalize(c.look_at - c.eye);
  EXPECT_NEAR(dot(view, Vec3{0, 0, -1}), std::sin(35.0 * M_PI / 180.0), 1e-12);
  EXPECT_GT(dot(c.up, hint.up), 0);
  // Nothing to frame: the default camera with auto_camera's field of view.
  EXPECT_EQ(auto_camera({}, std::nullopt, 1.0).fov_deg, 30);
}

TEST(SceneCamera, FocusRadiusOfASinglePointIsOne) {
  EXPECT_EQ(focus_radius({box_layer(LayerRole::kPoints, 2, 2)}), 1.0);
}

}  // namespace
}  // namespace iaa::viz
