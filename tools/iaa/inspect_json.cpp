// The JSON report of `iaa inspect` (see inspect_json.h).
#include "iaa/inspect_json.h"

#include <cmath>

#include "app/png.h"
#include "iaa/inspect_text.h"
#include "iaa/render_flags.h"

namespace iaa::cli {
namespace {

/// A number, or "inf" / "-inf" / "nan" (JSON has no such numbers).
nlohmann::json jnum(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

nlohmann::json jinterval(const Interval& i) {
  if (i.is_empty()) return nullptr;
  return nlohmann::json::array({jnum(i.lo()), jnum(i.hi())});
}

nlohmann::json jbox(const IBox& b) {
  if (b.is_empty()) return nullptr;
  return nlohmann::json::array({jinterval(b.x), jinterval(b.y), jinterval(b.z)});
}

nlohmann::json jvec(const Vec3& v) {
  return nlohmann::json::array({jnum(v.x), jnum(v.y), jnum(v.z)});
}

nlohmann::json jrgb8(const Vec3& c) {
  return nlohmann::json::array({app::to_byte(c.x), app::to_byte(c.y), app::to_byte(c.z)});
}

/// The colour exactly as render() stores it in its Film (floats), and as the PNG's bytes.
nlohmann::json result_json(const PixelResult& r) {
  return {{"color", {r.color.r, r.color.g, r.color.b}},
          {"rgb8", jrgb8({r.color.r, r.color.g, r.color.b})},
          {"certificate", certificate_name(r.certificate)},
          {"coverage", r.coverage},
          {"leaves", r.leaves},
          {"evaluations", r.evals},
          {"block_evaluations", r.block_evals}};
}

nlohmann::json piece_json(const DepthPieceTrace& p) {
  return {{"t", jinterval(p.t)},
          {"box", jbox(p.box)},
          {"f", p.box.is_empty() ? nlohmann::json(nullptr) : jinterval(p.f)},
          {"form", p.mean_value ? "mean-value" : "natural"},
          {"verdict", p.box.is_empty() ? "outside" : (p.kept ? "kept" : "excluded")},
          {"partial_domain", p.partial}};
}

nlohmann::json beam_json(std::size_t i, const BeamTrace& b, const RenderSettings& st) {
  nlohmann::json jb;
  jb["index"] = i;
  jb["parent"] = b.parent;
  jb["kind"] = b.level < 0 ? "screen-block" : (b.level == 0 ? "pixel" : "sub-beam");
  jb["level"] = b.level;
  jb["rect"] = {b.rect.u0, b.rect.v0, b.rect.u1, b.rect.v1};
  jb["searched"] = jinterval(b.searched);
  jb["pieces"] = nlohmann::json::array();
  for (const DepthPieceTrace& p : b.pieces) jb["pieces"].push_back(piece_json(p));
  jb["result"] = beam_result_name(b.result);
  if (b.result != BeamResult::kMiss) {
    jb["t_near"] = jnum(b.t_near);
    // Only a Full beam has a t_far (every ray hits by then); a Partial one searched to its end.
    if (b.result == BeamResult::kFull) jb["t_far"] = jnum(b.t_far);
    jb["hit_box"] = jbox(b.hit_box);
  }
  jb["full_reason"] = b.full_reason;
  jb["estimator"] = jinterval(b.estimator);
  jb["estimator_width"] =
      b.estimator.is_empty() ? nlohmann::json(nullptr) : jnum(b.estimator.width());
  jb["decision"] = beam_decision_name(b.decision);
  jb["why"] = decision_reason(b, st);
  if (is_shaded(b)) {
    jb["shading"] = {{"center_ray_hit", b.center_ray_hit},
                     {"point", jvec(b.point)},
                     {"normal", jvec(b.normal)},
                     {"color", jvec(b.color)},
                     {"rgb8", jrgb8(b.color)},
                     {"area", b.rect.area()},
                     {"weight", b.weight}};
    if (b.coverage_rays > 0) {
      jb["shading"]["coverage_rays"] = b.coverage_rays;
      jb["shading"]["coverage_hits"] = b.coverage_hits;
      jb["shading"]["behind_hits"] = b.behind_hits;
      jb["shading"]["coverage_ray_hit"] = b.coverage_ray_hit;
    }
  }
  jb["evaluations"] = b.evals;
  return jb;
}

nlohmann::json ray_json(const RayTrace& ray) {
  nlohmann::json jr = {{"u", ray.u},
                       {"v", ray.v},
                       {"searched", jinterval(ray.searched)},
                       {"hit", ray.hit},
                       {"certified", ray.certified},
                       {"color", jvec(ray.color)}};
  if (ray.hit) {
    jr["t_hit"] = jinterval(ray.t_hit);
    jr["point"] = jvec(ray.point);
    jr["normal"] = jvec(ray.normal);
  }
  return jr;
}

}  // namespace

nlohmann::json inspection_json(const Scene& scene, const std::string& path,
                               const RenderSettings& st, const PixelTrace& tr,
                               const PixelResult& r) {
  nlohmann::json j;
  j["scene"] = scene.name;
  j["file"] = path;
  j["image"] = {{"width", scene.width}, {"height", scene.height}};
  j["pixel"] = {tr.x, tr.y};
  j["settings"] = app::render_settings_json(st);
  j["result"] = result_json(r);
  if (tr.raised_coverage != 1.0) j["result"]["partial_weights_raised_by"] = tr.raised_coverage;
  j["beams"] = nlohmann::json::array();
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    j["beams"].push_back(beam_json(i, tr.beams[i], st));
  }
  j["rays"] = nlohmann::json::array();
  for (const RayTrace& ray : tr.rays) j["rays"].push_back(ray_json(ray));
  return j;
}

}  // namespace iaa::cli
