"""thicket.RaycastingScene's instances (add_instance, set_transform) against the same meshes
transformed in numpy and added as plain geometries: t, geometry, primitive and instance ids,
normals and closest points, under scales, shears and mirrors; bad transforms refused; and the
Accel.locate / Accel.set_transform bindings under it."""

import numpy as np
import pytest

import thicket
from conftest import cube_arrays
from test_raycasting_scene import sphere_arrays, torus_arrays

INVALID = 4294967295


def affine(linear, offset):
    m = np.eye(4)
    m[:3, :3] = linear
    m[:3, 3] = offset
    return m


def rotation(axis, degrees):
    axis = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    a = np.radians(degrees)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


TRANSFORMS = {
    "rotate": affine(rotation([1, 2, 3], 40), [4, 0, 0]),
    "scale": affine(np.diag([2.0, 0.5, 3.0]), [0, 5, 0]),
    "shear": affine([[1, 0.7, 0], [0, 1, 0.4], [0.2, 0, 1]], [0, 0, 6]),
    "mirror": affine(np.diag([-1.0, 1, 1]) @ rotation([0, 1, 1], 25), [-4, 0, 0]),
}


def moved(vertices, m):
    return np.asarray(vertices, np.float64) @ m[:3, :3].T + m[:3, 3]


def meshes():
    tv, tt = torus_arrays(major=0.6, minor=0.25)
    return [cube_arrays(), (tv, tt), sphere_arrays()]


def rays_at(points, n, seed):
    """Rays from a shell around the points towards random points near them: most hit."""
    rng = np.random.default_rng(seed)
    lo, hi = points.min(0), points.max(0)
    size = hi - lo
    target = points[rng.integers(len(points), size=n)] + 0.05 * rng.standard_normal((n, 3))
    org = lo - size + rng.random((n, 3)) * 3 * size
    return np.concatenate([org, target - org], 1).astype(np.float32)


def pair(placements, accel="bvh8"):
    """(instanced, reference): the meshes plus instances (geometry id, 4x4) in a RaycastingScene,
    and the same meshes plus each instance's transformed copy as plain geometries; with the
    reference's geometry id -> (instance id, geometry id) table."""
    ms = meshes()
    inst = thicket.RaycastingScene(accel=accel)
    ref = thicket.RaycastingScene(accel=accel)
    for v, t in ms:
        inst.add_triangles(v, t)
        ref.add_triangles(v, t)
    table = [(INVALID, g) for g in range(len(ms))]
    for k, (g, m) in enumerate(placements):
        assert inst.add_instance(g, m) == k
        v, t = ms[g]
        ref.add_triangles(moved(v, m), t)
        table.append((k, g))
    points = np.concatenate([ms[g][0] if k == INVALID else moved(ms[g][0], placements[k][1])
                             for k, g in table])
    return inst, ref, np.array(table, np.uint32), points


def assert_same_hits(inst, ref, table, rays, seen_instances):
    a, b = inst.cast_rays(rays), ref.cast_rays(rays)
    hit = np.isfinite(b["t_hit"])
    assert 0.5 < hit.mean() < 1
    np.testing.assert_array_equal(np.isfinite(a["t_hit"]), hit)
    np.testing.assert_allclose(a["t_hit"][hit], b["t_hit"][hit], rtol=2e-4, atol=1e-5)
    expect_instance = np.where(hit, table[np.minimum(b["geometry_ids"], len(table) - 1), 0], INVALID)
    expect_geometry = np.where(hit, table[np.minimum(b["geometry_ids"], len(table) - 1), 1], INVALID)
    np.testing.assert_array_equal(a["instance_ids"], expect_instance)
    np.testing.assert_array_equal(a["geometry_ids"], expect_geometry)
    assert set(np.unique(a["instance_ids"][hit])) == seen_instances | {INVALID}
    # The triangle: the same but where a ray passes through a shared edge (either may answer).
    same = a["primitive_ids"] == b["primitive_ids"]
    assert same[~hit].all() and (~same[hit]).mean() < 0.005
    both = hit & same
    np.testing.assert_allclose(a["primitive_normals"][both], b["primitive_normals"][both], atol=2e-4)
    np.testing.assert_allclose(a["primitive_uvs"][both], b["primitive_uvs"][both], atol=2e-3)
    return a


@pytest.mark.parametrize("name", sorted(TRANSFORMS))
def test_instance_hits_match_the_transformed_mesh(name):
    m = TRANSFORMS[name]
    inst, ref, table, points = pair([(1, m), (0, m @ affine(np.eye(3), [0.3, 0.2, 0.1]))])
    rays = rays_at(points, 4000, seed=3)
    a = assert_same_hits(inst, ref, table, rays, {0, 1})
    assert set(a) == {"t_hit", "geometry_ids", "primitive_ids", "primitive_uvs", "primitive_normals",
                      "instance_ids"}
    assert a["instance_ids"].dtype == np.uint32 and a["instance_ids"].shape == (4000,)


def test_set_transform_moves_the_instance_between_casts():
    first, second = TRANSFORMS["rotate"], TRANSFORMS["mirror"]
    inst, ref, table, points = pair([(2, first), (1, TRANSFORMS["scale"])])
    rays = rays_at(np.concatenate([points, moved(sphere_arrays()[0], second)]), 3000, seed=5)
    before = assert_same_hits(inst, ref, table, rays, {0, 1})
    inst.set_transform(0, second[:3])  # the (3, 4) form
    _, ref2, table2, _ = pair([(2, second), (1, TRANSFORMS["scale"])])
    after = assert_same_hits(inst, ref2, table2, rays, {0, 1})
    assert (before["t_hit"] != after["t_hit"]).mean() > 0.05
    # Only the top level was rebuilt: the structure is the same object, moved in place.
    accel = inst._accel
    inst.set_transform(0, first)
    inst.cast_rays(rays[:10])
    assert inst._accel is accel
    assert_same_hits(inst, ref, table, rays, {0, 1})


def test_other_queries_with_instances():
    inst, ref, table, points = pair([(0, TRANSFORMS["shear"]), (2, TRANSFORMS["scale"])])
    rays = rays_at(points, 500, seed=9)
    np.testing.assert_array_equal(inst.test_occlusions(rays), ref.test_occlusions(rays))
    np.testing.assert_array_equal(inst.count_intersections(rays), ref.count_intersections(rays))
    a, b = inst.list_intersections(rays), ref.list_intersections(rays)
    np.testing.assert_array_equal(a["ray_splits"], b["ray_splits"])
    np.testing.assert_array_equal(a["instance_ids"], table[b["geometry_ids"], 0])
    np.testing.assert_array_equal(a["geometry_ids"], table[b["geometry_ids"], 1])
    np.testing.assert_allclose(a["t_hit"], b["t_hit"], rtol=2e-4, atol=1e-5)
    query = points[::7] + 0.1
    c, d = inst.compute_closest_points(query), ref.compute_closest_points(query)
    np.testing.assert_allclose(c["points"], d["points"], atol=1e-5)
    np.testing.assert_array_equal(c["instance_ids"], table[d["geometry_ids"], 0])
    np.testing.assert_array_equal(c["geometry_ids"], table[d["geometry_ids"], 1])
    np.testing.assert_allclose(inst.compute_distance(query), ref.compute_distance(query), atol=1e-5)
    np.testing.assert_array_equal(inst.compute_occupancy(query), ref.compute_occupancy(query))
    # Signed distance and occupancy (issue 45), on points inside and outside the closed meshes.
    lo, hi = points.min(axis=0), points.max(axis=0)
    inside_and_out = (lo + np.random.default_rng(4).random((600, 3)) * (hi - lo)).astype(np.float32)
    want_occupancy = ref.compute_occupancy(inside_and_out)
    assert 0 < want_occupancy.sum() < len(inside_and_out), "points both inside and outside"
    np.testing.assert_array_equal(inst.compute_occupancy(inside_and_out), want_occupancy)
    np.testing.assert_allclose(inst.compute_signed_distance(inside_and_out), ref.compute_signed_distance(inside_and_out),
                               atol=1e-5)
    # A moved instance moves the closest points, the signed distance and the occupancy too.
    inst.set_transform(1, TRANSFORMS["rotate"])
    _, ref2, _, _ = pair([(0, TRANSFORMS["shear"]), (2, TRANSFORMS["rotate"])])
    np.testing.assert_allclose(inst.compute_distance(query), ref2.compute_distance(query), atol=1e-5)
    np.testing.assert_allclose(inst.compute_signed_distance(inside_and_out),
                               ref2.compute_signed_distance(inside_and_out), atol=1e-5)
    np.testing.assert_array_equal(inst.compute_occupancy(inside_and_out), ref2.compute_occupancy(inside_and_out))


def test_open3d_style_usage():
    # As Open3D code would write it: a mesh, its instance id, a pose per frame, rays from a camera.
    scene = thicket.RaycastingScene()
    box = scene.add_triangles(*cube_arrays())
    copy = scene.add_instance(box, np.eye(4))
    assert copy == 0
    rays = scene.create_rays_pinhole(fov_deg=60, center=[3, 0.5, 0.5], eye=[3, 0.5, 8], up=[0, 1, 0],
                                     width_px=32, height_px=24)
    hits = []
    for x in (1.5, 3.0):
        pose = np.eye(4)
        pose[0, 3] = x
        scene.set_transform(copy, pose)
        ans = scene.cast_rays(rays)
        assert ans["t_hit"].isfinite().any()
        hits.append(int((ans["instance_ids"].numpy() == copy).sum()))
        # The box added with add_triangles stays where it is; a centre ray meets the copy.
    assert hits[0] > 0 and hits[1] > 0
    assert "1 instances" in repr(scene)


def test_plain_geometries_stay_drawn_and_added_after_an_instance():
    scene = thicket.RaycastingScene()
    scene.add_triangles(*cube_arrays())
    scene.add_instance(0, affine(np.eye(3), [5, 0, 0]))
    later = scene.add_triangles(moved(cube_arrays()[0], affine(np.eye(3), [10, 0, 0])), cube_arrays()[1])
    rays = np.array([[x, 0.5, 5, 0, 0, -1] for x in (0.5, 5.5, 10.5, 20)], np.float32)
    ans = scene.cast_rays(rays)
    np.testing.assert_allclose(ans["t_hit"], [4, 4, 4, np.inf])
    np.testing.assert_array_equal(ans["geometry_ids"], [0, 0, later, INVALID])
    np.testing.assert_array_equal(ans["instance_ids"], [INVALID, 0, INVALID, INVALID])
    np.testing.assert_allclose(ans["primitive_normals"][:3], [[0, 0, 1]] * 3)


@pytest.mark.parametrize("transform, error, text", [
    (np.diag([1, 1, 1e-6, 1.0]), thicket.Error, "condition number"),
    (np.eye(3), ValueError, "(3, 4) or (4, 4)"),
    (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]), ValueError, "last row"),
    (np.full((3, 4), np.inf), ValueError, "not finite"),
    ([["a"] * 4] * 3, ValueError, "array of numbers"),
])
def test_bad_transforms_are_refused_by_the_call(transform, error, text):
    scene = thicket.RaycastingScene()
    scene.add_triangles(*cube_arrays())
    good = scene.add_instance(0, np.eye(4))
    with pytest.raises(error, match=text.replace("(", r"\(").replace(")", r"\)")):
        scene.add_instance(0, transform)
    with pytest.raises(error, match=text.replace("(", r"\(").replace(")", r"\)")):
        scene.set_transform(good, transform)
    assert len(scene._instances) == 1  # unchanged
    with pytest.raises(ValueError, match="geometry_id must be a geometry id in 0..0, got 1"):
        scene.add_instance(1, np.eye(4))
    with pytest.raises(ValueError, match="instance_id must be an instance id in 0..0, got 3"):
        scene.set_transform(3, np.eye(4))
    ans = scene.cast_rays(np.array([[0.5, 0.5, 5, 0, 0, -1]], np.float32))
    assert ans["t_hit"][0] == 4


def test_accel_bindings():
    v, t = cube_arrays()
    scene = thicket.Scene(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
    assert scene.add_geometry(thicket.Scene(v, t)) == 0
    assert scene.add_geometry(thicket.Scene(v + 3, t)) == 1
    assert scene.add_instance(1, affine(np.eye(3), [0, 0, 10])) == 0
    assert scene.add_instance(0, np.eye(4)[:3]) == 1
    assert scene.instance_count == 2
    accel = thicket.build(scene, "bvh8")
    assert accel.instance_count == 2
    where = accel.locate(np.array([[0, 11, 12], [23, 24, INVALID]]))
    np.testing.assert_array_equal(where["instance_ids"], [[0, 0, 1], [1, INVALID, INVALID]])
    np.testing.assert_array_equal(where["geometry_ids"], [[1, 1, 0], [0, INVALID, INVALID]])
    np.testing.assert_array_equal(where["primitive_ids"], [[0, 11, 0], [11, INVALID, INVALID]])
    for bad in ([-1], np.array([1 << 32], np.int64)):
        with pytest.raises(ValueError, match="primitive_ids: entry 0 is .*not a primitive id"):
            accel.locate(bad)
    with pytest.raises(ValueError, match="integer array"):
        accel.locate([0.5])
    ray = np.array([[3.5, 3.5, 20, 0, 0, -1]], np.float32)
    assert accel.cast_rays(ray)["t_hit"][0] == 6  # the copy at z 13..14 (the prototype is not drawn)
    accel.set_transform(0, affine(np.eye(3), [0, 0, 5]))
    ans = accel.cast_rays(ray)
    assert ans["t_hit"][0] == 11 and ans["primitive_normals"][0].tolist() == [0, 0, 1]
    with pytest.raises(thicket.Error, match="closest-point queries"):
        accel.compute_distance(np.zeros((1, 3), np.float32))
    with pytest.raises(ValueError, match="instance_id must be an instance id in 0..1, got 2"):
        accel.set_transform(2, np.eye(4))
    plain = thicket.build(thicket.Scene(v, t), "bvh8")
    assert plain.instance_count == 0
    with pytest.raises(thicket.Error, match="without instances"):
        plain.locate([0])
    with pytest.raises(ValueError, match="only a scene of triangles"):
        thicket.Scene(v, t).add_geometry(scene)


@pytest.mark.parametrize("accel", ["bvh8", "kdtree"])
def test_set_vertices_moves_every_copy(accel):
    # An instanced structure cannot refit: the next query builds it again, the instance with it.
    placements = [(1, TRANSFORMS["shear"])]
    inst, _, table, points = pair(placements, accel)
    tv, tt = meshes()[1]
    bent = tv * np.float32([1.3, 1, 1])
    inst.cast_rays(np.zeros((1, 6), np.float32))
    inst.set_vertices(1, bent)
    ref = thicket.RaycastingScene(accel=accel)
    for g, (v, t) in enumerate(meshes()):
        ref.add_triangles(bent if g == 1 else v, t)
    ref.add_triangles(moved(bent, TRANSFORMS["shear"]), tt)
    assert_same_hits(inst, ref, table, rays_at(points, 2000, seed=11), {0})
