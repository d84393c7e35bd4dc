// Fixture: viz includes the tools.
#include "iaa/command.h"
