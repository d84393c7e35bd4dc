// The enclosure octree as `iaa enclose` runs it (enclosing.h).
#include "app/enclosing.h"

#include "app/balance.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include "core/error.h"

namespace iaa::app {
namespace {

/// Short form for messages.
std::string brief(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// The smallest depth whose cells are no larger than `size` along every axis.
int depth_for_cell_size(const Box3& b, double size) {
  if (!(size > 0) || !std::isfinite(size)) {
    throw SettingError("--cell-size must be a positive number, got " + brief(size));
  }
  const Vec3 e = b.size();
  const double edge = std::fmax(e.x, std::fmax(e.y, e.z));
  int d = 1;
  while (d <= EncloseSettings::kMaxDepth && std::ldexp(edge, -d) > size) ++d;
  if (d > EncloseSettings::kMaxDepth) {
    throw SettingError("--cell-size " + brief(size) + " needs more than depth " +
                       std::to_string(EncloseSettings::kMaxDepth) +
                       " (the limit) for a box edge of " + brief(edge) +
                       "; the smallest cell size here is " +
                       brief(std::ldexp(edge, -EncloseSettings::kMaxDepth)));
  }
  return d;
}

}  // namespace

void check_octree_options(const OctreeOptions& o) {
  if (o.depth_given && o.cell_size_given)
    throw Error("give either --depth or --cell-size, not both");
}

EncloseSettings enclose_settings(const Box3& bounds, const OctreeOptions& o) {
  check_octree_options(o);
  EncloseSettings s;
  s.bounds = bounds;
  s.depth = o.cell_size_given ? depth_for_cell_size(s.bounds, o.cell_size) : o.depth;
  s.refine_possible = o.refine_possible;
  s.max_boxes = o.max_boxes;
  try {
    s.validate();
  } catch (const SettingError& e) {
    std::string m = e.what();
    for (auto [from, to] :
         {std::pair{"refine_possible", "--refine-possible"}, std::pair{"max_boxes", "--max-boxes"},
          std::pair{"depth", "--depth"}, std::pair{"bounds", "--bounds"}}) {
      if (m.rfind(from, 0) == 0) m = to + m.substr(std::string(from).size());
    }
    throw SettingError(m);
  }
  return s;
}

Enclosure run_enclose(const Tape& tape, const EncloseSettings& s, const Exec& exec) {
  try {
    return enclose(tape, s, exec);
  } catch (const SettingError& e) {
    std::string m = e.what();
    if (m.rfind("max_boxes", 0) == 0) {
      m = "--max-boxes " + std::to_string(s.max_boxes) +
          " exceeded: the enclosure needs more boxes" + " at --depth " + std::to_string(s.depth) +
          (s.refine_possible ? " --refine-possible " + std::to_string(s.refine_possible) : "") +
          "; lower the depth or raise --max-boxes (no file was written)";
    }
    throw SettingError(m);
  }
}

nlohmann::json enclose_report_json(const std::string& expression, const EncloseSettings& s,
                                   const Enclosure& enc, const EncloseTimes& t, int threads) {
  nlohmann::json j;
  j["expression"] = expression;
  j["bounds"] = {{s.bounds.lo.x, s.bounds.hi.x},
                 {s.bounds.lo.y, s.bounds.hi.y},
                 {s.bounds.lo.z, s.bounds.hi.z}};
  j["settings"] = {
      {"depth", s.depth}, {"refine_possible", s.refine_possible}, {"max_boxes", s.max_boxes}};
  j["threads"] = threads;
  j["boxes"] = enc.cells.size();
  j["crossing"] = enc.count(CellClass::kCrossing);
  j["possible"] = enc.count(CellClass::kPossible);
  nlohmann::json by = nlohmann::json::array();
  for (std::size_t d = 0; d < enc.counts_by_depth.size(); ++d) {
    const auto& c = enc.counts_by_depth[d];
    if (c[0] + c[1] > 0) by.push_back({{"depth", d}, {"crossing", c[0]}, {"possible", c[1]}});
  }
  j["by_depth"] = by;
  j["evaluations"] = enc.evaluations;
  j["corner_evaluations"] = enc.corner_evaluations;
  j["expansion_signs"] = enc.expansion_signs;
  j["time_s"] = {{"enclose", t.enclose}, {"write", t.write}};
  if (!enc.balance.ranks.empty()) j["mpi"] = balance_json(enc.balance);
  return j;
}

}  // namespace iaa::app
