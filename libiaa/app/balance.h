// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// The load balance of a run shared by processes under mpirun (core/spread.h): as JSON for the
// reports of render and enclose, and as the summary's line.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "core/spread.h"

namespace iaa::app {

/// {"processes", "max_over_mean_evaluations", "ranks": [{"rank", "items", "evaluations",
/// "busy_seconds", "idle_seconds"}...]}.
nlohmann::json balance_json(const SpreadBalance& balance);

/// One line: processes, max/mean evaluations, the largest idle time and whose it was.
std::string balance_summary(const SpreadBalance& balance);

}  // namespace iaa::app
