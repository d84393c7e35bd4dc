// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// What `iaa render` makes of a Film (render/film.h): the 8-bit image, the AOV images (the
// certificate in three colours, the coverage in grey, the leaves and evaluations as heat maps) and
// the JSON report. The command writes them to files; the Python module hands the same bytes over
// as arrays, so the two agree byte for byte.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

#include "app/png.h"
#include "render/film.h"
#include "scene/scene.h"

namespace iaa::app {

/// The image of `iaa render -o`: the film's linear colour through to_byte (app/png.h).
Image8 color_image(const Film& film);

/// The AOV images of `iaa render --aov`, by file name: certificate.png (light grey certified
/// empty, green certified covered, orange uncertain, grey not rendered), coverage.png (grey level
/// of the covered fraction), leaves.png and evals.png (heat maps, black-red-yellow-white on a log
/// scale up to the image's maximum).
std::vector<std::pair<std::string, Image8>> aov_images(const Film& film);

/// Writes aov_images() into directory `dir` (which must exist).
void write_aovs(const Film& film, const std::string& dir);

/// The JSON report of `iaa render --report`: scene, size, window, settings, threads, time, pixel
/// certificates, evaluations, leaves and covered fraction; under mpirun also "mpi", the load
/// balance (app/balance.h).
nlohmann::json render_report_json(const Scene& scene, const Film& film, int threads);

}  // namespace iaa::app
