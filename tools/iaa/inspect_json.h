// The JSON report of `iaa inspect --json`: one pixel's trace with every beam, depth piece, decision
// and sample ray, for scripts and tests (docs/inspect.md describes the fields).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "render/render.h"
#include "render/trace.h"

namespace iaa::cli {

/// The trace of pixel tr.x, tr.y as JSON: scene (`path` is its file), image size, settings,
/// result, beams and rays. Numbers that JSON cannot hold (inf, nan) are written as strings.
nlohmann::json inspection_json(const Scene& scene, const std::string& path,
                               const RenderSettings& st, const PixelTrace& tr,
                               const PixelResult& r);

}  // namespace iaa::cli
