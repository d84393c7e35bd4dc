// A mesh set against the ray trace's certificates of the same view (docs/design.md, "Meshing and
// comparison"). Per pixel, what the mesh shows (any triangle in the pixel's beam) is compared with
// what the IAA render proved there:
// - lost: IAA certifies that the pixel shows surface, the mesh shows none there;
// - wrong: IAA certifies that no ray through the pixel meets the surface, the mesh shows surface;
// - agreement otherwise; pixels IAA could not decide (uncertain) are counted apart, split by
//   whether the mesh shows surface there.
// CGAL-free: what the mesh shows comes in as plain per-pixel data (mesh/mesh_raycast.h computes
// it).
#pragma once

#include <cstdint>
#include <vector>

#include "render/film.h"

namespace iaa {

enum class PixelAgreement : std::uint8_t {
  kNotCompared = 0,     ///< outside the rendered window
  kBothEmpty = 1,       ///< certified empty, no mesh
  kBothSurface = 2,     ///< certified surface, mesh there
  kLost = 3,            ///< certified surface, no mesh
  kWrong = 4,           ///< certified empty, mesh there
  kUncertainMesh = 5,   ///< IAA undecided, mesh there
  kUncertainEmpty = 6,  ///< IAA undecided, no mesh (a possible loss that cannot be proved)
};
const char* agreement_name(PixelAgreement a);

struct CompareCounts {
  std::uint64_t pixels = 0;  ///< compared pixels
  std::uint64_t both_empty = 0, both_surface = 0, lost = 0, wrong = 0;
  std::uint64_t uncertain_mesh = 0, uncertain_empty = 0;
};

struct Comparison {
  int width = 0, height = 0;
  std::vector<PixelAgreement> pixel;  ///< row-major from the top-left
  CompareCounts counts;
};

/// Compares a film's certificates with a per-pixel flag "the mesh shows surface here" (1/0, same
/// size and order as the film). Throws iaa::Error when the sizes differ.
Comparison compare_with_film(const Film& film, const std::vector<std::uint8_t>& mesh_shows);

/// The marks of the diff picture (linear RGB): three clear colours, none of them light.
inline constexpr Rgb kLostColor{0.9f, 0.05f, 0.05f};       ///< red
inline constexpr Rgb kWrongColor{0.05f, 0.2f, 0.95f};      ///< blue
inline constexpr Rgb kUndecidedColor{0.95f, 0.6f, 0.05f};  ///< amber: undecided, no mesh

/// A render colour faded towards white (55% of it over white), behind the marks: every channel
/// at least 0.45.
inline Rgb faded(const Rgb& c) {
  return {0.55f * c.r + 0.45f, 0.55f * c.g + 0.45f, 0.55f * c.b + 0.45f};
}

/// The diff picture in linear RGB: the render faded towards white (faded()), with lost pixels
/// kLostColor, wrong pixels kWrongColor, and undecided pixels without mesh kUndecidedColor.
std::vector<Rgb> diff_picture(const Film& film, const Comparison& comparison);

}  // namespace iaa
