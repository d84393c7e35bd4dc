// `iaa inspect` end to end: its JSON agrees with the PNG and the certificate image that `iaa
// render` writes (neck, silhouettes, background; IAA and adaptive), its tree names every decision,
// `--vtk` + `iaa-viz` (own Xvfb, DISPLAY unset) give a picture that is not blank and shows the
// verdict and result colours, and bad input gives a clear error, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"

#include "app/png.h"

namespace {

namespace fs = std::filesystem;

const std::string kBin = IAA_BIN_DIR;
const std::string kScene = std::string(IAA_SOURCE_DIR) + "/data/scenes/teardrop.toml";

using iaa::e2e::Outcome;
using iaa::e2e::quoted;
using iaa::e2e::run;

fs::path fresh_dir(const std::string& name) {
  // The process id keeps two test runs on one machine (two build trees) apart.
  const fs::path d =
      fs::temp_directory_path() / ("iaa_inspect_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

nlohmann::json inspect_json(int x, int y, const std::string& extra = "") {
  const Outcome r = run("'" + kBin + "/iaa' inspect '" + kScene + "' --pixel " + std::to_string(x) +
                        "," + std::to_string(y) + " --json " + extra);
  EXPECT_EQ(r.status, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

/// The certificate colours of `iaa render --aov` (cmd_render.cpp).
std::string certificate_of(const std::uint8_t* p) {
  if (p[0] == 235 && p[1] == 235 && p[2] == 235) return "empty";
  if (p[0] == 30 && p[1] == 150 && p[2] == 60) return "covered";
  if (p[0] == 235 && p[1] == 110 && p[2] == 20) return "uncertain";
  return "?";
}

/// Pixels to check: the neck's row, silhouettes (a certificate change to the right), background.
std::vector<std::pair<int, int>> sample_pixels(const iaa::app::Image8& cert) {
  std::vector<std::pair<int, int>> out;
  for (int x = 248; x <= 272; x += 2) out.push_back({x, 250});
  int seen = 0;
  for (int y = 0; y < cert.height; ++y) {
    for (int x = 0; x + 1 < cert.width; ++x) {
      if (certificate_of(cert.at(x, y)) != certificate_of(cert.at(x + 1, y)) && seen++ % 40 == 0)
        out.push_back({x, y});
    }
  }
  for (auto p : {std::pair{3, 3}, std::pair{496, 12}, std::pair{120, 420}}) out.push_back(p);
  return out;
}

TEST(InspectCli, JsonAgreesWithTheRenderedPngAndCertificates) {
  const fs::path dir = fresh_dir("agree");
  for (const char* method : {"iaa", "adaptive"}) {
    const std::string png = (dir / (std::string(method) + ".png")).string();
    const std::string aov = (dir / (std::string(method) + "-aov")).string();
    const Outcome r = run("'" + kBin + "/iaa' render '" + kScene + "' -q --method " + method +
                          " -o '" + png + "' --aov '" + aov + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const iaa::app::Image8 img = iaa::app::read_png(png);
    const iaa::app::Image8 cert = iaa::app::read_png(aov + "/certificate.png");
    const auto pixels = sample_pixels(cert);
    ASSERT_GT(pixels.size(), 30u);
    int uncertain_neck = 0;
    for (const auto& [x, y] : pixels) {
      const nlohmann::json j = inspect_json(x, y, std::string("--method ") + method);
      ASSERT_EQ(j["pixel"][0], x);
      const std::uint8_t* p = img.at(x, y);
      const auto rgb = j["result"]["rgb8"];
      EXPECT_EQ(rgb[0], p[0]) << method << " pixel " << x << "," << y;
      EXPECT_EQ(rgb[1], p[1]) << method << " pixel " << x << "," << y;
      EXPECT_EQ(rgb[2], p[2]) << method << " pixel " << x << "," << y;
      EXPECT_EQ(j["result"]["certificate"], certificate_of(cert.at(x, y)))
          << method << " pixel " << x << "," << y;
      uncertain_neck += y == 250 && j["result"]["certificate"] == "uncertain";
    }
    if (std::string(method) == "iaa") {
      EXPECT_GT(uncertain_neck, 3);
    }
  }
  fs::remove_all(dir);
}

TEST(InspectCli, TreeAndJsonShowEveryBeamAndDecision) {
  const Outcome r = run("'" + kBin + "/iaa' inspect '" + kScene + "' --pixel 258,250");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* s :
       {"screen block 32x32", "pixel beam", "sub-beam level 2", "excluded (0 not in F)",
        "kept (0 in F)", "result partial: t_near", "decision split",
        "Partial above max_level 2: split into 4", "decision shade-leaf",
        "shading:", "certificate uncertain", "pixel colour #"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
  const nlohmann::json j = inspect_json(258, 250);
  int sub = 0;
  for (const auto& b : j["beams"]) {
    sub += b["kind"] == "sub-beam";
    ASSERT_TRUE(b.contains("pieces"));
    for (const auto& p : b["pieces"]) ASSERT_TRUE(p["verdict"].is_string());
    ASSERT_TRUE(b["why"].is_string());
  }
  EXPECT_GE(sub, 4);
  // A point-sampled pixel lists its ray.
  const nlohmann::json jp = inspect_json(258, 250, "--method point");
  EXPECT_EQ(jp["rays"].size(), 1u);
}

bool have_xvfb() {
  return std::system("command -v Xvfb >/dev/null 2>&1") == 0 ||
         std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
}

TEST(InspectCli, VtkPictureIsNotBlankAndShowsTheColours) {
  if (!fs::exists(kBin + "/iaa-viz")) GTEST_SKIP() << "iaa-viz not built";
  if (!have_xvfb()) GTEST_SKIP() << "no Xvfb";
  const fs::path dir = fresh_dir("viz");
  const std::string vtm = (dir / "neck.vtm").string(), png = (dir / "neck.png").string();
  Outcome r =
      run("'" + kBin + "/iaa' inspect '" + kScene + "' --pixel 256,250 --vtk '" + vtm + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + vtm), std::string::npos);
  r = run("env -u DISPLAY '" + kBin + "/iaa-viz' '" + vtm + "' --size 480x360 -o '" + png + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const iaa::app::Image8 img = iaa::app::read_png(png);
  ASSERT_EQ(img.width, 480);
  ASSERT_EQ(img.height, 360);
  int non_white = 0, reddish = 0, bluish = 0, orange = 0, dark = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.at(x, y);
      const int rr = p[0], g = p[1], b = p[2];
      non_white += rr < 240 || g < 240 || b < 240;
      reddish += rr > g + 50 && rr > b + 30;              // kept depth boxes
      bluish += b > rr + 30 && b > g + 10;                // excluded depth boxes
      orange += rr > 200 && g > 80 && g < 180 && b < 80;  // partial hit slabs / legend
      dark += rr < 70 && g < 70 && b < 80;                // legend box, hit points, arrows
    }
  }
  const int n = img.width * img.height;
  EXPECT_GT(non_white, n / 5) << "looks blank";
  EXPECT_GT(reddish, 200);
  EXPECT_GT(bluish, 200);
  EXPECT_GT(orange, 20);
  EXPECT_GT(dark, 500);
  fs::remove_all(dir);
}

TEST(InspectCli, BadInputIsAClearErrorWithNoFile) {
  const fs::path dir = fresh_dir("bad");
  const std::string iaa = "'" + kBin + "/iaa' inspect ";
  struct Case {
    std::string args, message;
  };
  const std::string vtk = " --vtk " + quoted((dir / "x.vtm").string());
  const std::string scene = quoted(kScene);
  const std::vector<Case> cases = {
      {scene + " --pixel 500,10" + vtk,
       "--pixel 500,10 is outside the 500x500 image: X must lie in 0..499 and Y in 0..499"},
      {scene + " --pixel 10,-1" + vtk, "outside the 500x500 image"},
      {scene + " --pixel 10" + vtk, "expected two integers X,Y"},
      {quoted((dir / "missing.toml").string()) + " --pixel 1,1" + vtk, "cannot read"},
      {quoted((dir / "scene.png").string()) + " --pixel 1,1" + vtk, "unknown file type '.png'"},
      {scene + " --pixel 1,1 --vtk " + quoted((dir / "x.vtu").string()), "must be a .vtm file"},
      {scene + " --pixel 1,1 --vtk " + quoted((dir / "no" / "x.vtm").string()), "does not exist"},
  };
  std::ofstream(dir / "scene.png") << "not a scene";
  for (const Case& c : cases) {
    const Outcome r = run(iaa + c.args);
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find("iaa inspect: error:"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  // Nothing was written but the file the test made.
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += !e.path().empty();
  EXPECT_EQ(entries, 1u);
  if (fs::exists(kBin + "/iaa-viz")) {
    Outcome r = run("env -u DISPLAY '" + kBin + "/iaa-viz' '" + (dir / "missing.vtm").string() +
                    "' -o '" + (dir / "a.png").string() + "'");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
    r = run("env -u DISPLAY '" + kBin + "/iaa-viz' '" + (dir / "scene.png").string() + "' -o '" +
            (dir / "a.png").string() + "'");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("unknown file type '.png'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "a.png"));
  }
  fs::remove_all(dir);
}

}  // namespace
