// Fixture: VTK outside viz/.
#include <vtkPolyData.h>
