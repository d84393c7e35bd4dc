// Comparison of a mesh view with the render's certificates; see compare.h.
#include "compare/compare.h"

#include <string>

#include "core/error.h"

namespace iaa {

const char* agreement_name(PixelAgreement a) {
  switch (a) {
    case PixelAgreement::kNotCompared:
      return "not compared";
    case PixelAgreement::kBothEmpty:
      return "both empty";
    case PixelAgreement::kBothSurface:
      return "both surface";
    case PixelAgreement::kLost:
      return "lost";
    case PixelAgreement::kWrong:
      return "wrong";
    case PixelAgreement::kUncertainMesh:
      return "uncertain, mesh";
    case PixelAgreement::kUncertainEmpty:
      return "uncertain, no mesh";
  }
  return "?";
}

Comparison compare_with_film(const Film& film, const std::vector<std::uint8_t>& mesh_shows) {
  const std::size_t n = std::size_t(film.width) * std::size_t(film.height);
  if (film.certificate.size() != n || mesh_shows.size() != n) {
    throw Error("compare: the mesh view (" + std::to_string(mesh_shows.size()) +
                " pixels) and the render (" + std::to_string(n) + " pixels) differ in size");
  }
  Comparison c;
  c.width = film.width;
  c.height = film.height;
  c.pixel.assign(n, PixelAgreement::kNotCompared);
  CompareCounts& k = c.counts;
  for (std::size_t i = 0; i < n; ++i) {
    const bool mesh = mesh_shows[i] != 0;
    PixelAgreement a = PixelAgreement::kNotCompared;
    switch (film.certificate[i]) {
      case PixelCertificate::kEmpty:
        a = mesh ? PixelAgreement::kWrong : PixelAgreement::kBothEmpty;
        (mesh ? k.wrong : k.both_empty) += 1;
        break;
      case PixelCertificate::kCovered:
        a = mesh ? PixelAgreement::kBothSurface : PixelAgreement::kLost;
        (mesh ? k.both_surface : k.lost) += 1;
        break;
      case PixelCertificate::kUncertain:
        a = mesh ? PixelAgreement::kUncertainMesh : PixelAgreement::kUncertainEmpty;
        (mesh ? k.uncertain_mesh : k.uncertain_empty) += 1;
        break;
      case PixelCertificate::kNotRendered:
        break;
    }
    if (a != PixelAgreement::kNotCompared) ++k.pixels;
    c.pixel[i] = a;
  }
  return c;
}

std::vector<Rgb> diff_picture(const Film& film, const Comparison& c) {
  std::vector<Rgb> out(c.pixel.size());
  for (std::size_t i = 0; i < c.pixel.size(); ++i) {
    const Rgb base = i < film.color.size() ? film.color[i] : Rgb{1, 1, 1};
    Rgb p = faded(base);  // so that the marks stand out
    switch (c.pixel[i]) {
      case PixelAgreement::kLost:
        p = kLostColor;
        break;
      case PixelAgreement::kWrong:
        p = kWrongColor;
        break;
      case PixelAgreement::kUncertainEmpty:
        p = kUndecidedColor;
        break;
      default:
        break;
    }
    out[i] = p;
  }
  return out;
}

}  // namespace iaa
