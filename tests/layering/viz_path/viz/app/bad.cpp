// Fixture: viz includes the tools through the source-tree include root.
#include "tools/iaa/command.h"
