// Fixture: core includes a module above it.
#include "render/film.h"
