// iaa.render: a render as `iaa render` makes it, handed over as NumPy arrays over the Film's own
// buffers (no copies): the 8-bit image (the PNG's pixels), the linear colour, the certificate,
// coverage, leaves and evaluations per pixel, and the report. iaa.write_png writes an image with
// the command's own PNG writer.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>

#include "app/png.h"
#include "app/render_flags.h"
#include "app/render_output.h"
#include "core/error.h"
#include "py_common.h"
#include "render/render.h"

namespace iaa::py {
namespace {

static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb must be three packed floats");
static_assert(sizeof(PixelCertificate) == 1, "PixelCertificate must be one byte");

/// The C++ side of a render: the Film and its 8-bit image, shared by the arrays over them.
struct RenderData {
  Film film;
  app::Image8 image;
};

struct RenderResult {
  std::shared_ptr<const RenderData> data;
  pb::object image, linear, certificate, coverage, leaves, evaluations, report;
};

/// The render's keyword arguments; None leaves the scene's own value.
struct RenderArgs {
  std::optional<std::string> method;
  std::optional<int> width, height, max_level;
  std::optional<double> threshold, depth_tol, adaptive_threshold;
  std::optional<bool> shadows;
  pb::object window;
};

/// "X0,Y0,X1,Y1" from a string or four integers.
std::string window_text(const pb::object& w) {
  if (pb::isinstance<pb::str>(w)) return w.cast<std::string>();
  std::string out;
  for (const pb::handle& v : pb::iter(w)) {
    if (!out.empty()) out += ',';
    out += std::to_string(v.cast<long long>());
  }
  return out;
}

/// The scene (re-read with the image size as overrides, as --width and --height do) and the
/// settings: the scene's, with the arguments that were given, validated as the command does.
std::pair<Scene, RenderSettings> scene_and_settings(const PyScene& ps, const RenderArgs& a) {
  app::RenderFlags f;
  f.width = a.width;
  f.height = a.height;
  f.max_level = a.max_level;
  f.threshold = a.threshold;
  f.depth_tol = a.depth_tol;
  f.adaptive_threshold = a.adaptive_threshold;
  f.method = a.method.value_or("");
  if (!a.window.is_none()) f.window = window_text(a.window);
  if (a.shadows) (*a.shadows ? f.shadows : f.no_shadows) = true;
  Scene scene =
      a.width || a.height
          ? parse_py_scene(ps.text, ps.source, app::with_image_size(f, ps.overrides)).scene
          : ps.scene;
  RenderSettings st = scene.settings;
  app::apply_render_flags(f, &st);
  st.validate_window(scene.width, scene.height);
  return {std::move(scene), st};
}

RenderResult make_result(std::shared_ptr<RenderData> d, nlohmann::json report) {
  RenderResult r;
  r.data = d;
  const Film& f = d->film;
  const pb::capsule base = owner_capsule(std::shared_ptr<const RenderData>(d));
  const pb::ssize_t h = f.height, w = f.width;
  r.image = array_over(d->image.data.data(), {h, w, 3}, base);
  r.linear = array_over(reinterpret_cast<const float*>(f.color.data()), {h, w, 3}, base);
  r.certificate =
      array_over(reinterpret_cast<const std::uint8_t*>(f.certificate.data()), {h, w}, base);
  r.coverage = array_over(f.coverage.data(), {h, w}, base);
  r.leaves = array_over(f.leaves.data(), {h, w}, base);
  r.evaluations = array_over(f.evals.data(), {h, w}, base);
  r.report = to_python(report);
  return r;
}

RenderResult render_scene(const PyScene& ps, const RenderArgs& args, int threads,
                          const pb::object& progress) {
  const std::pair<Scene, RenderSettings> ss = scene_and_settings(ps, args);
  const Scene& scene = ss.first;  // not a structured binding: the lambda below captures it
  const RenderSettings& settings = ss.second;
  auto data = std::make_shared<RenderData>();
  int used = 0;
  run_cancellable(
      [&](const Exec& exec) {
        data->film = render(scene, settings, exec);
        data->image = app::color_image(data->film);
        used = exec.resolved_threads();
      },
      threads, progress);
  return make_result(data, app::render_report_json(scene, data->film, used));
}

/// The AOV images of `iaa render --aov`, by name without ".png".
pb::dict aov_images(const RenderResult& r) {
  pb::dict out;
  for (auto& [name, image] : app::aov_images(r.data->film)) {
    auto held = std::make_shared<app::Image8>(std::move(image));
    const pb::capsule base = owner_capsule(std::shared_ptr<const app::Image8>(held));
    out[pb::str(name.substr(0, name.size() - 4))] =
        array_over(held->data.data(), {held->height, held->width, 3}, base);
  }
  return out;
}

/// iaa.write_png: an (H, W, 3) or (H, W, 4) uint8 array through the command's PNG writer.
void write_png(const std::filesystem::path& path,
               const pb::array_t<std::uint8_t, pb::array::c_style | pb::array::forcecast>& a) {
  if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4)) {
    throw Error("write_png: expected an (H, W, 3) or (H, W, 4) uint8 array");
  }
  app::Image8 img(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)),
                  static_cast<int>(a.shape(2)));
  std::copy(a.data(), a.data() + a.size(), img.data.begin());
  pb::gil_scoped_release release;
  app::write_png(path.string(), img);
}

}  // namespace

void bind_render(pb::module_& m) {
  pb::class_<RenderResult>(m, "RenderResult", R"doc(
What iaa.render returns. The arrays share the render's memory (no copies), rows from the top.)doc")
      .def_readonly("image", &RenderResult::image,
                    "(H, W, 3) uint8: the pixels of the PNG `iaa render -o` writes")
      .def_readonly("linear", &RenderResult::linear, "(H, W, 3) float32: linear RGB colour")
      .def_readonly("certificate", &RenderResult::certificate,
                    "(H, W) uint8: 0 certified empty, 1 certified covered, 2 uncertain, "
                    "3 not rendered (outside the window)")
      .def_readonly("coverage", &RenderResult::coverage,
                    "(H, W) float32: fraction of each pixel's area shown as surface")
      .def_readonly("leaves", &RenderResult::leaves,
                    "(H, W) uint32: IAA leaves (or rays) shaded per pixel")
      .def_readonly("evaluations", &RenderResult::evaluations,
                    "(H, W) uint32: interval evaluations per pixel (screen blocks not counted)")
      .def_readonly("report", &RenderResult::report,
                    "dict: the JSON report of `iaa render --report`")
      .def("aov_images", &aov_images,
           "dict of (H, W, 3) uint8 images: the certificate, coverage, leaves and evals PNGs of "
           "`iaa render --aov`, by name")
      .def("__repr__", [](const RenderResult& r) {
        const Film& f = r.data->film;
        return "<iaa.RenderResult " + std::to_string(f.width) + "x" + std::to_string(f.height) +
               " " + std::string(method_name(f.settings.method)) + ", " +
               std::to_string(f.stats.uncertain) + " uncertain pixels>";
      });

  m.def(
      "render",
      [](const PyScene& scene, std::optional<std::string> method, std::optional<int> width,
         std::optional<int> height, std::optional<int> max_level, std::optional<double> threshold,
         std::optional<double> depth_tol, std::optional<double> adaptive_threshold,
         std::optional<bool> shadows, const pb::object& window, int threads,
         const pb::object& progress) {
        const RenderArgs a{std::move(method),  width,   height, max_level, threshold, depth_tol,
                           adaptive_threshold, shadows, window};
        return render_scene(scene, a, threads, progress);
      },
      pb::arg("scene"), pb::arg("method") = pb::none(), pb::arg("width") = pb::none(),
      pb::arg("height") = pb::none(), pb::kw_only(), pb::arg("max_level") = pb::none(),
      pb::arg("threshold") = pb::none(), pb::arg("depth_tol") = pb::none(),
      pb::arg("adaptive_threshold") = pb::none(), pb::arg("shadows") = pb::none(),
      pb::arg("window") = pb::none(), pb::arg("threads") = 0, pb::arg("progress") = pb::none(),
      R"doc(
Renders a scene as `iaa render` does, with the same bytes for any thread count.

method: "iaa", "point", "grid N" or "adaptive" (None: the scene's, "iaa" unless its [render] table
says otherwise); width, height: override the scene's image size; max_level, threshold, depth_tol,
adaptive_threshold, shadows, window ((x0, y0, x1, y1), x1 and y1 exclusive): as the command's
flags (docs/render.md). threads: 0 = all cores. progress: None or progress(phase, done, total),
called on this thread about every 50 ms; an exception it raises, or Ctrl-C, cancels the render.
The GIL is released while the render runs. Raises ValueError with the command's message for bad
input.)doc");

  m.def("write_png", &write_png, pb::arg("path"), pb::arg("image"), R"doc(
Writes an (H, W, 3) or (H, W, 4) uint8 image as PNG with the writer `iaa render` uses (the bytes
depend only on the pixels), to a temporary file renamed into place.)doc");
}

}  // namespace iaa::py
