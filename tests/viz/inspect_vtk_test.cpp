// The multiblock of `iaa inspect --vtk`: written atomically through VTK's XML multiblock writer, it
// reads back with vtkXMLMultiBlockDataReader with the expected blocks, cell types and arrays, and
// iaa-viz's loader gives each block its role.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataReader.h>

#include "core/error.h"
#include "enclose/octree.h"
#include "mesh/octree_mesher.h"
#include "render/render.h"
#include "render/render_test_util.h"
#include "viz/inspect_vtk.h"
#include "viz/scene_render.h"

namespace iaa::viz {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("iaa_inspect_vtk_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Blocks of a multiblock read back, by name.
std::map<std::string, vtkDataSet*> blocks_by_name(vtkMultiBlockDataSet* mb) {
  std::map<std::string, vtkDataSet*> out;
  for (unsigned i = 0; i < mb->GetNumberOfBlocks(); ++i) {
    std::string name = "?";
    if (mb->HasMetaData(i) && mb->GetMetaData(i)->Has(vtkCompositeDataSet::NAME()))
      name = mb->GetMetaData(i)->Get(vtkCompositeDataSet::NAME());
    out[name] = vtkDataSet::SafeDownCast(mb->GetBlock(i));
  }
  return out;
}

void expect_cell_arrays(vtkDataSet* d, std::initializer_list<const char*> names) {
  ASSERT_NE(d, nullptr);
  for (const char* n : names) EXPECT_NE(d->GetCellData()->GetArray(n), nullptr) << n;
}

struct Inspected {
  Scene scene = test::bundled("teardrop", 500);
  RenderSettings settings = scene.settings;
  PixelTrace trace;
  PixelResult result;
  EncloseSettings es;
  Enclosure enclosure;
  OctreeMesh mesh;

  Inspected(int x, int y) {
    result = render_pixel(scene, settings, x, y, &trace);
    es.bounds = scene.bounds;
    es.depth = 5;
    enclosure = enclose(*scene.tape, es);
    OctreeMeshSettings ms;
    ms.enclose = es;
    mesh = extract_mesh(*scene.tape, enclosure, ms);
  }
  InspectionInput input() const {
    InspectionInput in;
    in.scene = &scene;
    in.settings = settings;
    in.trace = &trace;
    in.enclosure = &enclosure;
    in.enclose_settings = es;
    in.mesh = &mesh.soup;
    return in;
  }
};

TEST(InspectVtk, NeckPixelReadsBackWithBlocksAndArrays) {
  const Inspected ins(258, 250);  // on the teardrop's neck (docs/inspect.md)
  ASSERT_EQ(ins.result.certificate, PixelCertificate::kUncertain);
  const fs::path dir = fresh_dir("neck");
  const std::string path = (dir / "neck.vtm").string();
  write_vtm_atomically(path, inspection_to_multiblock(ins.input()));
  // Nothing but the file and its pieces' directory: no temporary left behind.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"neck", "neck.vtm"}));

  vtkNew<vtkXMLMultiBlockDataReader> r;
  r->SetFileName(path.c_str());
  r->Update();
  auto* mb = vtkMultiBlockDataSet::SafeDownCast(r->GetOutputDataObject(0));
  ASSERT_NE(mb, nullptr);
  const auto b = blocks_by_name(mb);
  for (const char* n : {kBeamsBlock, kSlabsBlock, kDepthBoxesBlock, kCoarseDepthBoxesBlock,
                        kHitPointsBlock, kEnclosureBlock, kMeshBlock})
    EXPECT_EQ(b.count(n), 1u) << n;
  EXPECT_EQ(b.count(kSampleRaysBlock), 0u);  // IAA casts no point rays

  // One pyramid per beam of the pixel's quadtree.
  int quad = 0, leaves = 0, pieces = 0;
  for (const BeamTrace& bt : ins.trace.beams) {
    if (bt.level < 0) continue;
    ++quad;
    leaves += bt.decision == BeamDecision::kShadeLeaf || bt.decision == BeamDecision::kShadeFull;
    for (const DepthPieceTrace& p : bt.pieces) pieces += !p.box.is_empty() && !p.mean_value;
  }
  auto* beams = vtkUnstructuredGrid::SafeDownCast(b.at(kBeamsBlock));
  ASSERT_NE(beams, nullptr);
  EXPECT_EQ(beams->GetNumberOfCells(), quad);
  EXPECT_EQ(beams->GetCellType(0), VTK_PYRAMID);
  expect_cell_arrays(beams, {kResultArray, "level", "beam", "decision", "t_near", "t_far"});

  auto* slabs = vtkUnstructuredGrid::SafeDownCast(b.at(kSlabsBlock));
  ASSERT_NE(slabs, nullptr);
  EXPECT_EQ(slabs->GetNumberOfCells(), leaves);
  EXPECT_EQ(static_cast<std::uint32_t>(leaves), ins.result.leaves);
  EXPECT_EQ(slabs->GetCellType(0), VTK_HEXAHEDRON);
  expect_cell_arrays(slabs, {kResultArray, "level", "t_near", "t_far"});
  // The neck pixel's leaves are Partial (uncertain): the result array says so.
  EXPECT_EQ(slabs->GetCellData()->GetArray(kResultArray)->GetTuple1(0), kResultPartial);

  auto* near_boxes = vtkUnstructuredGrid::SafeDownCast(b.at(kDepthBoxesBlock));
  auto* coarse = vtkUnstructuredGrid::SafeDownCast(b.at(kCoarseDepthBoxesBlock));
  ASSERT_NE(near_boxes, nullptr);
  ASSERT_NE(coarse, nullptr);
  EXPECT_EQ(near_boxes->GetNumberOfCells() + coarse->GetNumberOfCells(), pieces);
  EXPECT_EQ(near_boxes->GetCellType(0), VTK_VOXEL);
  expect_cell_arrays(near_boxes,
                     {kVerdictArray, "beam", "level", "order", "t", "f", "f_mean_value"});
  const double* vr = near_boxes->GetCellData()->GetArray(kVerdictArray)->GetRange();
  EXPECT_EQ(vr[0], kVerdictExcluded);  // both verdicts occur
  EXPECT_EQ(vr[1], kVerdictKept);

  auto* points = vtkPolyData::SafeDownCast(b.at(kHitPointsBlock));
  ASSERT_NE(points, nullptr);
  EXPECT_EQ(points->GetNumberOfPoints(), leaves);
  ASSERT_NE(points->GetPointData()->GetNormals(), nullptr);
  auto* color = vtkUnsignedCharArray::SafeDownCast(points->GetPointData()->GetArray("color"));
  ASSERT_NE(color, nullptr);
  EXPECT_EQ(color->GetNumberOfComponents(), 3);

  auto* enc = vtkUnstructuredGrid::SafeDownCast(b.at(kEnclosureBlock));
  ASSERT_NE(enc, nullptr);
  EXPECT_EQ(enc->GetNumberOfCells(), static_cast<vtkIdType>(ins.enclosure.cells.size()));
  expect_cell_arrays(enc, {kClassArray});
  auto* mesh = vtkPolyData::SafeDownCast(b.at(kMeshBlock));
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->GetNumberOfPolys(), static_cast<vtkIdType>(ins.mesh.soup.triangles.size()));

  // Field data: the pixel and the scene's camera.
  vtkDataArray* px = beams->GetFieldData()->GetArray("pixel");
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(px->GetTuple1(0), 258);
  EXPECT_EQ(px->GetTuple1(1), 250);
  const auto cam = recorded_camera(beams);
  ASSERT_TRUE(cam.has_value());
  EXPECT_EQ(cam->eye.z, ins.scene.camera.eye.z);

  // iaa-viz's loader: roles by block name and arrays, context outlined.
  std::optional<ViewCamera> rec;
  const std::vector<Layer> layers = load_layers(path, &rec);
  ASSERT_TRUE(rec.has_value());
  std::map<std::string, const Layer*> by;
  for (const Layer& l : layers) by[l.name] = &l;
  ASSERT_EQ(by.count(kBeamsBlock), 1u);
  EXPECT_EQ(by[kBeamsBlock]->role, LayerRole::kFrusta);
  EXPECT_EQ(by[kSlabsBlock]->role, LayerRole::kSlabs);
  EXPECT_EQ(by[kDepthBoxesBlock]->role, LayerRole::kDepthBoxes);
  EXPECT_FALSE(by[kDepthBoxesBlock]->outline);
  EXPECT_EQ(by[kCoarseDepthBoxesBlock]->role, LayerRole::kDepthBoxes);
  EXPECT_TRUE(by[kCoarseDepthBoxesBlock]->outline);
  EXPECT_EQ(by[kHitPointsBlock]->role, LayerRole::kPoints);
  EXPECT_EQ(by[kEnclosureBlock]->role, LayerRole::kEnclosure);
  EXPECT_TRUE(by[kEnclosureBlock]->outline);
  EXPECT_EQ(by[kMeshBlock]->role, LayerRole::kMesh);

  // Writing again replaces the file and its pieces, still without leftovers.
  write_vtm_atomically(path, inspection_to_multiblock(ins.input()));
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += !e.path().empty();
  EXPECT_EQ(entries, 2u);
  fs::remove_all(dir);
}

TEST(InspectVtk, BackgroundPixelShowsTheBlockThatDecidedIt) {
  const Inspected ins(0, 0);  // a corner of the image: a Miss screen block
  ASSERT_EQ(ins.result.certificate, PixelCertificate::kEmpty);
  InspectionInput in = ins.input();
  in.enclosure = nullptr;
  in.mesh = nullptr;
  const auto mb = inspection_to_multiblock(in);
  const auto b = blocks_by_name(mb);
  EXPECT_EQ(b.count(kEnclosureBlock), 0u);
  EXPECT_EQ(b.count(kMeshBlock), 0u);
  auto* beams = vtkUnstructuredGrid::SafeDownCast(b.at(kBeamsBlock));
  ASSERT_NE(beams, nullptr);
  ASSERT_EQ(beams->GetNumberOfCells(), 1);
  EXPECT_EQ(beams->GetCellData()->GetArray(kResultArray)->GetTuple1(0), kResultMiss);
  EXPECT_LT(beams->GetCellData()->GetArray("level")->GetTuple1(0), 0);
  EXPECT_EQ(b.at(kSlabsBlock)->GetNumberOfCells(), 0);
}

TEST(InspectVtk, PointMethodWritesItsRays) {
  Inspected ins(258, 250);
  ins.settings.method = RenderMethod::kPoint;
  ins.trace = PixelTrace{};
  ins.result = render_pixel(ins.scene, ins.settings, 258, 250, &ins.trace);
  const auto mb = inspection_to_multiblock(ins.input());
  const auto b = blocks_by_name(mb);
  ASSERT_EQ(b.count(kSampleRaysBlock), 1u);
  EXPECT_EQ(b.at(kSampleRaysBlock)->GetNumberOfCells(), 1);
}

TEST(InspectVtk, UnwritablePlaceIsAClearErrorAndLeavesNothing) {
  const fs::path dir = fresh_dir("missing");
  const Inspected ins(258, 250);
  const std::string path = (dir / "no" / "such" / "x.vtm").string();
  try {
    write_vtm_atomically(path, inspection_to_multiblock(ins.input()));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace iaa::viz
