// libiaa_vtk.so: the table of viz/plugin_api.h, filled with viz/'s functions. The only symbol this
// module exports is the C entry point; everything else (iaa's static libraries, viz/) stays
// inside it, so nothing here interposes on the command's own copies.
#include "viz/box_vtk.h"
#include "viz/enclosure_pvtu.h"
#include "viz/enclosure_vtk.h"
#include "viz/inspect_vtk.h"
#include "viz/plugin_api.h"
#include "viz/vtk_mesher.h"

namespace {

void write_inspection_vtm(const std::string& path, const iaa::viz::InspectionInput& in) {
  iaa::viz::write_vtm_atomically(path, iaa::viz::inspection_to_multiblock(in));
}

iaa::viz::PluginApi make_api() {
  iaa::viz::PluginApi api;
  api.write_enclosure_vtu = &iaa::viz::write_enclosure_vtu;
  api.write_enclosure_vtu_timed = &iaa::viz::write_enclosure_vtu_timed;
  api.write_enclosure_pvtu = &iaa::viz::write_enclosure_pvtu;
  api.write_inspection_vtm = &write_inspection_vtm;
  api.write_boxes_vtu = &iaa::viz::write_boxes_vtu;
  api.run_vtk_mesher = &iaa::viz::run_vtk_mesher;
  return api;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const iaa::viz::PluginApi* iaa_viz_plugin_api() {
  static const iaa::viz::PluginApi api = make_api();
  return &api;
}
