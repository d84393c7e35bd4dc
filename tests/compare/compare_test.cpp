// `compare`: the per-pixel verdicts and the diff picture's colours on hand-made data, and a sphere
// mesh against the sphere's own render: no wrong pixels, lost pixels only along the silhouette, and
// a hole cut into the mesh shows up as lost pixels.
#include "compare/compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/scene_toml.h"
#include "mesh/cgal_mesher.h"
#include "mesh/mesh_raycast.h"
#include "mesh/octree_mesher.h"
#include "render/context.h"
#include "render/render.h"
#include "scene/camera.h"
#include "test_progress.h"
#include "test_scenes.h"
#ifdef IAA_HAVE_VIZ
#include "viz/vtk_mesher.h"
#endif

namespace iaa {
namespace {

TEST(Compare, VerdictsPerPixel) {
  Film film(3, 2);
  film.certificate = {PixelCertificate::kEmpty,     PixelCertificate::kEmpty,
                      PixelCertificate::kCovered,   PixelCertificate::kCovered,
                      PixelCertificate::kUncertain, PixelCertificate::kNotRendered};
  const std::vector<std::uint8_t> mesh = {0, 1, 1, 0, 0, 1};
  const Comparison c = compare_with_film(film, mesh);
  EXPECT_EQ(c.pixel[0], PixelAgreement::kBothEmpty);
  EXPECT_EQ(c.pixel[1], PixelAgreement::kWrong);
  EXPECT_EQ(c.pixel[2], PixelAgreement::kBothSurface);
  EXPECT_EQ(c.pixel[3], PixelAgreement::kLost);
  EXPECT_EQ(c.pixel[4], PixelAgreement::kUncertainEmpty);
  EXPECT_EQ(c.pixel[5], PixelAgreement::kNotCompared);
  EXPECT_EQ(c.counts.pixels, 5u);
  EXPECT_EQ(c.counts.lost, 1u);
  EXPECT_EQ(c.counts.wrong, 1u);
  EXPECT_EQ(diff_picture(film, c).size(), 6u);
  EXPECT_THROW(compare_with_film(film, {0, 1}), Error);
}

// Every verdict in its colour: lost red, wrong blue, undecided-without-mesh amber, and every
// other pixel (agreement, undecided with mesh, not rendered) the render faded towards white.
TEST(Compare, DiffPictureShowsEachVerdictInItsColour) {
  Film film(4, 2);
  film.certificate = {PixelCertificate::kEmpty,       PixelCertificate::kEmpty,
                      PixelCertificate::kCovered,     PixelCertificate::kCovered,
                      PixelCertificate::kUncertain,   PixelCertificate::kUncertain,
                      PixelCertificate::kNotRendered, PixelCertificate::kCovered};
  for (std::size_t i = 0; i < film.color.size(); ++i) {
    film.color[i] = {0.1f * float(i), 0.5f, 1.0f - 0.1f * float(i)};  // a different colour each
  }
  const std::vector<std::uint8_t> mesh = {0, 1, 1, 0, 1, 0, 0, 1};
  const Comparison c = compare_with_film(film, mesh);
  const std::vector<Rgb> pic = diff_picture(film, c);
  ASSERT_EQ(pic.size(), 8u);
  const Rgb expected[8] = {faded(film.color[0]), kWrongColor,          faded(film.color[2]),
                           kLostColor,           faded(film.color[4]), kUndecidedColor,
                           faded(film.color[6]), faded(film.color[7])};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(pic[i], expected[i]) << "pixel " << i << ": " << agreement_name(c.pixel[i]);
  }
  EXPECT_EQ(faded({0, 0, 0}), (Rgb{0.45f, 0.45f, 0.45f}));
  EXPECT_EQ(faded({1, 1, 1}), (Rgb{1, 1, 1}));
}

// Clear colours: a faded render has every channel >= 0.45, each mark some channel <= 0.05, so no
// mark can be mistaken for the render; the marks differ from each other by >= 0.5 in a channel.
TEST(Compare, DiffColoursAreClear) {
  auto lo = [](const Rgb& c) { return std::min(c.r, std::min(c.g, c.b)); };
  auto far = [](const Rgb& a, const Rgb& b) {
    return std::max(std::fabs(a.r - b.r), std::max(std::fabs(a.g - b.g), std::fabs(a.b - b.b)));
  };
  for (const Rgb& m : {kLostColor, kWrongColor, kUndecidedColor}) EXPECT_LE(lo(m), 0.05f);
  for (float v : {0.0f, 0.3f, 1.0f}) EXPECT_GE(lo(faded({v, 1 - v, v / 2})), 0.45f);
  EXPECT_GE(far(kLostColor, kWrongColor), 0.5f);
  EXPECT_GE(far(kLostColor, kUndecidedColor), 0.5f);
  EXPECT_GE(far(kWrongColor, kUndecidedColor), 0.5f);
  EXPECT_GT(kLostColor.r, 0.8f);       // red
  EXPECT_GT(kWrongColor.b, 0.8f);      // blue
  EXPECT_GT(kUndecidedColor.g, 0.5f);  // amber: red and green
}

#ifdef IAA_HAVE_CGAL

const char* kSphereScene = R"(
name = "sphere"
[surface]
expression = "x^2 + y^2 + z^2 - 0.64"
min = [-1, -1, -1]
max = [1, 1, 1]
[camera]
eye = [0.4, 0.5, 3.0]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40
[image]
width = 80
height = 80
)";

struct SphereCase {
  Scene scene = parse_scene(kSphereScene, "sphere.toml");
  Film film;
  TriangleSoup mesh;
  SphereCase() {
    RenderSettings rs = scene.settings;
    rs.method = RenderMethod::kIaa;
    film = render(scene, rs);
    OctreeMeshSettings s;
    s.enclose.bounds = scene.bounds;
    s.enclose.depth = 6;
    mesh = mesh_octree(*scene.tape, s).soup;
  }
  // True when a pixel has a neighbour (8-connected) that IAA does not certify as covered.
  bool on_silhouette(int x, int y) const {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= film.width || v >= film.height) return true;
        if (film.cert(u, v) != PixelCertificate::kCovered) return true;
      }
    }
    return false;
  }
};

TEST(Compare, SphereMeshAgreesWithItsRender) {
  const SphereCase c;
  const MeshView view = view_mesh(c.mesh, c.scene, 2);
  const Comparison cmp = compare_with_film(c.film, view.any);
  EXPECT_GT(cmp.counts.both_surface, 1000u);
  EXPECT_EQ(cmp.counts.wrong, 0u);
  for (int y = 0; y < c.film.height; ++y) {
    for (int x = 0; x < c.film.width; ++x) {
      if (cmp.pixel[c.film.index(x, y)] == PixelAgreement::kLost) {
        EXPECT_TRUE(c.on_silhouette(x, y))
            << "lost pixel inside the silhouette at " << x << "," << y;
      }
    }
  }
}

TEST(Compare, AHoleInTheMeshShowsAsLostPixels) {
  SphereCase c;
  const std::uint64_t lost_before =
      compare_with_film(c.film, view_mesh(c.mesh, c.scene, 1).any).counts.lost;
  // Delete the triangles of a patch facing the camera (and those behind it, so nothing shows
  // through): every triangle within 0.25 of the line from the eye through the centre.
  const Vec3 eye = c.scene.camera.eye, d = normalize(-1.0 * eye);
  std::vector<std::array<std::uint32_t, 3>> kept;
  for (const auto& t : c.mesh.triangles) {
    const Vec3 m = (c.mesh.vertices[t[0]] + c.mesh.vertices[t[1]] + c.mesh.vertices[t[2]]) / 3.0;
    const Vec3 r = m - eye;
    if (length(r - dot(r, d) * d) > 0.25) kept.push_back(t);
  }
  ASSERT_LT(kept.size(), c.mesh.triangles.size());
  c.mesh.triangles = kept;
  const Comparison cmp = compare_with_film(c.film, view_mesh(c.mesh, c.scene, 1).any);
  EXPECT_EQ(cmp.counts.wrong, 0u);
  EXPECT_GT(cmp.counts.lost, lost_before + 50);
  // The hole is red in the diff picture, and only the lost pixels are.
  const std::vector<Rgb> pic = diff_picture(c.film, cmp);
  std::uint64_t red = 0;
  for (std::size_t i = 0; i < pic.size(); ++i) {
    const bool lost = cmp.pixel[i] == PixelAgreement::kLost;
    red += pic[i] == kLostColor;
    if (!lost) {
      EXPECT_NE(pic[i], kLostColor) << "pixel " << i;
    }
    if (cmp.pixel[i] == PixelAgreement::kBothSurface) {
      EXPECT_EQ(pic[i], faded(c.film.color[i])) << "pixel " << i;
    }
  }
  EXPECT_EQ(red, cmp.counts.lost);
}

#ifdef IAA_HAVE_VIZ
/// Proves that no ray through pixel (x, y) meets the surface, independently of EvalRaySet: the
/// pixel's beam over the whole depth range is split in (u, v) and in depth until the natural
/// interval enclosure excludes 0 on every cell (no mean-value forms, no depth tolerance, no
/// budget). False when `max_cells` cells do not suffice.
bool proved_empty_by_subdivision(const Scene& scene, int x, int y, int max_cells) {
  const RenderSetup setup(scene, scene.settings);
  RoundingScope scope;
  RenderContext ctx(setup);
  struct Cell {
    PixelRect r;
    Interval t;
  };
  std::vector<Cell> todo{{PixelRect{double(x), double(y), x + 1.0, y + 1.0}, setup.depth}};
  for (int cells = 0; !todo.empty(); ++cells) {
    if (cells >= max_cells) return false;
    const Cell c = todo.back();
    todo.pop_back();
    const IBox box =
        clip_box(segment_box(setup.frame.eye, setup.frame.dir_box(c.r), c.t), scene.bounds);
    if (box.is_empty()) continue;
    const Interval f = ctx.eval(box);
    if (f.is_empty() || !f.contains_zero()) continue;  // empty: f is defined nowhere there
    // Split the longer of the cell's lateral extent (at its far end) and its depth extent.
    const double lateral = c.r.width() * setup.frame.scale * c.t.hi();
    const double tm = c.t.mid(), um = 0.5 * (c.r.u0 + c.r.u1), vm = 0.5 * (c.r.v0 + c.r.v1);
    if (c.t.width() > lateral && tm > c.t.lo() && tm < c.t.hi()) {
      todo.push_back({c.r, Interval(c.t.lo(), tm)});
      todo.push_back({c.r, Interval(tm, c.t.hi())});
    } else if (um > c.r.u0 && um < c.r.u1 && vm > c.r.v0 && vm < c.r.v1) {
      for (const PixelRect& q :
           {PixelRect{c.r.u0, c.r.v0, um, vm}, PixelRect{um, c.r.v0, c.r.u1, vm},
            PixelRect{c.r.u0, vm, um, c.r.v1}, PixelRect{um, vm, c.r.u1, c.r.v1}}) {
        todo.push_back({q, c.t});
      }
    } else {
      return false;  // at the resolution of doubles and still 0 in F
    }
  }
  return true;
}

// The teardrop with its bounds in general position (no grid line along the neck's axis): at the
// same resolution, the octree mesh loses fewer pixels than the point-sampled peers. A peer's mesh
// may reach into a silhouette pixel that IAA proves empty (VTK's vertices are interpolated, up to
// ~2e-3 off the surface here, about 0.2 pixel; CGAL's facets are chords up to its facet distance,
// 0.7 pixel, off the surface where it curves away, as at the neck). A few such pixels at most, and
// each one proved empty again without EvalRaySet, so that the mesh is what is wrong there.
TEST(Compare, TeardropOctreeLosesFewerPixelsThanPeers) {
  const Scene scene = test::bundled_scene(
      "teardrop", {"surface.min=[-1.05, -1.03, -1.04]", "image.width=200", "image.height=200"});
  RenderSettings rs = scene.settings;
  rs.method = RenderMethod::kIaa;
  const Film film = render(scene, rs);
  struct Verdict {
    std::uint64_t lost = 0;
    std::vector<std::pair<int, int>> wrong;  // pixels IAA proves empty that the mesh covers
  };
  auto compare = [&](const TriangleSoup& m) {
    const Comparison c = compare_with_film(film, view_mesh(m, scene, 1).any);
    Verdict v;
    v.lost = c.counts.lost;
    for (int i = 0; i < film.width * film.height; ++i) {
      if (c.pixel[static_cast<std::size_t>(i)] == PixelAgreement::kWrong) {
        v.wrong.emplace_back(i % film.width, i / film.width);
      }
    }
    EXPECT_EQ(v.wrong.size(), c.counts.wrong);
    return v;
  };
  auto expect_mesh_is_wrong = [&](const Verdict& v, const char* peer) {
    EXPECT_LE(v.wrong.size(), 3u) << peer;
    for (const auto& [x, y] : v.wrong) {
      EXPECT_TRUE(proved_empty_by_subdivision(scene, x, y, 200000))
          << peer << ", pixel " << x << "," << y
          << ": IAA says empty, brute force cannot confirm it";
    }
  };
  OctreeMeshSettings os;
  os.enclose.bounds = scene.bounds;
  os.enclose.depth = 6;
  os.enclose.refine_possible = 4;
  viz::VtkMeshSettings vs;
  vs.bounds = scene.bounds;
  vs.grid = 64;
  CgalMeshSettings cs;
  cs.bounds = scene.bounds;
  cs.facet_size = 2.1 / 64;
  cs.facet_distance = cs.facet_size / 4;
  const Verdict ours = compare(mesh_octree(*scene.tape, os).soup);
  const Verdict vtk = compare(viz::mesh_vtk(*scene.tape, vs));
  // Mesh_3's mesh depends on its random far points: before mesh_cgal seeded them, 1 run in 60
  // covered one pixel IAA proves empty (150,80), which brute force proves empty too. Their number
  // is per hardware thread, so other machines mesh differently. One thread: the same mesh in every
  // run on a machine.
  Exec one_thread;
  one_thread.threads = 1;
  const Verdict cgal = compare(mesh_cgal(*scene.tape, cs, one_thread));
  EXPECT_LT(ours.lost, vtk.lost);
  EXPECT_LT(ours.lost, cgal.lost);
  EXPECT_GT(vtk.lost, 5u);
  EXPECT_TRUE(ours.wrong.empty());  // our mesher is deterministic: none, as ever
  expect_mesh_is_wrong(vtk, "vtk");
  expect_mesh_is_wrong(cgal, "cgal");
}
#endif

// Ctrl-C (Progress::cancel) reaches the mesh's ray cast: it stops with an error. The ray cast
// (view_mesh) is CGAL's AABB tree, so this too needs CGAL.
TEST(Compare, CancelStopsTheMeshCastWithAnError) {
  test::CancelAtStart progress;
  const SphereCase c;
  Exec exec;
  exec.progress = &progress;
  EXPECT_THROW(view_mesh(c.mesh, c.scene, 1, exec), Error);
}

#endif

}  // namespace
}  // namespace iaa
