// `iaa-viz enclose SCENE` and `iaa-viz mesh SCENE`: compute the enclosure (or the certified or
// octree mesh) of a scene with the iaa library and show it over the scene's camera in one command.
#pragma once

namespace iaa::viz {

/// Runs the shortcut `name` ("enclose" or "mesh"); argv[0] is the shortcut's name. Returns the
/// exit code (CLI errors) or throws iaa::Error.
int run_shortcut(const char* name, int argc, char** argv);

}  // namespace iaa::viz
