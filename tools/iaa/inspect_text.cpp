// The text report of `iaa inspect` (see inspect_text.h).
#include "iaa/inspect_text.h"

#include <cstdio>
#include <initializer_list>
#include <vector>

#include "app/png.h"

namespace iaa::cli {
namespace {

/// The parts between `open` and `close`, separated by ", ". Built with append: GCC 12 warns
/// falsely (-Wrestrict, PR 105651) on "[" + std::string once the callee is inlined.
std::string listed(char open, std::initializer_list<std::string> parts, char close) {
  std::string s(1, open);
  bool first = true;
  for (const std::string& p : parts) {
    if (!first) s.append(", ");
    s.append(p);
    first = false;
  }
  s.push_back(close);
  return s;
}

std::string interval_text(const Interval& i, int digits = 6) {
  if (i.is_empty()) return "empty";
  return listed('[', {num_text(i.lo(), digits), num_text(i.hi(), digits)}, ']');
}

std::string vec_text(const Vec3& v, int digits = 5) {
  return listed('(', {num_text(v.x, digits), num_text(v.y, digits), num_text(v.z, digits)}, ')');
}

std::string rect_text(const PixelRect& r) {
  return listed('[', {num_text(r.u0, 8), num_text(r.u1, 8)}, ']') + " x " +
         listed('[', {num_text(r.v0, 8), num_text(r.v1, 8)}, ']');
}

std::string hex_color(const Vec3& c) {
  char b[16];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", app::to_byte(c.x), app::to_byte(c.y),
                app::to_byte(c.z));
  return b;
}

/// What a beam is, in words.
std::string beam_kind(const BeamTrace& b) {
  if (b.level < 0) {
    const int size = 1 << -b.level;
    return "screen block " + std::to_string(size) + "x" + std::to_string(size);
  }
  if (b.level == 0) return "pixel beam";
  return "sub-beam level " + std::to_string(b.level) + " (1/" + std::to_string(1 << (2 * b.level)) +
         " pixel)";
}

/// Verdict of a piece in words.
const char* verdict(const DepthPieceTrace& p) {
  if (p.box.is_empty()) return "outside the bounds";
  return p.kept ? "kept (0 in F)" : "excluded (0 not in F)";
}

/// The first lines: the pixel, the method with its settings, and the result.
void print_heading(const Scene& scene, const RenderSettings& st, const PixelTrace& tr,
                   const PixelResult& r) {
  const Vec3 colour = tr.color;
  std::printf("%s: pixel %d,%d of %dx%d, method %s", scene.name.c_str(), tr.x, tr.y, scene.width,
              scene.height, std::string(method_name(st.method)).c_str());
  if (st.method == RenderMethod::kIaa) {
    std::printf(" (max_level %d, estimator threshold %s, depth tolerance %s)", st.max_level,
                num_text(st.estimator_threshold).c_str(), num_text(st.depth_tolerance).c_str());
  } else if (st.method == RenderMethod::kAdaptive) {
    std::printf(" (max_level %d, adaptive threshold %s)", st.max_level,
                num_text(st.adaptive_threshold).c_str());
  } else if (st.method == RenderMethod::kGrid) {
    std::printf(" (%dx%d rays)", st.grid_n, st.grid_n);
  }
  std::printf("\n");
  std::printf(
      "colour %s (linear %s), certificate %s, coverage %s, %u %s, %u evaluations (+%u on "
      "screen blocks)\n",
      hex_color(colour).c_str(), vec_text(colour).c_str(), certificate_name(r.certificate),
      num_text(r.coverage).c_str(), r.leaves, st.method == RenderMethod::kIaa ? "leaves" : "rays",
      r.evals, r.block_evals);
}

/// One beam, its lines indented by `ind`: its depth search, result, estimator, decision, shading.
void print_beam(std::size_t i, const BeamTrace& b, const std::string& ind,
                const RenderSettings& st) {
  std::printf("%s#%zu %s %s\n", ind.c_str(), i, beam_kind(b).c_str(), rect_text(b.rect).c_str());
  if (b.searched.is_empty() && b.pieces.empty()) {
    std::printf("%s  | no depth search: %llu evaluations\n", ind.c_str(),
                static_cast<unsigned long long>(b.evals));
  } else {
    std::printf("%s  | search t in %s: %zu depth tests, %llu evaluations\n", ind.c_str(),
                interval_text(b.searched, 9).c_str(), b.pieces.size(),
                static_cast<unsigned long long>(b.evals));
  }
  for (const DepthPieceTrace& p : b.pieces) {
    std::printf("%s  |   t %-30s %-11s F %-28s %s%s\n", ind.c_str(), interval_text(p.t, 9).c_str(),
                p.mean_value ? "mean-value" : "",
                p.box.is_empty() ? "-" : interval_text(p.f).c_str(), verdict(p),
                p.partial ? ", partial domain" : "");
  }
  std::printf("%s  | result %s", ind.c_str(), beam_result_name(b.result));
  if (b.result != BeamResult::kMiss) {
    std::printf(": t_near %s", num_text(b.t_near, 9).c_str());
    if (b.result == BeamResult::kFull) std::printf(", t_far %s", num_text(b.t_far, 9).c_str());
  }
  if (!b.full_reason.empty()) std::printf(" (%s)", b.full_reason.c_str());
  std::printf("\n");
  if (!b.estimator.is_empty()) {
    std::printf("%s  | estimator %s, width %s\n", ind.c_str(), interval_text(b.estimator).c_str(),
                b.estimator.is_finite() ? num_text(b.estimator.width()).c_str() : "inf");
  }
  std::printf("%s  | decision %s: %s\n", ind.c_str(), beam_decision_name(b.decision),
              decision_reason(b, st).c_str());
  if (is_shaded(b)) {
    std::printf("%s  | shading: %s at %s, normal %s, colour %s (linear %s), area %s\n", ind.c_str(),
                b.center_ray_hit     ? "central ray hit"
                : b.coverage_ray_hit ? "central ray missed; a coverage ray's hit"
                                     : "central ray missed; hit box centre, mid-point normal",
                vec_text(b.point).c_str(), vec_text(b.normal, 4).c_str(),
                hex_color(b.color).c_str(), vec_text(b.color, 4).c_str(),
                num_text(b.rect.area()).c_str());
    if (b.coverage_rays > 0) {
      std::printf(
          "%s  | weight %s: %d of its %d rays (central and coverage rays) found the surface\n",
          ind.c_str(), num_text(b.weight, 4).c_str(), b.coverage_hits, b.coverage_rays);
      if (b.behind_hits > 0) {
        std::printf(
            "%s  |   and %d coverage ray%s that missed it met surface further back (shown "
            "there, in the weight)\n",
            ind.c_str(), b.behind_hits, b.behind_hits == 1 ? "" : "s");
      }
    }
  }
}

/// One sample ray of a point-sampling method: where it searched and what it hit.
void print_ray(std::size_t i, const RayTrace& ray) {
  std::printf("ray %zu through (%s, %s): t in %s: ", i, num_text(ray.u, 8).c_str(),
              num_text(ray.v, 8).c_str(), interval_text(ray.searched, 9).c_str());
  if (ray.hit) {
    std::printf("hit at t %s (%s) at %s, normal %s, colour %s\n",
                interval_text(ray.t_hit, 12).c_str(), ray.certified ? "certified" : "possible",
                vec_text(ray.point).c_str(), vec_text(ray.normal, 4).c_str(),
                hex_color(ray.color).c_str());
  } else {
    std::printf("miss, background %s\n", hex_color(ray.color).c_str());
  }
}

/// How the pixel's colour was made from its parts, in words.
const char* colour_origin(const RenderSettings& st, const PixelResult& r, double raised) {
  if (r.certificate == PixelCertificate::kEmpty) return "certified background";
  if (st.method == RenderMethod::kPoint || st.method == RenderMethod::kGrid) {
    return "the mean of its rays";
  }
  if (st.method == RenderMethod::kAdaptive) {
    return "the area-weighted mean of its squares' corner-ray colours";
  }
  if (raised != 1.0) {
    return "the area-weighted mean of its parts, the Partial parts' weights raised so that the "
           "pixel shows the least coverage of one that may hold surface";
  }
  return "the area-weighted mean of its parts";
}

}  // namespace

std::string num_text(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string decision_reason(const BeamTrace& b, const RenderSettings& st) {
  const double w = b.estimator.is_empty() ? 0 : b.estimator.width();
  switch (b.decision) {
    case BeamDecision::kBackground:
      return b.level < 0 ? "Miss: every pixel of the block is certified background"
                         : "Miss: this area is certified background";
    case BeamDecision::kDescend:
      if (b.level < 0) return "not a Miss: the smaller blocks below search from its t_near";
      return "not a Miss: the " + std::string(method_name(st.method)) +
             " rays below search from its t_near";
    case BeamDecision::kShadeFull:
      return "Full and estimator width " + num_text(w) + " <= threshold " +
             num_text(st.estimator_threshold) + ": shaded once for its whole area";
    case BeamDecision::kShadeLeaf:
      return "at max_level " + std::to_string(st.max_level) + ": shaded as surface" +
             (b.result == BeamResult::kPartial ? ", uncertain (Partial)" : ", covered (Full)");
    case BeamDecision::kSplit:
      if (b.result == BeamResult::kPartial) {
        return "Partial above max_level " + std::to_string(st.max_level) + ": split into 4";
      }
      if (!b.estimator.is_finite()) {
        return "Full, but |grad F| is not bounded away from 0 on the hit box (estimator "
               "unbounded): split into 4";
      }
      return "Full, estimator width " + num_text(w) + " > threshold " +
             num_text(st.estimator_threshold) + ": split into 4";
  }
  return "";
}

bool is_shaded(const BeamTrace& b) {
  return b.decision == BeamDecision::kShadeFull || b.decision == BeamDecision::kShadeLeaf;
}

void print_inspection_tree(const Scene& scene, const RenderSettings& st, const PixelTrace& tr,
                           const PixelResult& r) {
  print_heading(scene, st, tr, r);
  // Depth in the tree of every beam (from its parent chain).
  std::vector<int> depth(tr.beams.size(), 0);
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    const int p = tr.beams[i].parent;
    depth[i] = p >= 0 ? depth[static_cast<std::size_t>(p)] + 1 : 0;
    print_beam(i, tr.beams[i], std::string(static_cast<std::size_t>(2 * depth[i]), ' '), st);
  }
  for (std::size_t i = 0; i < tr.rays.size(); ++i) print_ray(i, tr.rays[i]);
  std::printf("pixel colour %s (linear %s): %s\n", hex_color(tr.color).c_str(),
              vec_text(tr.color).c_str(), colour_origin(st, r, tr.raised_coverage));
}

}  // namespace iaa::cli
