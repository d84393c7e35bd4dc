// Shared argument parsing of the `iaa` subcommands.
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "iaa/command.h"

namespace iaa::cli {

namespace {
std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) parts.push_back(item);
  if (!text.empty() && text.back() == ',') parts.push_back("");
  return parts;
}
}  // namespace

double parse_double(const std::string& s, const std::string& what) {
  // strtod rather than stod: stod rejects subnormal numbers as out of range.
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  const std::size_t used = static_cast<std::size_t>(end - s.c_str());
  if (s.empty() || used != s.size() || !std::isfinite(v)) {
    throw Error(what + ": '" + s + "' is not a finite number");
  }
  return v;
}

std::array<double, 3> parse_triple(const std::string& text, const std::string& what) {
  const auto parts = split(text);
  if (parts.size() != 3) throw Error(what + ": expected three numbers X,Y,Z, got '" + text + "'");
  return {parse_double(parts[0], what), parse_double(parts[1], what), parse_double(parts[2], what)};
}

std::array<int, 2> parse_int_pair(const std::string& text, const std::string& what) {
  const auto parts = split(text);
  if (parts.size() != 2) throw Error(what + ": expected two integers X,Y, got '" + text + "'");
  std::array<int, 2> out{};
  for (int i = 0; i < 2; ++i) {
    const double v = parse_double(parts[static_cast<std::size_t>(i)], what);
    if (v != std::floor(v) || std::fabs(v) > 1e9) {
      throw Error(what + ": '" + parts[static_cast<std::size_t>(i)] + "' is not an integer");
    }
    out[static_cast<std::size_t>(i)] = static_cast<int>(v);
  }
  return out;
}

Box3 parse_box(const std::string& text, const std::string& what) {
  static const char* kAxes[3] = {"x", "y", "z"};
  const auto ranges = split(text);
  if (ranges.size() != 3) {
    throw Error(what + ": expected three ranges X0:X1,Y0:Y1,Z0:Z1, got '" + text + "'");
  }
  Box3 box;
  for (int i = 0; i < 3; ++i) {
    const std::string& r = ranges[static_cast<std::size_t>(i)];
    const auto colon = r.find(':', 1);
    if (colon == std::string::npos) {
      throw Error(what + ": the range for " + kAxes[i] + " must be LO:HI, got '" + r + "'");
    }
    const double lo = parse_double(r.substr(0, colon), what + " (" + kAxes[i] + " low)");
    const double hi = parse_double(r.substr(colon + 1), what + " (" + kAxes[i] + " high)");
    if (lo > hi) {
      throw Error(what + ": the " + kAxes[i] + " range " + r +
                  " is inverted; write LO:HI with LO <= HI");
    }
    box.lo[i] = lo;
    box.hi[i] = hi;
  }
  return box;
}

Params parse_params(const std::vector<std::string>& items) {
  Params p;
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw Error("--param: expected NAME=VALUE, got '" + item + "'");
    }
    const std::string name = item.substr(0, eq);
    p[name] = parse_double(item.substr(eq + 1), "--param " + name);
  }
  return p;
}

void add_scene_options(CLI::App& app, std::string* path, std::vector<std::string>* overrides) {
  app.add_option("scene", *path, "scene file (TOML, see docs/scene-format.md)")->required();
  app.add_option("--set", *overrides,
                 "override a scene key, KEY=VALUE with a dotted key (repeatable), e.g. "
                 "camera.fov=30, image.width=200, surface.params.r=0.4");
}

}  // namespace iaa::cli
