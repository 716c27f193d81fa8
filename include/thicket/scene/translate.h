#pragma once
/// A scene moved far from the origin, for precision checks (the double structures' tests and
/// `thicket bench --offset`).
#include "thicket/scene/scene.h"

namespace thicket {

/// The triangles of `scene` (one geometry, no materials or shapes) moved by `offset` on every
/// axis, the moved vertices kept in double (TriangleMesh::positions_double); their float
/// positions are what a float structure of the moved scene sees.
Scene translated_scene(const Scene& scene, double offset);

}  // namespace thicket
