// Reading .vtm/.vtu/.vtp/.vtk/.ply/.obj files into layers, each with the role its name and arrays
// suggest, and the camera the file records.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "viz/scene_camera.h"
#include "viz/scene_layer.h"

namespace iaa::viz {

/// Guesses a layer's role from its name and arrays.
LayerRole guess_role(const std::string& name, vtkDataSet* data);

/// Reads one file into layers (a multiblock gives one layer per non-empty leaf, named by its
/// block name). In a pixel inspection (a file with hit slabs or hit points), blocks whose name
/// says "coarse", enclosure boxes and beam frusta are outlined (Layer::outline). Throws iaa::Error
/// for a missing or unreadable file or an unknown extension (the message lists the known ones).
/// `camera`, when not null, receives a camera recorded in the file.
std::vector<Layer> load_layers(const std::string& path,
                               std::optional<ViewCamera>* camera = nullptr);

/// The file extensions load_layers reads, for messages ("vtm, vtu, ...").
std::string known_extensions();

}  // namespace iaa::viz
