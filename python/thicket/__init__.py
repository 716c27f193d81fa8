"""Thicket's ray-tracing acceleration structures, numpy in and out.

    import numpy as np, thicket
    scene = thicket.load_scene("bunny.ply")          # or thicket.Scene(vertices, triangles)
    accel = thicket.build(scene, "bvh8")              # any spec string: see thicket.accels()
    hits = accel.cast_rays(rays)                      # rays (..., 6) or (..., 8) float32
    rays = thicket.create_rays_pinhole(60.0, center, eye, up, 640, 480)  # (480, 640, 6), as Open3D's
    depth = accel.render("depth", 640, 480)           # (480, 640) float32 hit distances, inf on a miss
    image = thicket.path_trace(scene, spp=64)         # (480, 640, 3) float32 linear radiance
    thicket.save_png("bunny.png", image)              # sRGB-encoded, as `thicket render` writes it
    primary = thicket.rays(scene, "primary")          # the bench's ray sets, as `thicket rays`
    several = thicket.RaycastingScene()               # Open3D's multi-mesh class: add_triangles -> ids

Queries are named and shaped as Open3D's RaycastingScene answers them (t_hit, primitive_ids,
primitive_uvs, primitive_normals, ...); rays of 8 columns add a per-ray [tmin, tmax]. Tracing
releases the GIL and uses every core unless nthreads says otherwise.

Arguments are checked as the `thicket` CLI checks its own: paths are str, bytes or os.PathLike
(bytes as open() takes them); a path or spec with a NUL byte is a ValueError; nthreads is 0 (one
thread per core) or a count up to 2^32 - 1, as -j; an array whose copy or answers would not fit in
the memory available (MemAvailable, capped by RLIMIT_AS) is a MemoryError naming the argument and
its shape, raised before anything is allocated. Accel.save(path) replaces an existing file only
with overwrite=True, and never the scene file the structure was built from or the saved structure
it was loaded from (under any name).

Errors: ValueError for an array of the wrong shape or dtype or an argument out of range,
MemoryError for one too big for memory, OSError for a file that cannot be read or written
(FileExistsError for an existing output), thicket.Error for everything else (a bad spec, a
malformed file, a saved structure of another scene).
"""

from ._thicket import DEFAULT_SPEC, Accel, Error, Scene, accels, build, heat_colours, load, load_scene, path_trace, rays, save_png
from ._cameras import create_rays_pinhole
from ._raycasting import RaycastingScene

INVALID_ID = 4294967295
"""primitive_ids and geometry_ids of a miss (Open3D's RaycastingScene.INVALID_ID)."""

__all__ = ["Accel", "Error", "Scene", "accels", "build", "load", "load_scene", "create_rays_pinhole", "rays",
           "path_trace", "heat_colours", "save_png", "INVALID_ID", "DEFAULT_SPEC", "RaycastingScene"]
