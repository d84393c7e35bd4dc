// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// The enclosure octree as `iaa enclose` runs it: its settings from the command's options (depth or
// cell size, refinement, box limit), checked with messages that name the options; the run, whose
// one common failure (too many boxes) says which options to change; and the JSON report. The
// Python module's enclose() goes through the same functions, so its report and errors are the
// command's.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "core/exec.h"
#include "enclose/octree.h"
#include "expr/tape.h"

namespace iaa::app {

/// The options of `iaa enclose` that shape the octree.
struct OctreeOptions {
  int depth = 7;
  bool depth_given = false;  ///< --depth was given
  double cell_size = 0;      ///< replaces depth when cell_size_given
  bool cell_size_given = false;
  int refine_possible = 0;
  std::uint64_t max_boxes = EncloseSettings{}.max_boxes;
};

/// Throws iaa::Error when the options contradict each other (--depth and --cell-size both).
void check_octree_options(const OctreeOptions& options);

/// The octree's settings for `bounds`, validated; an error names the command-line option
/// (--depth, --cell-size, --refine-possible, --max-boxes, --bounds) rather than the setting.
EncloseSettings enclose_settings(const Box3& bounds, const OctreeOptions& options);

/// Runs the octree. Running out of boxes is the one failure a user meets in practice, so its
/// message says which options produced it and which to change.
Enclosure run_enclose(const Tape& tape, const EncloseSettings& settings, const Exec& exec);

/// Wall-clock seconds of the two parts of `iaa enclose`.
struct EncloseTimes {
  double enclose = 0;
  double write = 0;
};

/// The JSON report of `iaa enclose --report` (without "output", which the command adds): the
/// surface, bounds, settings, counts per class and per depth, evaluations and times.
nlohmann::json enclose_report_json(const std::string& expression, const EncloseSettings& settings,
                                   const Enclosure& enclosure, const EncloseTimes& times,
                                   int threads);

}  // namespace iaa::app
