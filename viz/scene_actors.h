// The look of each layer: the VTK actors that draw it (colours by category or by role, opacity,
// edges, point markers and normal arrows) and the legend entries that explain them.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "core/vec.h"
#include "viz/scene_layer.h"

class vtkRenderer;

namespace iaa::viz {

/// One line of the legend: a label drawn in its colour.
struct LegendEntry {
  std::string label;
  Vec3 color;
};

/// The legend's entries in the order they were first added, each label once.
class Legend {
 public:
  /// Adds an entry unless one with the same label is there already.
  void add(const std::string& label, Vec3 color) {
    if (seen_.insert(label).second) entries_.push_back({label, color});
  }
  /// The entries, first added first.
  const std::vector<LegendEntry>& entries() const { return entries_; }

 private:
  std::set<std::string> seen_;
  std::vector<LegendEntry> entries_;
};

/// Adds the actors that draw `layers` to `renderer` and the entries that explain them to
/// `legend`. `focus_radius` (scene_camera.h) sizes the normal arrows of hit points.
void add_layer_actors(vtkRenderer* renderer, const std::vector<Layer>& layers, double focus_radius,
                      Legend& legend);

}  // namespace iaa::viz
