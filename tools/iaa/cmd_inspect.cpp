// `iaa inspect`: why one pixel came out as it did. Runs the renderer's own code path for the pixel
// (render_pixel, the function render() calls per pixel) with a PixelTrace, and prints every
// beam (the screen blocks above the pixel, then its quadtree of sub-beams), every depth piece the
// search tested with its F bounds and verdict, the result, the estimator and the decision, the
// shading and the final colour: as an indented tree, or as JSON. `--vtk` writes the same as a VTK
// multiblock (viz/inspect_vtk.h) with the enclosure boxes and the octree mesh near the pixel.
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/png.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "enclose/octree.h"
#include "iaa/command.h"
#include "mesh/octree_mesher.h"
#include "render/camera.h"
#include "render/render.h"
#ifdef IAA_HAVE_VIZ
#include "viz/inspect_vtk.h"
#endif

namespace iaa::cli {
namespace {

/// Marks an integer option that was not given.
constexpr int kUnset = -2147483647;

struct InspectOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string pixel;
  std::string method;
  int max_level = -1;
  double threshold = -1, depth_tol = -1, adaptive_threshold = -1;
  int width = kUnset, height = kUnset;
  bool no_shadows = false, shadows = false;
  bool json = false;
  std::string vtk;
  int enclose_depth = 7;
  int refine_possible = 2;
  double near = 3;
  bool no_mesh = false;
};

// ---- Text helpers ---------------------------------------------------------------------------

std::string num(double v, int digits = 6) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string interval_text(const Interval& i, int digits = 6) {
  if (i.is_empty()) return "empty";
  return "[" + num(i.lo(), digits) + ", " + num(i.hi(), digits) + "]";
}

std::string vec_text(const Vec3& v, int digits = 5) {
  return "(" + num(v.x, digits) + ", " + num(v.y, digits) + ", " + num(v.z, digits) + ")";
}

std::string rect_text(const PixelRect& r) {
  return "[" + num(r.u0, 8) + ", " + num(r.u1, 8) + "] x [" + num(r.v0, 8) + ", " + num(r.v1, 8) +
         "]";
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

/// Why the renderer did what it did with a beam, from the trace and the settings.
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
      return "Full and estimator width " + num(w) + " <= threshold " + num(st.estimator_threshold) +
             ": shaded once for its whole area";
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
      return "Full, estimator width " + num(w) + " > threshold " + num(st.estimator_threshold) +
             ": split into 4";
  }
  return "";
}

bool shaded(const BeamTrace& b) {
  return b.decision == BeamDecision::kShadeFull || b.decision == BeamDecision::kShadeLeaf;
}

/// Verdict of a piece in words.
const char* verdict(const DepthPieceTrace& p) {
  if (p.box.is_empty()) return "outside the bounds";
  return p.kept ? "kept (0 in F)" : "excluded (0 not in F)";
}

// ---- The text tree --------------------------------------------------------------------------

void print_tree(const Scene& scene, const RenderSettings& st, const PixelTrace& tr,
                const PixelResult& r) {
  const Vec3 colour = tr.color;
  std::printf("%s: pixel %d,%d of %dx%d, method %s", scene.name.c_str(), tr.x, tr.y, scene.width,
              scene.height, std::string(method_name(st.method)).c_str());
  if (st.method == RenderMethod::kIaa) {
    std::printf(" (max_level %d, estimator threshold %s, depth tolerance %s)", st.max_level,
                num(st.estimator_threshold).c_str(), num(st.depth_tolerance).c_str());
  } else if (st.method == RenderMethod::kAdaptive) {
    std::printf(" (max_level %d, adaptive threshold %s)", st.max_level,
                num(st.adaptive_threshold).c_str());
  } else if (st.method == RenderMethod::kGrid) {
    std::printf(" (%dx%d rays)", st.grid_n, st.grid_n);
  }
  std::printf("\n");
  std::printf(
      "colour %s (linear %s), certificate %s, coverage %s, %u %s, %u evaluations (+%u on "
      "screen blocks)\n",
      hex_color(colour).c_str(), vec_text(colour).c_str(), certificate_name(r.certificate),
      num(r.coverage).c_str(), r.leaves, st.method == RenderMethod::kIaa ? "leaves" : "rays",
      r.evals, r.block_evals);

  // Depth in the tree of every beam (from its parent chain).
  std::vector<int> depth(tr.beams.size(), 0);
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    const int p = tr.beams[i].parent;
    depth[i] = p >= 0 ? depth[static_cast<std::size_t>(p)] + 1 : 0;
  }
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    const BeamTrace& b = tr.beams[i];
    const std::string ind(static_cast<std::size_t>(2 * depth[i]), ' ');
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
      std::printf("%s  |   t %-30s %-11s F %-28s %s%s\n", ind.c_str(),
                  interval_text(p.t, 9).c_str(), p.mean_value ? "mean-value" : "",
                  p.box.is_empty() ? "-" : interval_text(p.f).c_str(), verdict(p),
                  p.partial ? ", partial domain" : "");
    }
    std::printf("%s  | result %s", ind.c_str(), beam_result_name(b.result));
    if (b.result != BeamResult::kMiss) {
      std::printf(": t_near %s", num(b.t_near, 9).c_str());
      if (b.result == BeamResult::kFull) std::printf(", t_far %s", num(b.t_far, 9).c_str());
    }
    if (!b.full_reason.empty()) std::printf(" (%s)", b.full_reason.c_str());
    std::printf("\n");
    if (!b.estimator.is_empty()) {
      std::printf("%s  | estimator %s, width %s\n", ind.c_str(), interval_text(b.estimator).c_str(),
                  b.estimator.is_finite() ? num(b.estimator.width()).c_str() : "inf");
    }
    std::printf("%s  | decision %s: %s\n", ind.c_str(), beam_decision_name(b.decision),
                decision_reason(b, st).c_str());
    if (shaded(b)) {
      std::printf(
          "%s  | shading: %s at %s, normal %s, colour %s (linear %s), area %s\n", ind.c_str(),
          b.center_ray_hit ? "central ray hit"
                           : "central ray missed; hit box centre, mid-point normal",
          vec_text(b.point).c_str(), vec_text(b.normal, 4).c_str(), hex_color(b.color).c_str(),
          vec_text(b.color, 4).c_str(), num(b.rect.area()).c_str());
    }
  }
  for (std::size_t i = 0; i < tr.rays.size(); ++i) {
    const RayTrace& ray = tr.rays[i];
    std::printf("ray %zu through (%s, %s): t in %s: ", i, num(ray.u, 8).c_str(),
                num(ray.v, 8).c_str(), interval_text(ray.searched, 9).c_str());
    if (ray.hit) {
      std::printf("hit at t %s (%s) at %s, normal %s, colour %s\n",
                  interval_text(ray.t_hit, 12).c_str(), ray.certified ? "certified" : "possible",
                  vec_text(ray.point).c_str(), vec_text(ray.normal, 4).c_str(),
                  hex_color(ray.color).c_str());
    } else {
      std::printf("miss, background %s\n", hex_color(ray.color).c_str());
    }
  }
  const char* how = "the area-weighted mean of its parts";
  if (r.certificate == PixelCertificate::kEmpty) {
    how = "certified background";
  } else if (st.method == RenderMethod::kPoint || st.method == RenderMethod::kGrid) {
    how = "the mean of its rays";
  } else if (st.method == RenderMethod::kAdaptive) {
    how = "the area-weighted mean of its squares' corner-ray colours";
  }
  std::printf("pixel colour %s (linear %s): %s\n", hex_color(colour).c_str(),
              vec_text(colour).c_str(), how);
}

// ---- JSON ----------------------------------------------------------------------------------

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

nlohmann::json to_json(const Scene& scene, const std::string& path, const RenderSettings& st,
                       const PixelTrace& tr, const PixelResult& r) {
  nlohmann::json j;
  j["scene"] = scene.name;
  j["file"] = path;
  j["image"] = {{"width", scene.width}, {"height", scene.height}};
  j["pixel"] = {tr.x, tr.y};
  j["settings"] = {{"method", std::string(method_name(st.method))},
                   {"grid", st.grid_n},
                   {"max_level", st.max_level},
                   {"estimator_threshold", st.estimator_threshold},
                   {"depth_tolerance", st.depth_tolerance},
                   {"adaptive_threshold", st.adaptive_threshold},
                   {"shadows", st.shadows}};
  // The colour exactly as render() stores it in its Film (floats), and as the PNG's bytes.
  j["result"] = {{"color", {r.color.r, r.color.g, r.color.b}},
                 {"rgb8", jrgb8({r.color.r, r.color.g, r.color.b})},
                 {"certificate", certificate_name(r.certificate)},
                 {"coverage", r.coverage},
                 {"leaves", r.leaves},
                 {"evaluations", r.evals},
                 {"block_evaluations", r.block_evals}};
  nlohmann::json beams = nlohmann::json::array();
  for (std::size_t i = 0; i < tr.beams.size(); ++i) {
    const BeamTrace& b = tr.beams[i];
    nlohmann::json jb;
    jb["index"] = i;
    jb["parent"] = b.parent;
    jb["kind"] = b.level < 0 ? "screen-block" : (b.level == 0 ? "pixel" : "sub-beam");
    jb["level"] = b.level;
    jb["rect"] = {b.rect.u0, b.rect.v0, b.rect.u1, b.rect.v1};
    jb["searched"] = jinterval(b.searched);
    nlohmann::json pieces = nlohmann::json::array();
    for (const DepthPieceTrace& p : b.pieces) {
      pieces.push_back({{"t", jinterval(p.t)},
                        {"box", jbox(p.box)},
                        {"f", p.box.is_empty() ? nlohmann::json(nullptr) : jinterval(p.f)},
                        {"form", p.mean_value ? "mean-value" : "natural"},
                        {"verdict", p.box.is_empty() ? "outside" : (p.kept ? "kept" : "excluded")},
                        {"partial_domain", p.partial}});
    }
    jb["pieces"] = std::move(pieces);
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
    if (shaded(b)) {
      jb["shading"] = {{"center_ray_hit", b.center_ray_hit},
                       {"point", jvec(b.point)},
                       {"normal", jvec(b.normal)},
                       {"color", jvec(b.color)},
                       {"rgb8", jrgb8(b.color)},
                       {"area", b.rect.area()}};
    }
    jb["evaluations"] = b.evals;
    beams.push_back(std::move(jb));
  }
  j["beams"] = std::move(beams);
  nlohmann::json rays = nlohmann::json::array();
  for (const RayTrace& ray : tr.rays) {
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
    rays.push_back(std::move(jr));
  }
  j["rays"] = std::move(rays);
  return j;
}

#ifdef IAA_HAVE_VIZ
// ---- What lies near the pixel ---------------------------------------------------------------

/// Screen rectangle of a pixel widened by `near` pixels, and a test of whether points project
/// into it.
struct ScreenWindow {
  const CameraFrame& frame;
  double u0, v0, u1, v1;

  /// True when the bounding rectangle of the points' projections meets the window; points
  /// behind the eye make the answer false (they are never in view).
  template <class Points>
  bool meets(const Points& pts) const {
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY;
    for (const Vec3& p : pts) {
      const Vec3 rel = p - frame.eye;
      const double t = dot(rel, frame.forward);
      if (!(t > 0)) return false;
      const double u = dot(rel, frame.right) / (t * frame.scale) + frame.half_w;
      const double v = frame.half_h - dot(rel, frame.up) / (t * frame.scale);
      lo_u = std::fmin(lo_u, u);
      hi_u = std::fmax(hi_u, u);
      lo_v = std::fmin(lo_v, v);
      hi_v = std::fmax(hi_v, v);
    }
    return lo_u <= u1 && hi_u >= u0 && lo_v <= v1 && hi_v >= v0;
  }
};

struct Nearby {
  EncloseSettings settings;
  Enclosure enclosure;  ///< cells near the pixel
  std::uint64_t all_cells = 0;
  bool have_mesh = false;
  TriangleSoup mesh;  ///< triangles near the pixel
  std::uint64_t all_triangles = 0;
};

Nearby nearby(const Scene& scene, const InspectOptions& o, int x, int y) {
  Nearby n;
  n.settings.bounds = scene.bounds;
  n.settings.depth = o.enclose_depth;
  n.settings.refine_possible = o.refine_possible;
  try {
    n.settings.validate();
  } catch (const SettingError& e) {
    throw SettingError(std::string("--enclose-depth / --refine-possible: ") + e.what());
  }
  const Enclosure enc = enclose(*scene.tape, n.settings);
  n.all_cells = enc.cells.size();
  const CameraFrame frame(scene.camera, scene.width, scene.height);
  const ScreenWindow win{frame, x - o.near, y - o.near, x + 1 + o.near, y + 1 + o.near};
  n.enclosure.bounds = enc.bounds;
  n.enclosure.counts_by_depth.assign(enc.counts_by_depth.size(), {0, 0});
  for (const Cell& c : enc.cells) {
    const Box3 b = enc.box(c);
    std::array<Vec3, 8> corners;
    for (int k = 0; k < 8; ++k) {
      corners[static_cast<std::size_t>(k)] = {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                                              (k & 4) ? b.hi.z : b.lo.z};
    }
    if (!win.meets(corners)) continue;
    n.enclosure.cells.push_back(c);
    ++n.enclosure.counts_by_depth[c.depth][c.cls == CellClass::kCrossing ? 0 : 1];
  }
  if (o.no_mesh || enc.cells.empty()) return n;
  OctreeMeshSettings ms;
  ms.enclose = n.settings;
  ms.validate();
  const OctreeMesh mesh = extract_mesh(*scene.tape, enc, ms);
  n.have_mesh = true;
  n.all_triangles = mesh.soup.triangles.size();
  std::vector<std::uint32_t> remap(mesh.soup.vertices.size(), UINT32_MAX);
  for (const auto& t : mesh.soup.triangles) {
    const std::array<Vec3, 3> p = {mesh.soup.vertices[t[0]], mesh.soup.vertices[t[1]],
                                   mesh.soup.vertices[t[2]]};
    if (!win.meets(p)) continue;
    std::array<std::uint32_t, 3> nt{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& m = remap[t[static_cast<std::size_t>(k)]];
      if (m == UINT32_MAX) {
        m = static_cast<std::uint32_t>(n.mesh.vertices.size());
        n.mesh.vertices.push_back(mesh.soup.vertices[t[static_cast<std::size_t>(k)]]);
      }
      nt[static_cast<std::size_t>(k)] = m;
    }
    n.mesh.triangles.push_back(nt);
  }
  return n;
}

#endif  // IAA_HAVE_VIZ

// ---- The command ------------------------------------------------------------------------------

void check_output(const std::string& path) {
  const std::filesystem::path target(path);
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw Error("--vtk: cannot write '" + path + "': directory '" + dir.string() +
                "' does not exist");
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    throw Error("--vtk: cannot write '" + path + "': directory '" + dir.string() +
                "' is not writable");
  }
}

void run(const InspectOptions& o) {
  // Everything that can be checked before the work is.
#ifndef IAA_HAVE_VIZ
  if (!o.vtk.empty()) {
    throw Error("--vtk: this iaa was built without VTK (IAA_WITH_VTK=OFF); no .vtm output");
  }
#endif
  if (!o.vtk.empty()) {
    const std::string ext = std::filesystem::path(o.vtk).extension().string();
    if (ext != ".vtm" && ext != ".VTM") {
      throw Error("--vtk: the output must be a .vtm file (a VTK multiblock), got '" + o.vtk + "'");
    }
    check_output(o.vtk);
  }
  if (o.enclose_depth < 0 || o.enclose_depth > EncloseSettings::kMaxDepth) {
    throw SettingError("--enclose-depth must lie in 0.." +
                       std::to_string(EncloseSettings::kMaxDepth) + " (0: no enclosure), got " +
                       std::to_string(o.enclose_depth));
  }
  if (!(o.near >= 0 && o.near <= 1000)) {
    throw SettingError("--near must lie in 0..1000 pixels, got " + num(o.near));
  }
  {
    std::string ext = std::filesystem::path(o.scene).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!ext.empty() && ext != ".toml") {
      throw Error("'" + o.scene + "': unknown file type '" + ext +
                  "'; iaa inspect reads a scene file (.toml, see docs/scene-format.md)");
    }
  }
  const auto px = parse_int_pair(o.pixel, "--pixel");
  std::vector<std::string> sets = o.sets;
  if (o.width != kUnset) sets.push_back("image.width=" + std::to_string(o.width));
  if (o.height != kUnset) sets.push_back("image.height=" + std::to_string(o.height));
  const Scene scene = app::load_scene(o.scene, sets);
  const int x = px[0], y = px[1];
  if (x < 0 || y < 0 || x >= scene.width || y >= scene.height) {
    throw Error("--pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                std::to_string(scene.width) + "x" + std::to_string(scene.height) +
                " image: X must lie in 0.." + std::to_string(scene.width - 1) + " and Y in 0.." +
                std::to_string(scene.height - 1));
  }
  RenderSettings st = scene.settings;
  if (!o.method.empty()) st.method = parse_method(o.method, &st.grid_n);
  if (o.max_level >= 0) st.max_level = o.max_level;
  if (o.threshold >= 0) st.estimator_threshold = o.threshold;
  if (o.depth_tol >= 0) st.depth_tolerance = o.depth_tol;
  if (o.adaptive_threshold >= 0) st.adaptive_threshold = o.adaptive_threshold;
  if (o.no_shadows) st.shadows = false;
  if (o.shadows) st.shadows = true;
  st.validate();

  PixelTrace trace;
  const PixelResult r = render_pixel(scene, st, x, y, &trace);

  // The .vtm first: when it cannot be written, nothing is printed either.
  std::string wrote;
#ifdef IAA_HAVE_VIZ
  if (!o.vtk.empty()) {
    viz::InspectionInput in;
    in.scene = &scene;
    in.settings = st;
    in.trace = &trace;
    Nearby n;
    if (o.enclose_depth > 0) {
      n = nearby(scene, o, x, y);
      in.enclosure = &n.enclosure;
      in.enclose_settings = n.settings;
      if (n.have_mesh) in.mesh = &n.mesh;
    }
    viz::write_vtm_atomically(o.vtk, viz::inspection_to_multiblock(in));
    wrote = "wrote " + o.vtk;
    if (o.enclose_depth > 0) {
      wrote += " with " + std::to_string(n.enclosure.cells.size()) + " of " +
               std::to_string(n.all_cells) + " enclosure boxes (depth " +
               std::to_string(o.enclose_depth) + ") and " +
               (n.have_mesh ? std::to_string(n.mesh.triangles.size()) + " of " +
                                  std::to_string(n.all_triangles) + " mesh triangles"
                            : std::string("no mesh")) +
               " within " + num(o.near) + " pixels of the pixel";
    }
  }
#endif

  if (o.json) {
    nlohmann::json j = to_json(scene, o.scene, st, trace, r);
    if (!o.vtk.empty()) j["vtk"] = o.vtk;
    std::printf("%s\n", j.dump(1).c_str());
  } else {
    print_tree(scene, st, trace, r);
  }
  if (!o.json && !wrote.empty()) std::printf("%s\n", wrote.c_str());
}

void setup(CLI::App& app) {
  auto o = std::make_shared<InspectOptions>();
  add_scene_options(app, &o->scene, &o->sets);
  app.add_option("--pixel", o->pixel, "the pixel X,Y (column from the left, row from the top)")
      ->required();
  app.add_option("--method", o->method, "iaa (default), point, 'grid N' (or gridN), adaptive");
  app.add_option("--max-level", o->max_level,
                 "subdivision levels below the pixel (0..6, default 2)");
  app.add_option("--threshold", o->threshold, "iaa: estimator threshold (0..2)");
  app.add_option("--depth-tol", o->depth_tol, "iaa: depth tolerance relative to the beam width");
  app.add_option("--adaptive-threshold", o->adaptive_threshold,
                 "adaptive: colour threshold (0..1)");
  app.add_option("--width", o->width, "image width in pixels (overrides the scene)");
  app.add_option("--height", o->height, "image height in pixels (overrides the scene)");
  app.add_flag("--no-shadows", o->no_shadows, "do not cast shadow rays");
  app.add_flag("--shadows", o->shadows, "cast shadow rays");
  app.add_flag("--json", o->json, "print the trace as JSON instead of a tree");
  app.add_option("--vtk", o->vtk,
                 "write a VTK multiblock (.vtm): beam pyramids, hit slabs, depth boxes, hit "
                 "points, enclosure boxes and mesh near the pixel (view with iaa-viz)");
  app.add_option("--enclose-depth", o->enclose_depth,
                 "--vtk: depth of the enclosure whose boxes near the pixel are shown (0: none)")
      ->capture_default_str();
  app.add_option("--refine-possible", o->refine_possible,
                 "--vtk: extra levels for possible enclosure boxes")
      ->capture_default_str();
  app.add_option("--near", o->near,
                 "--vtk: boxes and triangles whose projection comes within this many pixels of "
                 "the pixel are shown")
      ->capture_default_str();
  app.add_flag("--no-mesh", o->no_mesh, "--vtk: do not mesh the enclosure");
  app.footer(
      "The pixel goes through exactly the code the full render runs for it (the screen blocks\n"
      "above it, then its beams), so its colour and certificate are those of `iaa render` with\n"
      "the same options.\n\n"
      "Examples:\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --json > neck.json\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --vtk neck.vtm\n"
      "  iaa-viz neck.vtm -o neck.png\n"
      "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --method point\n"
      "  iaa inspect data/scenes/chubs.toml --pixel 100,120 --max-level 3 --threshold 0.5\n"
      "See docs/inspect.md.");
  app.callback([o] { run(*o); });
}

CommandRegistrar reg{{"inspect",
                      "why one pixel came out as it did: every beam, depth test and decision", 25,
                      setup}};

}  // namespace
}  // namespace iaa::cli
