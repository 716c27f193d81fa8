// Planted: a structure may not include the query floor (it answers the queries, not asks them).
#include "thicket/query/point_queries.h"
