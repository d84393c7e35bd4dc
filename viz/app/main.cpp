// `iaa-viz`: looks at iaa's VTK overlays. Renders any mix of .vtm/.vtu/.vtp/.vtk/.ply/.obj files
// to a PNG (headless: it starts its own Xvfb when DISPLAY is unset) or opens an interactive
// window; `iaa-viz enclose SCENE` and `iaa-viz mesh SCENE` compute the enclosure or the mesh of a
// scene with the iaa library and show it in one command.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "viz/app/shortcuts.h"
#include "viz/app/view_options.h"

namespace iaa::viz {
namespace {

struct FilesOptions {
  std::vector<std::string> files;
  ViewOptions view;
};

void run_files(const FilesOptions& o) {
  if (o.files.empty()) throw Error("no files given; see iaa-viz --help");
  check_view(o.view);
  std::vector<Layer> layers;
  std::optional<ViewCamera> recorded;
  for (const std::string& f : o.files) {
    std::vector<Layer> more = load_layers(f, &recorded);
    for (Layer& l : more) layers.push_back(std::move(l));
  }
  show(layers, o.view, recorded, /*scene=*/nullptr);
}

const char* kFooter =
    "Examples:\n"
    "  iaa inspect data/scenes/teardrop.toml --pixel 256,250 --vtk neck.vtm\n"
    "  iaa-viz neck.vtm -o neck.png                  # beams, hit slabs, depth boxes\n"
    "  iaa-viz teardrop.vtu mesh.ply -o both.png --camera auto --size 1024x768\n"
    "  iaa-viz boxes.vtu --camera 2,1,3:0,0,0:0,1,0 --fov 30 -o boxes.png\n"
    "  iaa-viz enclose data/scenes/teardrop.toml --depth 6 -o boxes.png\n"
    "  iaa-viz mesh data/scenes/chubs.toml -o mesh.png\n"
    "  iaa-viz neck.vtm                               # interactive window (needs a display)\n"
    "Without DISPLAY, iaa-viz starts its own Xvfb to render (package 'xvfb').";

int run_main(int argc, char** argv) {
  // The shortcuts are dispatched by hand so that a file named like them is not mistaken for one.
  if (argc >= 2 && (std::string(argv[1]) == "enclose" || std::string(argv[1]) == "mesh")) {
    return run_shortcut(argv[1], argc - 1, argv + 1);
  }
  CLI::App app{
      "iaa-viz: render iaa's VTK overlays (inspection multiblocks, enclosure boxes, meshes) to a "
      "PNG or an interactive window.\n"
      "  iaa-viz FILES... [-o out.png] [--size WxH] [--camera scene|auto|EYE:LOOK:UP]\n"
      "  iaa-viz enclose SCENE [options]   boxes of the guaranteed enclosure of a scene\n"
      "  iaa-viz mesh SCENE [options]      the certified mesh of a scene next to its enclosure"};
  FilesOptions o;
  app.add_option("files", o.files, "files to show: " + known_extensions());
  add_view_options(app, o.view);
  app.footer(kFooter);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  run_files(o);
  return 0;
}

}  // namespace
}  // namespace iaa::viz

int main(int argc, char** argv) {
  try {
    return iaa::viz::run_main(argc, argv);
  } catch (const iaa::Error& e) {
    std::fprintf(stderr, "iaa-viz: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "iaa-viz: error: out of memory\n");
    return 1;
  }
}
