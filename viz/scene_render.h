// The viewer's public entry point: what `iaa-viz` and the tests use to show iaa's VTK overlays.
// One header for the whole pipeline, each step in its own file:
//   scene_layer.h   layers, their roles, and the categorical arrays iaa's writers mark cells with
//   scene_load.h    reading .vtm/.vtu/.vtp/.vtk/.ply/.obj files into layers
//   scene_camera.h  the camera a file records, automatic framing
//   scene_stage.h   views, actors, legend; drawing into an image or an interactive window
#pragma once

#include "viz/scene_camera.h"
#include "viz/scene_layer.h"
#include "viz/scene_load.h"
#include "viz/scene_stage.h"
