// EvalRaySet's certificates, as properties: a Miss beam holds no root of any of 100 random rays
// inside it; a Full beam's random rays all meet the surface inside [t_near, t_far]. Both for
// beams searched on their own and for children of Full beams that inherit the parent's proof.
#include "render/beam.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <initializer_list>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "expr/eval_interval.h"
#include "expr/eval_point_grad.h"
#include "render/ray_search.h"
#include "render/render_test_util.h"

namespace iaa {
namespace {

/// Dense point sampling of f along the ray: true when a strict sign change is seen.
bool sign_change_along(PointEval& pe, const Vec3& eye, const Vec3& d, double t0, double t1,
                       const Box3& b) {
  int last = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double t = t0 + (t1 - t0) * i / 2000.0;
    const Vec3 p = eye + t * d;
    if (!b.contains(p)) {
      last = 0;
      continue;
    }
    const double v = pe.eval(p);
    const int s = v > 0 ? 1 : (v < 0 ? -1 : 0);
    if (s != 0 && last != 0 && s != last) return true;
    if (s != 0) last = s;
  }
  return false;
}

TEST(EvalRaySet, MissBeamsHoldNoRootOfRandomRays) {
  std::mt19937 rng(12345);
  int misses = 0, fulls = 0;
  for (const char* name : {"teardrop", "chubs", "blobby", "tritrumpet"}) {
    const Scene s = test::bundled(name, 64);
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    PointEval pe(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int trial = 0; trial < 60; ++trial) {
      // Beams of many sizes, from 1/16 pixel to 8 pixels, anywhere on the image.
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 8) - 4);
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w);
      const PixelRect rect{u0, v0, u0 + w, v0 + w};
      const BeamSearch b = eval_ray_set(ctx, rect, setup.depth, nullptr, nullptr);
      for (int k = 0; k < 100; ++k) {
        const double u = rect.u0 + U(rng) * w, v = rect.v0 + U(rng) * w;
        const Vec3 d = setup.frame.dir(u, v);
        if (b.result == BeamResult::kMiss) {
          const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v), setup.depth,
                                      setup.ray_tol, 1.0);
          EXPECT_FALSE(h.certified) << name << " beam " << u0 << "," << v0 << " w " << w;
          EXPECT_FALSE(sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), setup.depth.hi(),
                                         s.bounds));
        } else {
          // No ray of the beam meets the surface before t_near.
          EXPECT_FALSE(
              sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), b.t_near, s.bounds));
          if (b.result == BeamResult::kFull) {
            const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v),
                                        Interval(b.t_near, b.t_far), setup.ray_tol, 1.0);
            EXPECT_TRUE(h.hit) << name;
          }
        }
      }
      misses += b.result == BeamResult::kMiss;
      fulls += b.result == BeamResult::kFull;
    }
  }
  EXPECT_GT(misses, 20);
  EXPECT_GT(fulls, 5);
}

/// A bundled scene at 64x64, or "sphere": a sphere of radius 0.5 seen from distance 3.
Scene scene_64(const std::string& name) {
  return name == "sphere" ? test::parse(test::sphere_scene(0.5, 3, 30, 64))
                          : test::bundled(name, 64);
}

// Beams that graze the surface (on silhouettes and the rims of thin features) are where the
// mean-value form in the beam's own frame excludes depth pieces that the box form keeps
// (beam.cpp, piece_mean_value_form). Beams of 1/16 to 1 pixel centred on a silhouette, found as
// a pixel-long step across which a point ray goes from hit to miss: a Miss beam holds no root of
// any of 100 random rays, and no ray of the others meets the surface before t_near.
TEST(EvalRaySet, SilhouetteBeamsKeepTheirCertificates) {
  std::mt19937 rng(777);
  int beams = 0, misses = 0;
  for (const char* name : {"sphere", "teardrop", "chubs", "tritrumpet", "twist"}) {
    const Scene s = scene_64(name);
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    PointEval pe(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const auto hits = [&](double u, double v) {
      return sign_change_along(pe, setup.frame.eye, setup.frame.dir(u, v), setup.depth.lo(),
                               setup.depth.hi(), s.bounds);
    };
    int found = 0;
    for (int trial = 0; trial < 4000 && found < 40; ++trial) {
      const double u = 1 + U(rng) * 62, v = 1 + U(rng) * 62;
      const double a = U(rng) * 6.283185307179586;
      const double du = std::cos(a), dv = std::sin(a);
      if (hits(u, v) == hits(u + du, v + dv)) continue;
      // Bisect the step to within 1/64 pixel of the silhouette.
      double lo = 0, hi = 1;
      const bool at_lo = hits(u, v);
      for (int i = 0; i < 6; ++i) {
        const double m = 0.5 * (lo + hi);
        (hits(u + m * du, v + m * dv) == at_lo ? lo : hi) = m;
      }
      const double cu = u + lo * du, cv = v + lo * dv;
      ++found;
      for (int level = 0; level <= 4; ++level) {
        const double w = std::ldexp(1.0, -level);
        // Over the silhouette, or beside it by up to its own width.
        const double ou = (U(rng) - 0.5) * 3 * w, ov = (U(rng) - 0.5) * 3 * w;
        const PixelRect rect{cu + ou - w / 2, cv + ov - w / 2, cu + ou + w / 2, cv + ov + w / 2};
        const BeamSearch b = eval_ray_set(ctx, rect, setup.depth, nullptr, nullptr);
        ++beams;
        misses += b.result == BeamResult::kMiss;
        for (int k = 0; k < 100; ++k) {
          const double ru = rect.u0 + U(rng) * w, rv = rect.v0 + U(rng) * w;
          const Vec3 d = setup.frame.dir(ru, rv);
          const double t_end = b.result == BeamResult::kMiss ? setup.depth.hi() : b.t_near;
          ASSERT_FALSE(sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), t_end, s.bounds))
              << name << ": beam [" << rect.u0 << ", " << rect.v0 << "; w " << w << "] "
              << (b.result == BeamResult::kMiss ? "Miss" : "t_near " + std::to_string(b.t_near))
              << ", but the ray at " << ru << "," << rv << " meets the surface before";
          if (b.result == BeamResult::kMiss) {
            const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(ru, rv),
                                        setup.depth, setup.ray_tol, 1.0);
            ASSERT_FALSE(h.certified) << name << ": Miss beam, certified root at " << h.t.mid();
          }
        }
      }
    }
    EXPECT_GE(found, 20) << name << ": too few silhouette points found";
  }
  // Small beams beside a silhouette are often proved empty: both outcomes are tested.
  EXPECT_GT(misses, 50);
  EXPECT_GT(beams - misses, 200);
  RecordProperty("beams", beams);
  RecordProperty("misses", misses);
}

/// A scene with partial domains (sqrt of a negative part of the box, a pole of the division
/// inside the bounds) that the batched evaluators serve (no min/max, few lane-by-lane operations).
Scene partial_domain_scene() {
  return test::parse(
      "[surface]\nexpression = \"sqrt(x + 0.3) + y^2 + z^2 - 0.6 + 0.01 / (x - 0.1)\"\n"
      "min = [-1, -1, -1]\nmax = [1, 1, 1]\n[camera]\neye = [0.5, 0.4, 3]\nlook_at = [0, 0, 0]\n"
      "up = [0, 1, 0]\nfov = 40\n[image]\nwidth = 64\nheight = 64\n");
}

/// The scenes of the depth-search tests: bundled ones at 64x64 and the partial-domain one.
std::vector<std::pair<std::string, Scene>> search_scenes(std::initializer_list<const char*> names) {
  std::vector<std::pair<std::string, Scene>> out;
  for (const char* n : names) out.emplace_back(n, test::bundled(n, 64));
  out.emplace_back("partial-domain", partial_domain_scene());
  return out;
}

/// A beam's depth search (`width` pixels wide), checked from its trace: the pieces it excluded
/// tile `range` from its front without a gap up to t_near (to its end for a Miss); each piece's
/// natural enclosure is evaluated again with the whole tape (the same interval and partial-domain
/// flag), and where it excluded the piece, 0 is outside it; the piece found is no wider than the
/// depth tolerance. Counts the misses and hits.
void check_search(const std::vector<DepthPieceTrace>& trace, const Interval& range, bool found,
                  double t_near, double width, const RenderSetup& setup, IntervalEval& ie,
                  const std::string& where, int* misses, int* hits) {
  // One verdict per piece: a mean-value entry follows its piece's natural one and decides.
  std::vector<DepthPieceTrace> pieces;
  for (const DepthPieceTrace& p : trace) {
    if (p.mean_value) {
      ASSERT_FALSE(pieces.empty()) << where;
      ASSERT_EQ(pieces.back().t.lo(), p.t.lo()) << where;
      ASSERT_EQ(pieces.back().t.hi(), p.t.hi()) << where;
      EXPECT_EQ(p.kept, p.f.contains_zero()) << where;
      pieces.back().kept = p.kept;
      continue;
    }
    if (!p.box.is_empty()) {
      const Interval f = ie.eval(p.box);
      EXPECT_EQ(f.lo(), p.f.lo()) << where << " t " << p.t.lo();
      EXPECT_EQ(f.hi(), p.f.hi()) << where << " t " << p.t.lo();
      EXPECT_EQ(ie.partial_domain(), p.partial) << where << " t " << p.t.lo();
      if (!p.kept) {
        EXPECT_TRUE(f.is_empty() || !f.contains_zero()) << where << ": excluded with 0 in F";
      }
    }
    pieces.push_back(p);
  }
  ASSERT_FALSE(pieces.empty()) << where;
  double front = range.lo();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const DepthPieceTrace& p = pieces[k];
    EXPECT_EQ(p.t.lo(), front) << where << ": piece " << k << " leaves a gap";
    EXPECT_LE(p.t.hi(), range.hi()) << where;
    if (!p.kept) front = p.t.hi();
  }
  if (!found) {
    ++*misses;
    EXPECT_EQ(front, range.hi()) << where << ": a Miss leaves depths unexcluded";
    EXPECT_FALSE(pieces.back().kept) << where;
    return;
  }
  ++*hits;
  const DepthPieceTrace& last = pieces.back();
  EXPECT_TRUE(last.kept) << where;
  EXPECT_EQ(last.t.lo(), t_near) << where;
  const double tol =
      std::max(1e-12 * std::max(1.0, range.hi()),
               setup.settings.depth_tolerance * width * setup.frame.scale * last.t.hi());
  EXPECT_LE(last.t.width(), tol) << where << ": the kept piece is too wide";
}

// The depth search's own guarantee, read from its trace: the pieces it excluded (0 not in F, by
// the natural enclosure, evaluated here again, or the mean-value form, or outside the bounds)
// tile the range from its front without a gap up to t_near (the whole range for a Miss), and the
// piece it returns is no wider than the depth tolerance at its far end. The search is an adaptive
// march (a kept piece halved, wider pieces after excluded ones). Beams of every size searched
// alone, and the four quadrants of each searched side by side sharing one budget (as a pixel's
// sub-beams are), in scenes with thin features, silhouettes and partial domains; ranges from the
// front of the depths or from partway in (a parent's t_near).
TEST(EvalRaySet, ExcludedPiecesTileTheDepthsInFrontOfTheHit) {
  std::mt19937 rng(777);
  int misses = 0, hits = 0;
  for (const auto& [name, s] :
       search_scenes({"teardrop", "chubs", "twist", "klein_bottle", "blobby", "thin_torus"})) {
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    IntervalEval ie(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int trial = 0; trial < 60; ++trial) {
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 8) - 4);  // 1/16 to 8 pixels
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w), h = 0.5 * w;
      const PixelRect rect{u0, v0, u0 + w, v0 + w};
      const Interval range(setup.depth.lo() + U(rng) * 0.3 * setup.depth.width(), setup.depth.hi());
      std::ostringstream where;
      where << name << " beam [" << u0 << ", " << v0 << "; w " << w << "]";
      BeamTrace tr;
      const BeamSearch b = eval_ray_set(ctx, rect, range, nullptr, &tr);
      check_search(tr.pieces, range, b.result != BeamResult::kMiss, b.t_near, w, setup, ie,
                   where.str(), &misses, &hits);
      const PixelRect kids[4] = {{u0, v0, u0 + h, v0 + h},
                                 {u0 + h, v0, u0 + w, v0 + h},
                                 {u0, v0 + h, u0 + h, v0 + w},
                                 {u0 + h, v0 + h, u0 + w, v0 + w}};
      FirstPiece together[4];
      first_pieces(ctx, kids, 4, range, true, together);
      for (int k = 0; k < 4; ++k) {
        check_search(together[k].pieces, range, together[k].found, together[k].a, h, setup, ie,
                     where.str() + " quadrant " + std::to_string(k), &misses, &hits);
      }
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  EXPECT_GT(misses, 200);
  EXPECT_GT(hits, 200);
}

/// Bit equality of two doubles (a -0 is not a +0).
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Sibling beams searched side by side (first_pieces: four boxes per pass of the batched
// evaluators) find what each finds alone: with a mean-value budget per beam, the same pieces with
// the same enclosures (bit for bit), the same first piece and the same evaluation count as
// eval_ray_set's own search from that budget. Quadrants of random beams of every size, with
// every number of siblings 1..4, in scenes the batch serves (no min/max, few lane-by-lane
// operations: polynomials, blobby's exp, a scene with partial domains), from budgets of every
// kind, with SSE2 and AVX2 lanes alike.
TEST(EvalRaySet, SiblingsSearchedTogetherFindWhatEachFindsAlone) {
  std::mt19937 rng(4242);
  int compared = 0, found = 0, partial_pieces = 0;
  for (const auto& [name, s] :
       search_scenes({"chubs", "teardrop", "barth_sextic", "klein_bottle", "blobby"})) {
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    ASSERT_TRUE(ctx.batched) << name;
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 8) - 3);  // 1/8 to 16 pixels
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w), h = 0.5 * w;
      const PixelRect kids[4] = {{u0, v0, u0 + h, v0 + h},
                                 {u0 + h, v0, u0 + w, v0 + h},
                                 {u0, v0 + h, u0 + h, v0 + w},
                                 {u0 + h, v0 + h, u0 + w, v0 + w}};
      // A range from the front of the depths, or from partway in (a parent's t_near).
      const Interval range(setup.depth.lo() + U(rng) * 0.5 * setup.depth.width(), setup.depth.hi());
      const int n = 1 + trial % 4;
      // Budgets that try the mean-value form and evaluate the natural enclosure first, that
      // take the gradient first, and that no longer try the mean-value form.
      MeanValueBudget start;
      const int kind = (trial / 4) % 3;
      for (int k = 0; k < 12; ++k) {
        start.record_natural(MeanValueBudget::kPiece, kind == 0 && k % 2 == 0);
        start.record(kind != 2 && k % 3 == 0);
      }
      EXPECT_EQ(start.gradient_first(MeanValueBudget::kPiece), kind == 1);
      EXPECT_EQ(start.allowed(), kind != 2);
      ctx.se.use_baseline(trial % 2 == 1);
      MeanValueBudget budgets[4] = {start, start, start, start};
      FirstPiece together[4];
      first_pieces(ctx, kids, n, range, true, together, budgets);
      for (int k = 0; k < n; ++k) {
        std::ostringstream where;
        where << name << " beam [" << kids[k].u0 << ", " << kids[k].v0 << "; w " << h << "] of "
              << n;
        ctx.mv = start;
        BeamTrace alone;
        const std::uint64_t e0 = ctx.evals;
        const BeamSearch b = eval_ray_set(ctx, kids[k], range, nullptr, &alone, false);
        const FirstPiece& t = together[k];
        EXPECT_EQ(t.evals, ctx.evals - e0) << where.str();
        EXPECT_EQ(t.found, b.result != BeamResult::kMiss) << where.str();
        if (t.found && b.result != BeamResult::kMiss) {
          EXPECT_EQ(t.a, b.t_near) << where.str();
          ++found;
        }
        ASSERT_EQ(t.pieces.size(), alone.pieces.size()) << where.str();
        for (std::size_t p = 0; p < t.pieces.size(); ++p) {
          const DepthPieceTrace &x = t.pieces[p], &y = alone.pieces[p];
          EXPECT_TRUE(same_bits(x.t.lo(), y.t.lo()) && same_bits(x.t.hi(), y.t.hi()))
              << where.str() << " piece " << p;
          EXPECT_TRUE(same_bits(x.f.lo(), y.f.lo()) && same_bits(x.f.hi(), y.f.hi()))
              << where.str() << " piece " << p << ": " << x.f.lo() << ", " << x.f.hi()
              << " against " << y.f.lo() << ", " << y.f.hi();
          for (int i = 0; i < 3; ++i) {
            EXPECT_TRUE(same_bits(x.box[i].lo(), y.box[i].lo()) &&
                        same_bits(x.box[i].hi(), y.box[i].hi()))
                << where.str() << " piece " << p;
          }
          EXPECT_EQ(x.kept, y.kept) << where.str() << " piece " << p;
          EXPECT_EQ(x.partial, y.partial) << where.str() << " piece " << p;
          EXPECT_EQ(x.mean_value, y.mean_value) << where.str() << " piece " << p;
          partial_pieces += x.partial;
        }
        // The budget after the search is the one the beam's own search leaves (slices aside:
        // eval_ray_set was told not to try full coverage).
        EXPECT_EQ(budgets[k].tries, ctx.mv.tries) << where.str();
        EXPECT_EQ(budgets[k].hits, ctx.mv.hits) << where.str();
        for (int i = 0; i < 2; ++i) {
          EXPECT_EQ(budgets[k].seen[i], ctx.mv.seen[i]) << where.str();
          EXPECT_EQ(budgets[k].natural[i], ctx.mv.natural[i]) << where.str();
        }
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 500);
  EXPECT_GT(found, 100);
  EXPECT_GT(partial_pieces, 10);  // the partial-domain scene's flags were compared too
}

// The estimator encloses n . d at the first hits: for random Full beams (before and after
// tighten_far, over 1 to 8 depth pieces), the unit normal at the first root of random rays of the
// beam, dotted with the ray's unit direction, lies in the estimator's interval.
TEST(BeamEstimator, EnclosesTheNormalsAtTheFirstHits) {
  std::mt19937 rng(4242);
  int checked = 0;
  for (const char* name : {"sphere", "teardrop", "chubs", "tritrumpet", "twist", "blobby"}) {
    const Scene s = scene_64(name);
    const RenderSetup setup(s, RenderSettings{});
    RoundingScope scope;
    RenderContext ctx(setup);
    PointGradEval pg(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    int fulls = 0;
    for (int trial = 0; trial < 400 && fulls < 12; ++trial) {
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 5) - 2);
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w);
      const PixelRect rect{u0, v0, u0 + w, v0 + w};
      BeamSearch b = eval_ray_set(ctx, rect, setup.depth, nullptr, nullptr);
      if (b.result != BeamResult::kFull) continue;
      ++fulls;
      for (int variant = 0; variant < 2; ++variant) {
        if (variant == 1) tighten_far(ctx, &b, 1e-3 * w * setup.frame.scale * b.t_near);
        for (int pieces : {1, 2, 4, 8}) {
          const Interval est = beam_estimator(ctx, b, pieces);
          for (int k = 0; k < 20; ++k) {
            const double u = rect.u0 + U(rng) * w, v = rect.v0 + U(rng) * w;
            const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v),
                                        Interval(b.t_near, b.t_far), setup.ray_tol, 1.0);
            if (!h.certified) continue;
            // The first root of this ray: none before t_near (the beam's certificate).
            const Vec3 d = setup.frame.dir(u, v);
            const Vec3 g = pg.eval(setup.frame.eye + h.t.mid() * d).g;
            if (!(length(g) > 0)) continue;
            const double nd = dot(g, d) / (length(g) * length(d));
            // The point gradient is taken at a point within the ray tolerance of the root.
            EXPECT_TRUE(est.contains(nd) ||
                        std::min(std::fabs(nd - est.lo()), std::fabs(nd - est.hi())) < 1e-6)
                << name << " beam [" << u0 << ", " << v0 << "; w " << w << "] pieces " << pieces
                << (variant ? " (tightened)" : "") << ": n.d " << nd << " outside [" << est.lo()
                << ", " << est.hi() << "]";
            ++checked;
          }
        }
      }
    }
    EXPECT_GE(fulls, 5) << name;
  }
  EXPECT_GT(checked, 2000);
}

/// Sign of f at the point of the ray eye + t d(u, v), proved with intervals on the box of that
/// point (the natural form, then the mean-value form): +1 / -1, or 0 when intervals cannot tell.
int proved_sign_on_ray(RenderContext& ctx, const RenderSetup& setup, double u, double v, double t) {
  const IBox p = segment_box(setup.frame.eye, setup.frame.dir_box(u, v), Interval(t));
  bool partial = false;
  Interval f = ctx.eval(p, &partial);
  if (partial) return 0;
  if (f.contains_zero()) {
    const IGrad g = ctx.eval_grad(p, &partial);
    if (partial) return 0;
    IBox c;
    for (int i = 0; i < 3; ++i) c[i] = Interval(p[i].mid());
    Interval m = ctx.eval(c);
    for (int i = 0; i < 3; ++i) m += g.g[static_cast<std::size_t>(i)] * (p[i] - c[i]);
    f = intersect(f, m);
  }
  return f.certainly_positive() ? 1 : (f.certainly_negative() ? -1 : 0);
}

/// The four quarters of a beam, as the renderer splits it.
std::array<PixelRect, 4> quarters(const PixelRect& r) {
  const double um = 0.5 * (r.u0 + r.u1), vm = 0.5 * (r.v0 + r.v1);
  return {PixelRect{r.u0, r.v0, um, vm}, PixelRect{um, r.v0, r.u1, vm},
          PixelRect{r.u0, vm, um, r.v1}, PixelRect{um, vm, r.u1, r.v1}};
}

/// Counts of the inherited-proof property test.
struct InheritedCounts {
  int parents = 0, misses = 0, fulls = 0, other = 0;
};

/// Checks one child beam searched, as render.cpp does, over its Full parent's child range with
/// the parent passed in, then recurses into its quarters down to `levels` more levels.
/// A Miss child: no ray of it has a root anywhere in the depth range (its area is shown as
/// background). A Full child: every ray of it has f of the proved sign at t_s, the opposite sign
/// at t_far, and no root in front of t_near, so it meets the surface inside [t_near, t_far].
void check_children(RenderContext& ctx, const RenderSetup& setup, PointEval& pe,
                    const BeamSearch& parent, const PixelRect& parent_rect, int levels,
                    std::mt19937& rng, InheritedCounts& n, const std::string& where) {
  ASSERT_EQ(parent.result, BeamResult::kFull);
  const Scene& s = *setup.scene;
  std::uniform_real_distribution<double> U(0.0, 1.0);
  // render.cpp's child_range() for a Full beam.
  const Interval sub(parent.t_near, parent.t_far);
  for (const PixelRect& q : quarters(parent_rect)) {
    const BeamSearch c = eval_ray_set(ctx, q, sub, &parent, nullptr);
    std::ostringstream at;
    at << where << " child [" << q.u0 << ", " << q.v0 << "; " << q.u1 << ", " << q.v1 << "]";
    const std::string msg = at.str();
    if (c.result == BeamResult::kMiss) {
      ++n.misses;
    } else if (c.result == BeamResult::kFull) {
      ++n.fulls;
    } else {
      ++n.other;
    }
    for (int k = 0; k < 100; ++k) {
      const double u = q.u0 + U(rng) * q.width(), v = q.v0 + U(rng) * q.height();
      const Vec3 d = setup.frame.dir(u, v);
      if (c.result == BeamResult::kMiss) {
        const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v), setup.depth,
                                    setup.ray_tol, 1.0);
        ASSERT_FALSE(h.certified) << msg << ": Miss, but the ray at " << u << "," << v
                                  << " has a root at " << h.t.mid();
        ASSERT_FALSE(
            sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), setup.depth.hi(), s.bounds))
            << msg << ": Miss, but f changes sign along the ray at " << u << "," << v;
      } else if (c.result == BeamResult::kFull) {
        ASSERT_LE(c.t_s, c.t_near) << msg;
        ASSERT_LE(c.t_near, c.t_far) << msg;
        ASSERT_TRUE(c.sign == 1 || c.sign == -1) << msg;
        // A certified sign change of this ray within [t_s, t_far] ...
        EXPECT_EQ(proved_sign_on_ray(ctx, setup, u, v, c.t_s), c.sign)
            << msg << ": ray " << u << "," << v << " at t_s " << c.t_s;
        EXPECT_EQ(proved_sign_on_ray(ctx, setup, u, v, c.t_far), -c.sign)
            << msg << ": ray " << u << "," << v << " at t_far " << c.t_far;
        // ... and no root in front of t_near, so the root is within [t_near, t_far].
        // (Dense point sampling is a slow cross-check: on the first rays only.)
        if (c.t_near > setup.depth.lo()) {
          const RayHit front = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v),
                                          Interval(setup.depth.lo(), c.t_near), setup.ray_tol, 1.0);
          EXPECT_FALSE(front.certified)
              << msg << ": a root at " << front.t.mid() << " before t_near " << c.t_near;
          if (k < 10) {
            EXPECT_FALSE(
                sign_change_along(pe, setup.frame.eye, d, setup.depth.lo(), c.t_near, s.bounds))
                << msg << ": a sign change before t_near " << c.t_near;
          }
        }
        const RayHit h = search_ray(ctx, setup.frame.eye, setup.frame.dir_box(u, v),
                                    Interval(c.t_near, c.t_far), setup.ray_tol, 1.0);
        EXPECT_TRUE(h.hit) << msg << ": ray " << u << "," << v;
      }
    }
    if (c.result == BeamResult::kFull && levels > 0) {
      check_children(ctx, setup, pe, c, q, levels - 1, rng, n, msg);
    }
  }
}

// The inherited-proof path of EvalRaySet: a child of a Full beam is searched only over the
// parent's [t_near, t_far] and takes over its sign-change proof without evaluating slices of its
// own (beam.h). Children and grandchildren of random Full parents keep both certificates.
TEST(EvalRaySet, ChildrenOfFullBeamsKeepTheirCertificates) {
  std::mt19937 rng(2024);
  InheritedCounts total;
  // Some scenes with coarser or finer depth pieces than the default (wider kept pieces, other
  // t_near and t_far) as well.
  const std::pair<const char*, double> cases[] = {
      {"teardrop", 1.0}, {"chubs", 1.0}, {"blobby", 4.0}, {"tritrumpet", 0.25}, {"twist", 1.0}};
  for (const auto& [name, tol] : cases) {
    const Scene s = test::bundled(name, 64);
    RenderSettings st;
    st.depth_tolerance = tol;
    const RenderSetup setup(s, st);
    RoundingScope scope;
    RenderContext ctx(setup);
    PointEval pe(*s.tape);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    InheritedCounts n;
    for (int trial = 0; trial < 400 && n.parents < 8; ++trial) {
      // Parents from 1/4 pixel to 4 pixels (pixels and the blocks above them).
      const double w = std::ldexp(1.0, static_cast<int>(U(rng) * 5) - 2);
      const double u0 = U(rng) * (64 - w), v0 = U(rng) * (64 - w);
      const PixelRect rect{u0, v0, u0 + w, v0 + w};
      const BeamSearch p = eval_ray_set(ctx, rect, setup.depth, nullptr, nullptr);
      if (p.result != BeamResult::kFull) continue;
      ++n.parents;
      std::ostringstream where;
      where << name << " (depth_tolerance " << tol << ") parent [" << u0 << ", " << v0 << "; w "
            << w << "]";
      check_children(ctx, setup, pe, p, rect, 1, rng, n, where.str());
      if (::testing::Test::HasFatalFailure()) return;
    }
    EXPECT_GE(n.parents, 5) << name << ": too few Full parents to test";
    total.parents += n.parents;
    total.misses += n.misses;
    total.fulls += n.fulls;
    total.other += n.other;
  }
  // Children of a Full parent are Full or Miss: the proof always carries over once a piece is
  // kept.
  EXPECT_GT(total.fulls, 100);
  RecordProperty("parents", total.parents);
  RecordProperty("full_children", total.fulls);
  RecordProperty("miss_children", total.misses);
}

}  // namespace
}  // namespace iaa
