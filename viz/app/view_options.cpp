// Shared iaa-viz options and the final render-or-show step (see view_options.h).
#include "viz/app/view_options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

#include "app/files.h"
#include "app/png.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "viz/app/xserver.h"

namespace iaa::viz {

void add_view_options(CLI::App& app, ViewOptions& o) {
  app.add_option("-o,--output", o.output,
                 "write a PNG here (no display needed); without it, open a window");
  app.add_option("--size", o.size, "image or window size WxH (16..8192)")->capture_default_str();
  app.add_option("--camera", o.camera,
                 "scene (the scene's camera), auto (fit the data; a pixel's beam is seen from its "
                 "side), or EYE:LOOK:UP as ex,ey,ez:lx,ly,lz:ux,uy,uz. Default: auto for an "
                 "inspection, else the scene's camera when one is known, else auto");
  app.add_option("--fov", o.fov, "vertical field of view in degrees (overrides the camera's)");
  app.add_option("--scene", o.scene, "a scene file (TOML) whose camera --camera scene uses");
  app.add_option("--title", o.title, "a title drawn at the top left");
  app.add_flag("--no-legend", o.no_legend, "draw no legend");
}

std::pair<int, int> parse_size(const std::string& text) {
  const auto x = text.find_first_of("xX");
  int w = 0, h = 0;
  bool ok = x != std::string::npos;
  if (ok) {
    try {
      std::size_t u1 = 0, u2 = 0;
      const std::string a = text.substr(0, x), b = text.substr(x + 1);
      w = std::stoi(a, &u1);
      h = std::stoi(b, &u2);
      ok = u1 == a.size() && u2 == b.size() && !a.empty() && !b.empty();
    } catch (...) {
      ok = false;
    }
  }
  if (!ok) throw Error("--size: expected WxH such as 800x600, got '" + text + "'");
  if (w < 16 || h < 16 || w > 8192 || h > 8192) {
    throw SettingError("--size " + text + ": width and height must lie in 16..8192");
  }
  return {w, h};
}

namespace {

Vec3 parse_vec(const std::string& text, const std::string& what) {
  std::stringstream ss(text);
  std::string item;
  double v[3];
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n == 3)
      throw Error("--camera: " + what + " must be three numbers x,y,z, got '" + text + "'");
    std::size_t used = 0;
    try {
      v[n] = std::stod(item, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v[n])) {
      throw Error("--camera: " + what + ": '" + item + "' is not a finite number");
    }
    ++n;
  }
  if (n != 3) throw Error("--camera: " + what + " must be three numbers x,y,z, got '" + text + "'");
  return {v[0], v[1], v[2]};
}

}  // namespace

ViewCamera parse_camera(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ':')) parts.push_back(item);
  if (parts.size() != 3) {
    throw Error(
        "--camera: expected scene, auto, or EYE:LOOK:UP (ex,ey,ez:lx,ly,lz:ux,uy,uz), got '" +
        text + "'");
  }
  ViewCamera c;
  c.eye = parse_vec(parts[0], "EYE");
  c.look_at = parse_vec(parts[1], "LOOK");
  c.up = parse_vec(parts[2], "UP");
  c.fov_deg = 30;
  const Vec3 d = c.look_at - c.eye;
  if (length(d) == 0) throw Error("--camera: EYE and LOOK are the same point");
  if (length(cross(d, c.up)) <= 1e-12 * length(d) * length(c.up)) {
    throw Error("--camera: UP must not be parallel to the viewing direction LOOK - EYE");
  }
  return c;
}

ViewCamera camera_of(const Scene& s) {
  ViewCamera c;
  c.eye = s.camera.eye;
  c.look_at = s.camera.look_at;
  c.up = s.camera.up;
  c.fov_deg = s.camera.fov_deg;
  return c;
}

void check_view(const ViewOptions& o) {
  parse_size(o.size);
  if (o.fov != 0 && !(o.fov >= Camera::kMinFovDeg && o.fov <= Camera::kMaxFovDeg)) {
    // The same limits as a scene's camera.fov.
    throw SettingError("--fov must lie in [0.001, 179] degrees (as a scene's camera.fov), got " +
                       std::to_string(o.fov));
  }
  if (o.camera != "scene" && o.camera != "auto" && o.camera != "default") parse_camera(o.camera);
  if (!o.output.empty()) {
    if (app::extension_of(o.output) != "png") {
      throw Error("-o " + o.output + ": iaa-viz writes PNG images; give a file ending in .png");
    }
    const auto parent = std::filesystem::path(o.output).parent_path();
    std::error_code ec;
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
      throw Error("-o " + o.output + ": the directory '" + parent.string() + "' does not exist");
    }
    return;
  }
  if (!have_display()) {
    throw Error(
        "no display to open a window on (DISPLAY is unset); give -o FILE.png to render "
        "to a file");
  }
  if (!display_reachable()) {
    throw Error(std::string("cannot open the X display DISPLAY=") + std::getenv("DISPLAY") +
                "; check DISPLAY (and xauth), or give -o FILE.png to render to a file");
  }
}

void show(const std::vector<Layer>& layers, const ViewOptions& o,
          const std::optional<ViewCamera>& recorded, const Scene* scene) {
  // Checked before rendering so that a typo does not cost a render (the callers check first too).
  check_view(o);
  const auto [w, h] = parse_size(o.size);

  std::unique_ptr<Scene> owned;
  if (!o.scene.empty()) {
    owned = std::make_unique<Scene>(app::load_scene(o.scene));
    scene = owned.get();
  }
  std::optional<ViewCamera> scene_cam = recorded;
  if (scene) scene_cam = camera_of(*scene);

  ViewSettings v;
  v.width = w;
  v.height = h;
  v.legend = !o.no_legend;
  v.title = o.title;
  v.viewports = o.viewports;
  v.captions = o.captions;
  const double aspect = double(w) / double(o.viewports) / double(h);
  bool has_focus = false;
  for (const Layer& l : layers) {
    has_focus |= l.role == LayerRole::kSlabs || l.role == LayerRole::kDepthBoxes ||
                 l.role == LayerRole::kPoints;
  }
  if (o.camera == "scene") {
    if (!scene_cam) {
      throw Error(
          "--camera scene: no camera is known; give --scene SCENE.toml, or show a file "
          "written by iaa inspect (it records its scene's camera)");
    }
    v.camera = scene_cam;
  } else if (o.camera == "auto" || (o.camera == "default" && (has_focus || !scene_cam))) {
    v.camera = auto_camera(layers, scene_cam, aspect);
  } else if (o.camera == "default") {
    v.camera = scene_cam;
  } else {
    v.camera = parse_camera(o.camera);
  }
  if (o.fov != 0) v.camera->fov_deg = o.fov;

  if (o.output.empty()) {
    show_interactive(layers, v);
    return;
  }
  // A PNG needs no display of the user's: without one, or when the one DISPLAY names cannot be
  // opened (VTK would abort), render on a private Xvfb.
  std::unique_ptr<PrivateXServer> xserver;
  if (!have_display()) {
    xserver = PrivateXServer::start(w, h);
  } else if (!display_reachable()) {
    std::fprintf(stderr,
                 "iaa-viz: cannot open the X display DISPLAY=%s; rendering on a private Xvfb\n",
                 std::getenv("DISPLAY"));
    xserver = PrivateXServer::start(w, h);
  }
  const RgbImage img = render_to_image(layers, v);
  app::Image8 out(img.width, img.height, 3);
  out.data = img.rgb;
  app::write_png(o.output, out);
  std::printf("wrote %s (%dx%d, %zu layers)\n", o.output.c_str(), img.width, img.height,
              layers.size());
}

}  // namespace iaa::viz
