// libFuzzer target over scene files: any byte string is either rejected with an iaa::Error (a
// message naming the key or the line) or is a scene that renders at 16x16 and encloses at depth 3
// with results that keep their invariants. Leading lines "#set KEY=VALUE" (TOML comments, so the
// rest still parses as the file) are applied as `--set` overrides, as `iaa render --set` does.
// Anything else (a crash, a sanitizer report, another exception, a broken invariant, a run over
// the -timeout) is a finding. Seeds: data/scenes/*.toml and tests/fuzz/scene_corpus/.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "enclose/octree.h"
#include "io/scene_toml.h"
#include "render/render.h"

namespace {

/// Splits the leading "#set KEY=VALUE" lines off as overrides; the text stays whole (they are
/// comments to TOML).
std::vector<iaa::SceneOverride> leading_overrides(std::string_view text) {
  std::vector<iaa::SceneOverride> out;
  constexpr std::string_view kSet = "#set ";
  while (text.substr(0, kSet.size()) == kSet) {
    const std::size_t end = text.find('\n');
    out.push_back(iaa::parse_override(text.substr(kSet.size(), end - kSet.size())));
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return out;
}

/// The scene's own render settings made small: 16x16 pixels, at most 2 levels below the pixel
/// and 4x4 rays per pixel, every pixel rendered. What is left of a pathological scene's cost is
/// its expression's length (bounded by -max_len).
iaa::RenderSettings small_render(iaa::Scene* scene) {
  scene->width = scene->height = 16;
  iaa::RenderSettings st = scene->settings;
  st.max_level = std::min(st.max_level, 2);
  st.grid_n = std::min(st.grid_n, 4);
  st.window = {};
  return st;
}

void check_film(const iaa::Film& f) {
  for (std::size_t i = 0; i < f.color.size(); ++i) {
    const iaa::Rgb& c = f.color[i];
    if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b)) std::abort();
    if (!(f.coverage[i] >= 0.0f && f.coverage[i] <= 1.0f)) std::abort();
    if (f.certificate[i] == iaa::PixelCertificate::kNotRendered) std::abort();
  }
}

/// Leaves lie on the grid of their depth, hold 0 in their value, and are counted per depth.
void check_enclosure(const iaa::Enclosure& e, const iaa::EncloseSettings& s) {
  std::uint64_t counted = 0;
  for (const auto& c : e.counts_by_depth) counted += c[0] + c[1];
  if (counted != e.cells.size()) std::abort();
  for (const iaa::Cell& c : e.cells) {
    if (c.depth > s.depth + s.refine_possible) std::abort();
    for (const std::uint32_t i : c.index) {
      if (i >> c.depth != 0) std::abort();
    }
    if (!c.f.contains_zero()) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  iaa::Scene scene;
  try {
    scene = iaa::parse_scene(text, "fuzz.toml", leading_overrides(text));
  } catch (const iaa::Error&) {
    return 0;  // rejected with a message: the expected outcome for most inputs
  }
  // Past parse_scene every setting is checked: render and enclose must not throw.
  const iaa::Exec exec{1, nullptr};
  check_film(iaa::render(scene, small_render(&scene), exec));
  iaa::EncloseSettings es;
  es.bounds = scene.bounds;
  es.depth = 3;
  es.refine_possible = 1;
  es.max_boxes = 4096;  // 8^4: depth 4 in full, never exceeded
  es.all_corner_signs = true;
  check_enclosure(iaa::enclose(*scene.tape, es, exec), es);
  return 0;
}
