// Fixture: the iaa command includes a VTK header of viz/ instead of viz/plugin_api.h.
#include "viz/enclosure_vtk.h"
#include "viz/plugin_api.h"
