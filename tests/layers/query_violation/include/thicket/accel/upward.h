#pragma once
// Planted: the interface may not include the batch queries that sit on it.
#include "thicket/query/ray_rows.h"
