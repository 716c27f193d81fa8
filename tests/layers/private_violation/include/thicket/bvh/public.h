#pragma once
// Deliberately wrong, for the layers.detects_private_violation test: a public header including a
// private one (src/bvh/...), which is not installed.
#include "bvh/builder_choices.h"
