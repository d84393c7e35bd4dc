// Tracing one pixel: every sub-beam, every depth piece tested, every decision, with its numbers.
//
// `iaa inspect --pixel X,Y` (and tests) call render_pixel() (render.h) with a PixelTrace. The full
// render calls the *same* function per pixel with a null trace, so what inspect shows is exactly
// what the render did. All recording goes through `if (trace)`: a null trace costs one branch.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/interval.h"
#include "core/vec.h"
#include "scene/camera.h"

namespace iaa {

/// Result of EvalRaySet on a beam (docs/design.md, "Beams and the depth search").
enum class BeamResult : std::uint8_t {
  kMiss = 0,     ///< certified: no ray of the beam meets the surface in the searched depths
  kFull = 1,     ///< certified: every ray of the beam meets the surface in [t_near, t_far]
  kPartial = 2,  ///< possible: some ray may meet the surface, none before t_near
};
const char* beam_result_name(BeamResult r);

/// One depth piece [t0, t1] of a beam that was evaluated.
struct DepthPieceTrace {
  Interval t;    ///< the depth range
  IBox box;      ///< the beam's box over t, clipped to the scene bounds
  Interval f;    ///< F(box); empty when the box was empty (outside the bounds)
  bool kept;     ///< false: excluded (0 not in F), true: 0 in F (may hold surface)
  bool partial;  ///< F met a partial domain on the box
  /// F is the mean-value form on the same piece (a second, sharper test after a natural
  /// interval value that kept it), not the natural interval value.
  bool mean_value;
};

/// What the renderer did with a beam after EvalRaySet.
enum class BeamDecision : std::uint8_t {
  kBackground = 0,  ///< Miss: the whole area is background
  kShadeFull = 1,   ///< Full and estimator within threshold: shaded once
  kShadeLeaf = 2,   ///< at max_level: shaded as surface (uncertain when Partial)
  kSplit = 3,       ///< split into 4 sub-beams
  kDescend = 4,     ///< screen-block elimination: passed on to smaller blocks
};
const char* beam_decision_name(BeamDecision d);

/// One beam: a screen block above the pixel (level < 0) or a sub-beam of the pixel
/// (level 0 = the pixel, level k = 1/4^k of it).
struct BeamTrace {
  PixelRect rect;
  int level = 0;
  int parent = -1;    ///< index of the parent in PixelTrace::beams, -1 for the root
  Interval searched;  ///< depth range searched ([parent t_near, ...])
  std::vector<DepthPieceTrace> pieces;  ///< every piece evaluated, in order
  BeamResult result = BeamResult::kMiss;
  double t_near = 0, t_far = 0;  ///< t_far only meaningful for kFull
  IBox hit_box;                  ///< box of the beam over [t_near, t_far] (Full) or the kept piece
  std::string full_reason;       ///< why full coverage was or was not certified
  Interval estimator = Interval::empty();  ///< the estimator interval (empty when not computed)
  BeamDecision decision = BeamDecision::kBackground;
  // Shading (for kShadeFull / kShadeLeaf).
  bool center_ray_hit = false;    ///< the central ray's exact hit was found
  bool coverage_ray_hit = false;  ///< Partial: shaded at a coverage ray's hit (the central missed)
  Vec3 point, normal;             ///< shading point and unit normal (facing the eye)
  Vec3 color;                     ///< linear RGB of this part (surface blended by `weight`)
  double weight = 1.0;            ///< share of the part's area shown as surface (coverage)
  int coverage_rays = 0;          ///< Partial: rays whose hits gave the weight (central included)
  int coverage_hits = 0;          ///< Partial: of those, the ones that found the surface
  int behind_hits = 0;      ///< Partial: coverage rays that missed it and met surface further back
  std::uint64_t evals = 0;  ///< interval evaluations spent on this beam (search + shading)
};

/// One point-sampled ray (baselines, or the central ray of an IAA leaf).
struct RayTrace {
  double u = 0, v = 0;  ///< pixel coordinates of the ray
  Interval searched;    ///< depth range searched
  bool hit = false;
  bool certified = false;  ///< the root was proved (sign change or interval Newton)
  Interval t_hit;          ///< enclosure of the first root when hit
  Vec3 point, normal;      ///< shading point and unit normal (facing the eye) when hit
  Vec3 color;
};

/// Everything render_pixel() did for one pixel. Pass a pointer to one to record; null = no cost.
struct PixelTrace {
  int x = 0, y = 0;
  std::vector<BeamTrace> beams;  ///< screen blocks first (level < 0), then the pixel's quadtree
  std::vector<RayTrace> rays;    ///< point-sampled rays (baseline methods)
  Vec3 color;                    ///< final linear colour of the pixel
  /// IAA: the factor by which the Partial parts' weights were raised so that the pixel shows
  /// the least coverage of a pixel that may hold surface (1: not raised).
  double raised_coverage = 1.0;
};

}  // namespace iaa
