// `iaa-viz` end to end: a picture rendered on the display of `xvfb-run -a` (not iaa-viz's own
// Xvfb) has the class colours of the boxes; the `iaa-viz mesh` shortcut shows the mesh on the left
// and the enclosure on the right; `--camera scene|auto|EYE:LOOK:UP` each give a picture and a bad
// camera is one clear error with no file; asking for a window without a display, or with a
// DISPLAY that cannot be opened, is an error, while a PNG is then rendered on a private Xvfb.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/png.h"
#include "cli_run.h"

namespace {

namespace fs = std::filesystem;

const std::string kBin = IAA_BIN_DIR;
const std::string kScene = std::string(IAA_SOURCE_DIR) + "/data/scenes/teardrop.toml";

using iaa::e2e::Outcome;
using iaa::e2e::quoted;
using iaa::e2e::run;

bool have(const char* program) {
  return std::system(("command -v " + std::string(program) + " >/dev/null 2>&1").c_str()) == 0;
}

/// iaa-viz with DISPLAY unset, so that it starts its own Xvfb (or, without -o, has no display).
std::string viz() {
  return "env -u DISPLAY " + quoted(kBin + "/iaa-viz");
}

/// Pixels of the colour families iaa-viz uses (viz/scene_actors.cpp), under its lighting.
struct Colours {
  int white = 0;   ///< background
  int teal = 0;    ///< crossing boxes (0.1, 0.55, 0.6)
  int yellow = 0;  ///< possible boxes (0.95, 0.75, 0.1)
  int grey = 0;    ///< mesh (0.78, 0.78, 0.84): neutral, a little blue
  int red = 0;     ///< uncertified cells (0.9, 0.1, 0.1)
};

Colours count(const iaa::app::Image8& img, int x0, int x1) {
  Colours c;
  for (int y = 0; y < img.height; ++y) {
    for (int x = x0; x < x1; ++x) {
      const std::uint8_t* p = img.at(x, y);
      const int r = p[0], g = p[1], b = p[2];
      c.white += r >= 250 && g >= 250 && b >= 250;
      c.teal += g > r + 40 && b > r + 40;
      c.yellow += r > 120 && g > 80 && r > b + 80 && g > b + 50;
      c.grey += r > 60 && r < 245 && std::abs(r - g) <= 10 && b >= r && b <= r + 40;
      c.red += r > 150 && g < 90 && b < 90;
    }
  }
  return c;
}

class VizCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kBin + "/iaa-viz")) GTEST_SKIP() << "iaa-viz not built";
    dir_ = fs::temp_directory_path() /
           ("iaa_viz_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  std::string tmp(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// The display comes from xvfb-run; iaa-viz renders on it without starting a server of its own.
TEST_F(VizCli, UnderXvfbRunTheBoxesHaveTheirClassColours) {
  if (!have("xvfb-run")) GTEST_SKIP() << "no xvfb-run";
  const std::string png = tmp("enc.png");
  const Outcome r =
      run("xvfb-run -a sh -c " +
          quoted("test -n \"$DISPLAY\" && echo \"display $DISPLAY\" && " + kBin +
                 "/iaa-viz enclose " + kScene + " --depth 5 -q --size 320x240 -o " + png));
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("display :"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("private Xvfb"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("wrote " + png + " (320x240, 1 layers)"), std::string::npos) << r.out;
  const iaa::app::Image8 img = iaa::app::read_png(png);
  ASSERT_EQ(img.width, 320);
  ASSERT_EQ(img.height, 240);
  const Colours c = count(img, 0, img.width);
  const int n = img.width * img.height;
  EXPECT_GT(c.white, n / 4) << "background";
  EXPECT_GT(c.teal, n / 10) << "crossing boxes";
  EXPECT_GT(c.yellow, 300) << "possible boxes";
  // The corners are background (the teardrop is in the middle, the legend at the top right).
  for (const auto& [x, y] :
       {std::pair{2, img.height - 3}, std::pair{img.width / 2, img.height - 3}}) {
    const std::uint8_t* p = img.at(x, y);
    EXPECT_GE(p[0], 250) << x << "," << y;
    EXPECT_GE(p[1], 250) << x << "," << y;
    EXPECT_GE(p[2], 250) << x << "," << y;
  }
}

// `iaa-viz mesh SCENE`: the certified mesh (grey) with its uncertified cells, the teardrop's
// singular point (red, marked at a fixed screen size however small the cells), in the left half;
// the enclosure (teal and yellow boxes) in the right half, one camera.
TEST_F(VizCli, MeshShortcutShowsTheCertifiedMeshAndItsUncertifiedCells) {
  const std::string png = tmp("mesh.png");
  const Outcome r = run(viz() + " mesh " + quoted(kScene) +
                        " --depth 5 --resolution 64 -q --size 480x240 -o " + quoted(png));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mesh: certified, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" uncertified cells"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote " + png + " (480x240, 3 layers)"), std::string::npos) << r.out;
  const iaa::app::Image8 img = iaa::app::read_png(png);
  ASSERT_EQ(img.width, 480);
  const Colours left = count(img, 0, img.width / 2), right = count(img, img.width / 2, img.width);
  const int half = img.width / 2 * img.height;
  EXPECT_GT(left.grey, half / 20) << "no mesh on the left";
  // The legend (its "uncertified cell" entry is red) is drawn at the top right, over the right
  // half.
  EXPECT_GT(left.red, 12) << "the uncertified cells at the neck are not marked";
  EXPECT_LT(left.teal, 50) << "crossing boxes on the mesh's side";
  EXPECT_GT(right.teal, half / 10) << "no crossing boxes on the right";
}

// `iaa-viz mesh SCENE --method octree`: the octree mesh (grey) and the possible boxes it left
// unmeshed (yellow) in the left half, the enclosure (teal and yellow boxes) in the right half.
TEST_F(VizCli, OctreeMeshShortcutShowsTheMeshBesideItsEnclosure) {
  const std::string png = tmp("mesh.png");
  const Outcome r = run(viz() + " mesh " + quoted(kScene) +
                        " --method octree --depth 5 -q --size 480x240 -o " + quoted(png));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("mesh: octree, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" triangles from "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote " + png + " (480x240, 3 layers)"), std::string::npos) << r.out;
  const iaa::app::Image8 img = iaa::app::read_png(png);
  ASSERT_EQ(img.width, 480);
  ASSERT_EQ(img.height, 240);
  const Colours left = count(img, 0, img.width / 2), right = count(img, img.width / 2, img.width);
  const int half = img.width / 2 * img.height;
  EXPECT_GT(left.grey, half / 20) << "no mesh on the left";
  EXPECT_LT(left.teal, 50) << "crossing boxes on the mesh's side";
  // The possible boxes the mesher could not mesh are drawn with the mesh (they may hold surface).
  EXPECT_GT(left.yellow, 200) << "the unmeshed possible boxes are not drawn with the mesh";
  EXPECT_GT(right.teal, half / 10) << "no crossing boxes on the right";
  EXPECT_GT(right.yellow, 200) << "no possible boxes on the right";
  EXPECT_GT(left.white, half / 3);
}

// The three camera forms give three different pictures of the same boxes.
TEST_F(VizCli, CameraSceneAutoAndExplicit) {
  std::vector<std::vector<std::uint8_t>> pictures;
  for (const char* cam : {"scene", "auto", "2,1,3:0,0,0:0,1,0"}) {
    const std::string png = tmp("cam" + std::to_string(pictures.size()) + ".png");
    const Outcome r = run(viz() + " enclose " + quoted(kScene) + " --depth 4 -q --size 160x120" +
                          " --camera " + cam + " -o " + quoted(png));
    ASSERT_EQ(r.status, 0) << cam << ": " << r.err;
    const iaa::app::Image8 img = iaa::app::read_png(png);
    const Colours c = count(img, 0, img.width);
    EXPECT_GT(c.teal, 200) << cam << ": the boxes are not in view";
    EXPECT_GT(c.white, 200) << cam << ": no background";
    pictures.push_back(img.data);
  }
  EXPECT_NE(pictures[0], pictures[1]);
  EXPECT_NE(pictures[0], pictures[2]);
  EXPECT_NE(pictures[1], pictures[2]);

  // A file without a recorded camera needs --scene for --camera scene.
  const std::string vtu = tmp("boxes.vtu");
  ASSERT_EQ(
      run(quoted(kBin + "/iaa") + " enclose " + quoted(kScene) + " --depth 3 -q -o " + quoted(vtu))
          .status,
      0);
  Outcome r = run(viz() + " " + quoted(vtu) + " --camera scene --size 160x120 -o " +
                  quoted(tmp("noscene.png")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--camera scene: no camera is known"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp("noscene.png")));
  r = run(viz() + " " + quoted(vtu) + " --camera scene --scene " + quoted(kScene) +
          " --size 160x120 -o " + quoted(tmp("withscene.png")));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(tmp("withscene.png")));
}

TEST_F(VizCli, BadCameraIsOneClearErrorWithNoFile) {
  struct Case {
    std::string camera, message;
  };
  const std::vector<Case> cases = {
      {"1,1,1:1,1,1:0,1,0", "--camera: EYE and LOOK are the same point"},
      {"0,0,3:0,0,0:0,0,1", "UP must not be parallel"},
      {"1,2:0,0,0:0,1,0", "--camera: EYE must be three numbers x,y,z, got '1,2'"},
      {"1,2,3,4:0,0,0:0,1,0", "EYE must be three numbers"},
      {"1,x,3:0,0,0:0,1,0", "--camera: EYE: 'x' is not a finite number"},
      {"1,2,3:0,0,0:0,1,nan", "UP: 'nan' is not a finite number"},
      {"1,2,3:0,0,0", "expected scene, auto, or EYE:LOOK:UP"},
      {"side", "expected scene, auto, or EYE:LOOK:UP (ex,ey,ez:lx,ly,lz:ux,uy,uz), got 'side'"},
  };
  const std::string png = tmp("bad.png");
  for (const Case& c : cases) {
    const Outcome r = run(viz() + " enclose " + quoted(kScene) + " --depth 2 -q --size 64x64" +
                          " --camera " + quoted(c.camera) + " -o " + quoted(png));
    EXPECT_EQ(r.status, 1) << c.camera;
    EXPECT_NE(r.err.find("iaa-viz: error: "), std::string::npos) << c.camera << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.camera << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << c.camera;
    // Checked before the enclosure is computed.
    EXPECT_EQ(r.out.find("enclosure:"), std::string::npos) << c.camera << ": " << r.out;
  }
}

// Without -o iaa-viz opens a window; with no display that is one clear error (it never starts a
// private Xvfb for a window nobody could see).
TEST_F(VizCli, WindowWithoutADisplayIsAnError) {
  const std::string vtu = tmp("boxes.vtu");
  ASSERT_EQ(
      run(quoted(kBin + "/iaa") + " enclose " + quoted(kScene) + " --depth 3 -q -o " + quoted(vtu))
          .status,
      0);
  for (const std::string& args : {quoted(vtu), "enclose " + quoted(kScene) + " --depth 3 -q",
                                  "mesh " + quoted(kScene) + " --depth 3 -q"}) {
    const Outcome r = run(viz() + " " + args);
    EXPECT_EQ(r.status, 1) << args;
    EXPECT_NE(r.err.find("iaa-viz: error: no display to open a window on (DISPLAY is unset); "
                         "give -o FILE.png to render to a file"),
              std::string::npos)
        << args << ": " << r.err;
    // Before any enclosure or mesh is computed.
    EXPECT_EQ(r.out, "") << args;
  }
}

/// A display number with no X server (no socket), or -1.
int unused_display() {
  for (int n = 987; n < 1000; ++n) {
    if (!fs::exists("/tmp/.X11-unix/X" + std::to_string(n))) return n;
  }
  return -1;
}

// DISPLAY names a display that is not there: VTK would abort the process. A window is one clear
// error; a PNG is rendered on a private Xvfb, with a note.
TEST_F(VizCli, UnreachableDisplay) {
  const int n = unused_display();
  if (n < 0) GTEST_SKIP() << "no unused display number";
  const std::string env = "env DISPLAY=:" + std::to_string(n) + " " + quoted(kBin + "/iaa-viz");
  const std::string vtu = tmp("boxes.vtu");
  ASSERT_EQ(
      run(quoted(kBin + "/iaa") + " enclose " + quoted(kScene) + " --depth 3 -q -o " + quoted(vtu))
          .status,
      0);
  for (const std::string& args : {quoted(vtu), "enclose " + quoted(kScene) + " --depth 3 -q"}) {
    const Outcome r = run(env + " " + args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("iaa-viz: error: cannot open the X display DISPLAY=:" + std::to_string(n) +
                         "; check DISPLAY"),
              std::string::npos)
        << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
  }
  if (!have("Xvfb")) return;
  const std::string png = tmp("x.png");
  const Outcome r = run(env + " " + quoted(vtu) + " --size 160x120 -o " + quoted(png));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("rendering on a private Xvfb"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("wrote " + png + " (160x120, 1 layers)"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(count(iaa::app::read_png(png), 0, 160).teal, 200);
}

}  // namespace
