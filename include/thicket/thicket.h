#pragma once
/// Everything a user of the library needs: load a scene, build a structure by its spec, cast rays.
///
///   thicket::Scene scene = thicket::load_scene("bunny.ply");
///   auto accel = thicket::build_accel("bvh:builder=sweep-sah", scene);
///   thicket::Hit hit = accel->intersect({{0, 0.1f, 1}, 0.0f, {0, 0, -1}, thicket::kInfinity});
///
/// Rows of floats in, answers out (query/ray_rows.h); closest points, distances, occupancy
/// (query/point_queries.h). The structures by name (one folder each) for users who build them
/// directly, and the shape kernels a Scene can hold next to triangles (prims/shapes.h).
#include "thicket/accel/accel.h"
#include "thicket/instances/instances.h"
#include "thicket/query/point_queries.h"
#include "thicket/query/ray_rows.h"
#include "thicket/accel/registry.h"
#include "thicket/bih/bih.h"
#include "thicket/brute/brute_force.h"
#include "thicket/bsp/bsp.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/core/error.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"
#include "thicket/kdtree/kdtree.h"
#include "thicket/obb/obb.h"
#include "thicket/octree/octree.h"
#include "thicket/prims/shapes.h"
#include "thicket/prims/triangles.h"
#include "thicket/scene/scene.h"
#include "thicket/tetra/tetra.h"
