// Allowed, for the layers.detects_violation test: prims may include core.
#include "thicket/core/aabb.h"
