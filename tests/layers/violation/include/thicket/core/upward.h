#pragma once
// Deliberately wrong, for the layers.detects_violation test: core may not include scene.
#include "thicket/scene/scene.h"
