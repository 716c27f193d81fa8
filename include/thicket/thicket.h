#pragma once
/// Everything a user of the library needs: load a scene, build a structure by its spec, cast rays.
///
///   thicket::Scene scene = thicket::load_scene("bunny.ply");
///   auto accel = thicket::build_accel("bvh:builder=sweep-sah", scene);
///   thicket::Hit hit = accel->intersect({{0, 0.1f, 1}, 0.0f, {0, 0, -1}, thicket::kInfinity});
#include "thicket/accel/accel.h"
#include "thicket/accel/registry.h"
#include "thicket/brute/brute_force.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"
#include "thicket/scene/scene.h"
