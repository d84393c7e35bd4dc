// What `iaa inspect` shows is what the render did: on the teardrop at its full size, pixels on the
// thin neck, on silhouettes (next to a pixel of another certificate) and in the background give
// the same colour and certificate through render_pixel() with a trace as in render()'s film, for
// IAA, adaptive and point sampling; and the trace accounts for the colour (the area-weighted mean
// of its shaded and background parts), the coverage and the number of leaves.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "render/render.h"
#include "render/render_test_util.h"

namespace iaa {
namespace {

/// Pixels worth checking in a film: the neck's row, silhouette pixels, and a spread of others.
std::vector<std::pair<int, int>> sample_pixels(const Film& f) {
  std::set<std::pair<int, int>> out;
  // The neck: row 250, columns 248..272 (docs/inspect.md; x in [-0.06, 0.06] on the x axis).
  for (int x = 246; x <= 274; ++x) out.insert({x, 250});
  // Silhouettes: pixels whose certificate differs from their right or lower neighbour.
  int sil = 0;
  for (int y = 0; y + 1 < f.height && sil < 400; ++y) {
    for (int x = 0; x + 1 < f.width && sil < 400; ++x) {
      if (f.cert(x, y) != f.cert(x + 1, y) || f.cert(x, y) != f.cert(x, y + 1)) {
        if ((x * 7 + y * 13) % 11 == 0) {
          out.insert({x, y});
          ++sil;
        }
      }
    }
  }
  // A grid over the whole image (background, body, drop).
  for (int y = 3; y < f.height; y += 37) {
    for (int x = 5; x < f.width; x += 41) out.insert({x, y});
  }
  return {out.begin(), out.end()};
}

RenderSettings with_method(const Scene& s, RenderMethod m) {
  RenderSettings st = s.settings;
  st.method = m;
  return st;
}

TEST(InspectTrace, TeardropPixelsAgreeWithTheFullRender) {
  const Scene s = test::bundled("teardrop", 500);
  for (RenderMethod m : {RenderMethod::kIaa, RenderMethod::kAdaptive, RenderMethod::kPoint}) {
    const RenderSettings st = with_method(s, m);
    Exec exec;
    exec.threads = 2;
    const Film f = render(s, st, exec);
    const auto pixels = sample_pixels(f);
    ASSERT_GT(pixels.size(), 100u);
    int neck_uncertain = 0, silhouettes = 0, background = 0;
    for (const auto& [x, y] : pixels) {
      PixelTrace tr;
      const PixelResult r = render_pixel(s, st, x, y, &tr);
      ASSERT_EQ(r.color, f.at(x, y)) << method_name(m) << " pixel " << x << "," << y;
      ASSERT_EQ(r.certificate, f.cert(x, y)) << method_name(m) << " pixel " << x << "," << y;
      EXPECT_EQ(r.coverage, f.coverage[f.index(x, y)]);
      // The adaptive render shares corner rays with the pixels around, so only there it may
      // count fewer rays and evaluations for a pixel than the pixel alone takes.
      if (m != RenderMethod::kAdaptive) {
        EXPECT_EQ(r.leaves, f.leaves[f.index(x, y)]);
        EXPECT_EQ(r.evals, f.evals[f.index(x, y)]);
      } else {
        EXPECT_GE(r.leaves, f.leaves[f.index(x, y)]);
        EXPECT_EQ(r.leaves, tr.rays.size());  // each corner ray of the pixel cast once
      }
      EXPECT_EQ(tr.x, x);
      EXPECT_EQ(tr.y, y);
      // The trace's colour is the pixel's.
      EXPECT_EQ(static_cast<float>(tr.color.x), r.color.r);
      EXPECT_EQ(static_cast<float>(tr.color.z), r.color.b);
      neck_uncertain += y == 250 && r.certificate == PixelCertificate::kUncertain;
      background += r.certificate == PixelCertificate::kEmpty;
      silhouettes += x + 1 < f.width && f.cert(x, y) != f.cert(x + 1, y);
    }
    if (m == RenderMethod::kIaa) {
      EXPECT_GT(neck_uncertain, 5);  // the neck is thinner than a pixel there
      EXPECT_GT(background, 20);
      EXPECT_GT(silhouettes, 20);
    }
  }
}

TEST(InspectTrace, IaaTraceAccountsForColourCoverageAndLeaves) {
  const Scene s = test::bundled("teardrop", 500);
  const RenderSettings st = with_method(s, RenderMethod::kIaa);
  for (int x = 246; x <= 274; ++x) {
    PixelTrace tr;
    const PixelResult r = render_pixel(s, st, x, 250, &tr);
    Vec3 sum;
    double area = 0, covered = 0;
    std::uint32_t leaves = 0;
    int pixel_beams = 0;
    for (std::size_t i = 0; i < tr.beams.size(); ++i) {
      const BeamTrace& b = tr.beams[i];
      if (b.parent >= 0) {
        EXPECT_LT(b.parent, static_cast<int>(i));
      }
      EXPECT_EQ(b.pieces.empty(), b.searched.is_empty());
      if (b.level < 0) continue;
      pixel_beams += b.level == 0;
      EXPECT_LE(b.level, st.max_level);
      if (b.decision == BeamDecision::kBackground) {
        EXPECT_EQ(b.result, BeamResult::kMiss);
        sum = sum + b.rect.area() * s.background;
        area += b.rect.area();
      } else if (b.decision == BeamDecision::kShadeFull || b.decision == BeamDecision::kShadeLeaf) {
        EXPECT_NE(b.result, BeamResult::kMiss);
        if (b.decision == BeamDecision::kShadeFull) {
          EXPECT_EQ(b.result, BeamResult::kFull);
          EXPECT_LE(b.estimator.width(), st.estimator_threshold);
        } else {
          EXPECT_EQ(b.level, st.max_level);
        }
        sum = sum + b.rect.area() * b.color;
        area += b.rect.area();
        covered += b.rect.area() * b.weight;  // Partial slivers are shown at a weight < 1
        ++leaves;
      } else {
        EXPECT_EQ(b.decision, BeamDecision::kSplit);
        EXPECT_LT(b.level, st.max_level);
      }
      // A kept piece (or a Miss) ends every search; t_near is where the kept piece starts.
      if (b.result != BeamResult::kMiss && b.full_reason.find("Full parent") == std::string::npos) {
        ASSERT_FALSE(b.pieces.empty());
        EXPECT_TRUE(b.pieces.back().kept);
        EXPECT_EQ(b.pieces.back().t.lo(), b.t_near);
      }
      for (const DepthPieceTrace& p : b.pieces) {
        if (!p.box.is_empty() && !p.f.is_empty()) {
          EXPECT_EQ(p.kept, p.f.contains_zero());
        }
      }
    }
    if (r.certificate == PixelCertificate::kEmpty && pixel_beams == 0) continue;  // a Miss block
    EXPECT_EQ(pixel_beams, 1) << x;
    EXPECT_NEAR(area, 1.0, 1e-12) << x;  // the leaves tile the pixel
    EXPECT_NEAR(sum.x, r.color.r, 1e-6) << x;
    EXPECT_NEAR(sum.y, r.color.g, 1e-6) << x;
    EXPECT_NEAR(sum.z, r.color.b, 1e-6) << x;
    EXPECT_NEAR(covered, r.coverage, 1e-6) << x;
    EXPECT_EQ(leaves, r.leaves) << x;
  }
}

}  // namespace
}  // namespace iaa
