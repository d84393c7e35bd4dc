// The text report of `iaa inspect`: one pixel's trace as an indented tree of beams, depth tests,
// decisions and shading, and the words for a beam's decision that the JSON report shares.
#pragma once

#include <string>

#include "render/render.h"
#include "render/trace.h"
#include "scene/scene.h"

namespace iaa::cli {

/// A number in printf's %g form with `digits` significant digits.
std::string num_text(double v, int digits = 6);

/// Why the renderer did what it did with a beam, in words, from the trace and the settings.
std::string decision_reason(const BeamTrace& b, const RenderSettings& st);

/// True when the beam was shaded (a leaf of the pixel's quadtree, or a Full beam shaded whole).
bool is_shaded(const BeamTrace& b);

/// Prints the trace of pixel tr.x, tr.y on stdout: a heading with the settings and the result,
/// every beam with its depth tests, result, estimator, decision and shading, every sample ray,
/// and how the pixel's colour was made.
void print_inspection_tree(const Scene& scene, const RenderSettings& st, const PixelTrace& tr,
                           const PixelResult& r);

}  // namespace iaa::cli
