// Deliberately wrong, for the layers.detects_private_violation test: prims may not include the
// private headers of accel/.
#include "accel/dispatch.h"
