// The renderer's entry points (pbrt-style): render(scene, settings, exec) returns a Film;
// render_pixel() renders one pixel through exactly the same code path, optionally recording a
// PixelTrace (trace.h) of every sub-beam and depth piece. The library does no I/O.
#pragma once

#include "core/exec.h"
#include "render/film.h"
#include "render/trace.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace iaa {

/// Renders the scene (the window of `settings`, or all of it). Results are identical for any
/// number of threads in `exec`. Throws SettingError for bad settings or Error for a bad camera.
/// Returns early with the pixels done so far when exec.progress is cancelled.
Film render(const Scene& scene, const RenderSettings& settings, const Exec& exec = {});

/// What render_pixel() returns for one pixel; the same numbers render() stores in its Film.
struct PixelResult {
  Rgb color;
  PixelCertificate certificate = PixelCertificate::kEmpty;
  std::uint32_t leaves = 0;
  std::uint32_t evals = 0;        ///< evaluations for this pixel (blocks above it not counted)
  std::uint32_t block_evals = 0;  ///< evaluations of the screen blocks above it (traced only)
  float coverage = 0;
};

/// Renders pixel (x, y) alone, running exactly the code path render() runs for it (including
/// the screen blocks above it). When `trace` is not null, records everything into it.
PixelResult render_pixel(const Scene& scene, const RenderSettings& settings, int x, int y,
                         PixelTrace* trace = nullptr);

}  // namespace iaa
