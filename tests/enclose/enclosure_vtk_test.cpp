// An enclosure written as .vtu reads back through vtkXMLUnstructuredGridReader with the same boxes
// (bit for bit), arrays, counts and metadata.
#ifdef IAA_HAVE_VIZ
#include "viz/enclosure_vtk.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "enclose_support.h"

namespace iaa {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("iaa-enclose-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

void expect_same(const Enclosure& a, const Enclosure& b) {
  ASSERT_EQ(a.cells.size(), b.cells.size());
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(a.bounds.lo[i], b.bounds.lo[i]);
    EXPECT_EQ(a.bounds.hi[i], b.bounds.hi[i]);
  }
  for (std::size_t i = 0; i < a.cells.size(); ++i) {
    const Cell& x = a.cells[i];
    const Cell& y = b.cells[i];
    ASSERT_EQ(x.index, y.index) << i;
    ASSERT_EQ(x.depth, y.depth) << i;
    ASSERT_EQ(x.cls, y.cls) << i;
    ASSERT_EQ(x.f.lo(), y.f.lo()) << i;
    ASSERT_EQ(x.f.hi(), y.f.hi()) << i;
  }
  EXPECT_EQ(a.counts_by_depth, b.counts_by_depth);
  EXPECT_EQ(a.evaluations, b.evaluations);
  EXPECT_EQ(a.corner_evaluations, b.corner_evaluations);
}

TEST(EnclosureVtk, ReadsBackIdentical) {
  const auto& s = test::test_surface("teardrop");  // refined: cells of several depths
  const Tape tape = Tape::parse(s.expr);
  EncloseSettings set;
  set.bounds = s.bounds;
  set.depth = 5;
  set.refine_possible = 3;
  set.max_boxes = 123456;
  const Enclosure e = enclose(tape, set);
  ASSERT_GT(e.cells.size(), 100u);
  const std::string path = temp_path("teardrop.vtu");
  viz::write_enclosure_vtu(path, e, viz::EnclosureInfo{s.expr, set});

  // The file is appended raw binary with a compressor, as documented.
  std::ifstream in(path, std::ios::binary);
  const std::string head((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(head.find("compressor=\"vtkLZ4DataCompressor\""), std::string::npos);
  EXPECT_NE(head.find("format=\"appended\""), std::string::npos);
  EXPECT_NE(head.find("<AppendedData encoding=\"raw\">"), std::string::npos);

  const viz::EnclosureFile back = viz::read_enclosure_vtu(path);
  expect_same(e, back.enclosure);
  EXPECT_TRUE(back.points_match_boxes);
  EXPECT_EQ(back.info.expression, s.expr);
  EXPECT_EQ(back.info.settings.depth, 5);
  EXPECT_EQ(back.info.settings.refine_possible, 3);
  EXPECT_EQ(back.info.settings.max_boxes, 123456u);
  fs::remove_all(fs::path(path).parent_path());
}

// A set of cells without counts_by_depth (the boxes a mesher left, as iaa-viz shows them) converts
// with every point on its cell's corner: the corner grid is the deepest level of the cells.
TEST(EnclosureVtk, CellsWithoutCountsConvert) {
  const auto& s = test::test_surface("teardrop");
  EncloseSettings set;
  set.bounds = s.bounds;
  set.depth = 5;
  set.refine_possible = 3;
  const Enclosure e = enclose(Tape::parse(s.expr), set);
  Enclosure rest;
  rest.bounds = e.bounds;
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    if (i % 5 == 0 || e.cells[i].depth > set.depth) rest.cells.push_back(e.cells[i]);
  }
  ASSERT_GT(rest.cells.back().depth, set.depth);
  const std::string path = temp_path("rest.vtu");
  viz::write_enclosure_vtu(path, rest, viz::EnclosureInfo{s.expr, set});
  EXPECT_TRUE(viz::read_enclosure_vtu(path).points_match_boxes);
  fs::remove_all(fs::path(path).parent_path());
}

TEST(EnclosureVtk, EmptyEnclosureRoundTrips) {
  const Tape tape = Tape::parse("x^2 + y^2 + z^2 + 1");
  EncloseSettings set;
  set.bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
  set.depth = 4;
  const Enclosure e = enclose(tape, set);
  ASSERT_TRUE(e.cells.empty());
  const std::string path = temp_path("empty.vtu");
  viz::write_enclosure_vtu(path, e, viz::EnclosureInfo{"x^2 + y^2 + z^2 + 1", set});
  const viz::EnclosureFile back = viz::read_enclosure_vtu(path);
  expect_same(e, back.enclosure);
  fs::remove_all(fs::path(path).parent_path());
}

TEST(EnclosureVtk, BadFilesAreClearErrors) {
  EXPECT_THROW(viz::read_enclosure_vtu("/nonexistent/boxes.vtu"), Error);
  const std::string path = temp_path("garbage.vtu");
  std::ofstream(path) << "<VTKFile>not really</VTKFile>";
  EXPECT_THROW(viz::read_enclosure_vtu(path), Error);
  fs::remove_all(fs::path(path).parent_path());
}

}  // namespace
}  // namespace iaa
#endif
