"""Not collected (not test_*.py): typed code over the whole public API, which test_stub.py has mypy
--strict check against thicket/__init__.pyi, and runs, so that the stub's types are the answers'."""

import numpy as np
import numpy.typing as npt

import thicket


def use_everything(tmp_dir: str) -> float:
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    scene: thicket.Scene = thicket.Scene(v, np.array([[0, 1, 2]], np.int32))
    names: list[str] = [a["name"] for a in thicket.accels()]
    assert "bvh" in names and scene.triangle_count == 1 and scene.primitive_count == 1 and scene.shape_count == 0
    lo, hi = scene.bounds
    assert lo[0] == 0.0 and hi[1] == 1.0 and scene.name != "" or True
    accel = thicket.build(scene, "bvh")
    rays: npt.NDArray[np.float32] = thicket.create_rays_pinhole(40.0, [0.25, 0.25, 0], [0.25, 0.25, 2], [0, 1, 0], 3, 3)
    also = thicket.create_rays_pinhole(np.eye(3), np.eye(4), width_px=2, height_px=2)
    hits = accel.cast_rays(rays, nthreads=1)
    t: npt.NDArray[np.float32] = hits["t_hit"]
    ids: npt.NDArray[np.uint32] = hits["primitive_ids"]
    assert ids.shape == (3, 3) and also.shape == (2, 2, 6) and hits["geometry_ids"][1, 1] == 0
    occluded: npt.NDArray[np.bool_] = accel.test_occlusions(rays, tnear=0.0, tfar=10.0)
    counts: npt.NDArray[np.int32] = accel.count_intersections(rays)
    listed = accel.list_intersections(rays.reshape(-1, 6))
    assert listed["ray_splits"].shape == (10,) and bool(occluded[1, 1]) and int(counts[1, 1]) == 1
    far = thicket.build(scene, "bvh:precision=double")  # float64 rays: answers in float64
    wide = rays.astype(np.float64)
    t64: npt.NDArray[np.float64] = far.cast_rays(wide)["t_hit"]
    uv64: npt.NDArray[np.float64] = far.list_intersections(wide.reshape(-1, 6))["primitive_uvs"]
    assert t64.dtype == np.float64 and uv64.dtype == np.float64 and int(far.count_intersections(wide)[1, 1]) == 1
    points = np.array([[0.2, 0.2, 1.0]], np.float32)
    closest = accel.compute_closest_points(points)
    assert closest["points"].shape == (1, 3)
    d: npt.NDArray[np.float32] = accel.compute_distance(points)
    assert accel.compute_signed_distance(points, nsamples=1).shape == accel.compute_occupancy(points).shape
    path = tmp_dir + "/tri.bvh"
    accel.save(path, overwrite=True)
    again: thicket.Accel = thicket.load(path, accel.scene)
    assert again.spec == accel.spec and again.stats()["primitives"] == 1 and accel.bounds == scene.bounds
    # Moving vertices, then refitting (bvh can).
    scene.set_vertices(0, v + np.float32(0.0))
    refittable: bool = accel.refittable
    accel.refit(scene, nthreads=1)
    assert refittable and accel.scene.triangle_count == 1
    assert thicket.INVALID_ID == 4294967295 and issubclass(thicket.Error, RuntimeError)
    # Rays and pictures.
    primary = thicket.rays(scene, "primary", width=4, height=3, eye=(0.25, 0.25, 2), center=(0.25, 0.25, 0))
    origins: npt.NDArray[np.float32] = primary["rays"][:, :3]
    assert origins.shape == (12, 3) and primary["tmax"].shape == (12,) and not primary["any_hit"]
    depth: npt.NDArray[np.float32] = accel.render("depth", 4, 3, eye=(0.25, 0.25, 2), center=(0.25, 0.25, 0))
    normal: npt.NDArray[np.float32] = accel.render("normal", 4, 3, eye=(0.25, 0.25, 2), center=(0.25, 0.25, 0), vfov_deg=30)
    work: npt.NDArray[np.uint32] = accel.render("heatmap", 4, 3, counter="prims")
    colours: npt.NDArray[np.uint8] = thicket.heat_colours(work)
    radiance: npt.NDArray[np.float32] = thicket.path_trace(accel, spp=1, width=4, height=3, lights=[((0, 0, 1), 1.0)])
    thicket.save_png(tmp_dir + "/tri.png", radiance, exposure=2.0, overwrite=True)
    assert depth.shape == (3, 4) and normal.shape == (3, 4, 3) and colours.shape == (3, 4, 3)
    # Open3D's multi-mesh class: geometry ids, per-geometry primitive ids, Tensor's numpy().
    several = thicket.RaycastingScene(nthreads=1, accel="bvh8")
    first: int = several.add_triangles(v, np.array([[0, 1, 2]], np.uint32))
    second = several.add_triangles(mesh=scene)
    several.set_vertices(second, v + np.float32(0.0))
    several.refit()
    answers = several.cast_rays(thicket.RaycastingScene.create_rays_pinhole(40.0, [0.25, 0.25, 0], [0.25, 0.25, 2], [0, 1, 0], 3, 3))
    which: npt.NDArray[np.uint32] = answers["geometry_ids"].numpy()
    seen: npt.NDArray[np.bool_] = answers["t_hit"].isfinite()
    assert first == 0 and second == 1 and int(which[1, 1]) in (0, 1) and bool(seen[1, 1])
    assert several.compute_closest_points(points)["primitive_ids"][0] == 0 and several.INVALID_ID == thicket.INVALID_ID
    inside: npt.NDArray[np.float32] = several.compute_occupancy(points, nsamples=3)
    copy: int = several.add_instance(first, np.eye(4))
    several.set_transform(copy, np.eye(4)[:3])
    placed = several.cast_rays(np.array([[0.25, 0.25, 1, 0, 0, -1]], np.float32))
    assert placed.get("instance_ids") is not None and int(placed["geometry_ids"][0]) == first
    prototypes = thicket.Scene(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
    prototypes.add_instance(prototypes.add_geometry(scene), np.eye(4))
    instanced = thicket.build(prototypes)
    instanced.set_transform(0, np.eye(4))
    where: npt.NDArray[np.uint32] = instanced.locate(instanced.cast_rays(rays)["primitive_ids"])["instance_ids"]
    assert prototypes.instance_count == instanced.instance_count == 1 and where[1, 1] == 0
    assert several.test_occlusions(rays, tfar=10.0).shape == (3, 3) and inside.shape == (1,)
    return float(t[1, 1]) + float(d[0])
