// The film's constructor and the names of pixel certificates.
#include "render/film.h"

namespace iaa {

const char* certificate_name(PixelCertificate c) {
  switch (c) {
    case PixelCertificate::kEmpty:
      return "empty";
    case PixelCertificate::kCovered:
      return "covered";
    case PixelCertificate::kUncertain:
      return "uncertain";
    case PixelCertificate::kNotRendered:
      return "not-rendered";
  }
  return "?";
}

Film::Film(int w, int h)
    : width(w),
      height(h),
      color(std::size_t(w) * std::size_t(h)),
      certificate(std::size_t(w) * std::size_t(h), PixelCertificate::kNotRendered),
      leaves(std::size_t(w) * std::size_t(h), 0),
      evals(std::size_t(w) * std::size_t(h), 0),
      coverage(std::size_t(w) * std::size_t(h), 0.0f) {}

std::vector<std::uint8_t> Film::certificate_bytes() const {
  std::vector<std::uint8_t> out(certificate.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<std::uint8_t>(certificate[i]);
  return out;
}

}  // namespace iaa
