// A stand-in for libiaa_vtk.so from another build: the right entry point, interface number and
// version, but a different layout fingerprint. tests/e2e/viz_plugin_cli.sh checks that iaa
// refuses it and says why (bin/fake/libiaa_vtk.so, built only where the real plugin is).
#include "viz/plugin_api.h"

extern "C" __attribute__((visibility("default"))) const iaa::viz::PluginApi* iaa_viz_plugin_api() {
  static const iaa::viz::PluginApi api = [] {
    iaa::viz::PluginApi a;
    a.layout ^= 1;  // as if one of the types passed had another size
    return a;
  }();
  return &api;
}
