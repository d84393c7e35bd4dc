// The result of a render: colour per pixel as linear floats, and per pixel what was proved there
// (the certificate), how much work it took, and how much of it is covered. The library returns a
// Film; the tools turn it into PNGs, AOV images and a JSON report.
#pragma once

#include <cstdint>
#include <vector>

#include "core/spread.h"
#include "core/vec.h"
#include "scene/settings.h"

namespace iaa {

/// What a render proved about one pixel.
enum class PixelCertificate : std::uint8_t {
  kEmpty = 0,        ///< certified: no ray through the pixel meets the surface
  kCovered = 1,      ///< certified: some part of the pixel certainly shows the surface
  kUncertain = 2,    ///< the surface may or may not be seen there (shaded conservatively)
  kNotRendered = 3,  ///< outside the render window
};
const char* certificate_name(PixelCertificate c);

/// Linear RGB colour of a pixel.
struct Rgb {
  float r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb& a, const Rgb& b) {
    return a.r == b.r && a.g == b.g && a.b == b.b;
  }
};

/// Totals over the rendered pixels.
struct FilmStats {
  std::uint64_t pixels = 0;        ///< pixels rendered (the window)
  std::uint64_t empty = 0;         ///< certificate kEmpty
  std::uint64_t covered = 0;       ///< certificate kCovered
  std::uint64_t uncertain = 0;     ///< certificate kUncertain
  std::uint64_t evals = 0;         ///< interval evaluations, including screen-block elimination
  std::uint64_t leaves = 0;        ///< shaded parts (IAA leaves) or rays (point methods)
  std::uint64_t block_evals = 0;   ///< of `evals`, those spent on screen blocks above pixels
  std::uint64_t pruned_evals = 0;  ///< of `evals`, those with a tape pruned of min/max branches
  double covered_area = 0;         ///< sum of per-pixel coverage (in pixels)
};

/// A rendered image and its per-pixel records, row-major from the top-left pixel.
struct Film {
  int width = 0, height = 0;
  PixelWindow window;       ///< the pixels that were rendered
  RenderSettings settings;  ///< what was asked
  std::vector<Rgb> color;   ///< linear colour
  std::vector<PixelCertificate> certificate;
  std::vector<std::uint32_t> leaves;  ///< IAA leaves / rays shaded per pixel
  std::vector<std::uint32_t> evals;   ///< interval evaluations per pixel (not blocks)
  std::vector<float> coverage;        ///< fraction of the pixel's area shown as surface
  FilmStats stats;
  double seconds = 0;  ///< wall time of render()
  /// How the root blocks were shared between processes (Exec::spread); empty without a spread.
  SpreadBalance balance;

  Film() = default;
  Film(int w, int h);
  std::size_t index(int x, int y) const {
    return std::size_t(y) * std::size_t(width) + std::size_t(x);
  }
  const Rgb& at(int x, int y) const { return color[index(x, y)]; }
  PixelCertificate cert(int x, int y) const { return certificate[index(x, y)]; }
  /// The certificate image as one byte per pixel (PixelCertificate values), for `iaa compare`.
  std::vector<std::uint8_t> certificate_bytes() const;
};

}  // namespace iaa
