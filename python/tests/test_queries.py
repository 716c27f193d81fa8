"""count_intersections, list_intersections and the point queries (closest points, distance,
signed distance, occupancy): answers known on the unit cube, brute force agreement, layouts."""

import numpy as np
import pytest

import thicket
from conftest import SHARED_SCENES, random_rays


# The sbvh spec cuts the cube's face triangles (each pair shares one box): triangles in several leaves.
@pytest.fixture(scope="module", params=["bvh8", "kdtree", "brute", "bvh:alpha=0,budget=2,builder=sbvh,max-leaf=1"])
def cube_accel(request, cube):
    return thicket.build(cube, request.param)


def axis_rays(s):
    """Along +x, +y, +z through the diagonals that split the cube's faces (coordinates equal)."""
    rays = []
    for axis in range(3):
        o = [s, s, s]
        o[axis] = -1
        d = [0, 0, 0]
        d[axis] = 1
        rays.append(o + d)
    return rays


def test_count_through_shared_edges_counts_each_crossing_once(cube_accel):
    rays = np.array(axis_rays(0.5) + axis_rays(0.25) + [[0.5, 0.5, 0.5, 0, 0, 1], [5, 5, 5, 1, 0, 0]], np.float32)
    counts = cube_accel.count_intersections(rays)
    assert counts.dtype == np.int32
    assert counts.tolist() == [2] * 6 + [1, 0]
    grid = rays.reshape(2, 4, 6)
    assert cube_accel.count_intersections(grid).shape == (2, 4)


def test_list_intersections_layout(cube_accel):
    rays = np.array(axis_rays(0.5)[:1] + [[5, 5, 5, 1, 0, 0], [np.nan, 0, 0, 1, 0, 0], [0.5, 0.5, 0.5, 0, 0, 1]],
                    np.float32)
    out = cube_accel.list_intersections(rays)
    assert set(out) == {"ray_splits", "ray_ids", "t_hit", "geometry_ids", "primitive_ids", "primitive_uvs"}
    assert out["ray_splits"].dtype == np.uint32 and out["ray_splits"].tolist() == [0, 2, 2, 2, 3]
    assert out["ray_ids"].tolist() == [0, 0, 3]
    assert out["t_hit"].tolist() == [1, 2, 0.5]
    assert out["primitive_ids"][0] in (0, 1) and out["primitive_ids"][1] in (2, 3)   # x = 0, then x = 1
    assert out["geometry_ids"].tolist() == [0, 0, 0]
    assert out["primitive_uvs"].shape == (3, 2) and out["primitive_uvs"].dtype == np.float32


def test_lists_agree_with_counts_cast_and_brute_force(cornell):
    rays = random_rays(cornell, 3000, seed=11)
    accel, brute = thicket.build(cornell, "bvh8"), thicket.build(cornell, "brute")
    counts = accel.count_intersections(rays)
    lists = accel.list_intersections(rays)
    assert np.array_equal(np.diff(lists["ray_splits"]), counts)
    assert counts.max() >= 2
    assert np.array_equal(counts, brute.count_intersections(rays))
    ref = brute.list_intersections(rays)
    assert np.array_equal(lists["ray_ids"], ref["ray_ids"])
    assert np.allclose(lists["t_hit"], ref["t_hit"], rtol=1e-5, atol=0)
    # Sorted by t within each ray, and the first crossing is the closest hit.
    same_ray = lists["ray_ids"][1:] == lists["ray_ids"][:-1]
    assert np.all(np.diff(lists["t_hit"])[same_ray] > 0)
    first = lists["ray_splits"][:-1][counts > 0]
    assert np.array_equal(lists["t_hit"][first], accel.cast_rays(rays)["t_hit"][counts > 0])


def test_a_triangle_in_several_leaves_is_counted_once():
    """Spatial splits (builder=sbvh) list a cut triangle in one leaf per part; rays along the
    long thin diagonal triangles reach several of them, and still cross each triangle once."""
    rng = np.random.default_rng(4)
    n = 200
    d = np.array([[1 if i & 1 else -1, 1 if i & 2 else -1, 1] for i in range(n)], np.float32)
    start = np.array([5, 5, 1], np.float32) - 4 * d + rng.uniform(0, 2, (n, 3)).astype(np.float32)
    end = start + d * rng.uniform(4, 8, (n, 1)).astype(np.float32)
    vertices = np.stack([start, end, end + np.array([0.02, -0.02, 0], np.float32)], axis=1).reshape(-1, 3)
    scene = thicket.Scene(vertices, np.arange(3 * n, dtype=np.int32).reshape(n, 3))
    o = np.concatenate([rng.uniform(0, 10, (4000, 2)), np.full((4000, 1), -2.0)], axis=1)
    target = np.concatenate([rng.uniform(0, 10, (4000, 2)), np.full((4000, 1), 12.0)], axis=1)
    rays = np.concatenate([o, target - o], axis=1).astype(np.float32)
    brute = thicket.build(scene, "brute")
    want = brute.count_intersections(rays)
    assert want.sum() > 500
    for spec in ["bvh:builder=sbvh,budget=2,max-leaf=1", "bvh8:budget=2,quality=high"]:
        accel = thicket.build(scene, spec)
        assert int(accel.stats()["extra"]["references"].split()[0]) > n, spec
        assert np.array_equal(accel.count_intersections(rays), want), spec
        got, ref = accel.list_intersections(rays), brute.list_intersections(rays)
        assert np.array_equal(got["ray_splits"], ref["ray_splits"]), spec
        assert np.allclose(got["t_hit"], ref["t_hit"], rtol=1e-5, atol=0), spec


def test_closest_points_on_the_cube(cube_accel):
    pts = np.array([[0.5, 0.5, 2], [0.5, 0.5, 0.4], [2, 2, 2], [0.25, 0.5, 1]], np.float32)
    out = cube_accel.compute_closest_points(pts)
    assert set(out) == {"points", "geometry_ids", "primitive_ids", "primitive_uvs", "primitive_normals"}
    assert np.allclose(out["points"], [[0.5, 0.5, 1], [0.5, 0.5, 0], [1, 1, 1], [0.25, 0.5, 1]])
    assert np.array_equal(out["primitive_normals"][:2], [[0, 0, 1], [0, 0, -1]])
    assert out["primitive_ids"][0] in (10, 11) and out["primitive_ids"][1] in (8, 9)
    assert out["geometry_ids"].tolist() == [0] * 4
    d = cube_accel.compute_distance(pts)
    assert d.dtype == np.float32 and np.allclose(d, [1, 0.4, np.sqrt(3), 0])
    grid = np.broadcast_to(pts, (2, 4, 3)).copy()
    assert cube_accel.compute_distance(grid).shape == (2, 4)
    assert cube_accel.compute_closest_points(grid)["primitive_uvs"].shape == (2, 4, 2)


def test_closest_points_agree_with_brute_force(cornell):
    rng = np.random.default_rng(5)
    lo, hi = (np.array(b) for b in cornell.bounds)
    pts = (lo - 0.2 * (hi - lo) + rng.random((3000, 3)) * 1.4 * (hi - lo)).astype(np.float32)
    brute = thicket.build(cornell, "brute").compute_closest_points(pts)
    for spec in ("bvh", "bvh8", "kdtree"):  # kdtree answers through a bvh8 built on first use
        got = thicket.build(cornell, spec).compute_closest_points(pts)
        d = np.linalg.norm(got["points"] - pts, axis=1)
        dref = np.linalg.norm(brute["points"] - pts, axis=1)
        assert np.allclose(d, dref, rtol=1e-5, atol=1e-6), spec
        assert (got["primitive_ids"] == brute["primitive_ids"]).mean() > 0.95, spec


def test_bvh8_closest_points_are_brute_forces_bitwise(cornell):
    """bvh8 answers closest points itself, with brute force's point-triangle test and its tie rule
    (the lower id): every output array equal, on every ISA, threaded or not, in chunks that do not
    divide the batch, and for structures that answer through a bvh8 helper."""
    rng = np.random.default_rng(8)
    lo, hi = (np.array(b) for b in cornell.bounds)
    pts = (lo - 0.3 * (hi - lo) + rng.random((2999, 3)) * 1.6 * (hi - lo)).astype(np.float32)
    verts = cornell.vertices[cornell.triangles[:200, 0]]  # on shared vertices: ties
    pts = np.concatenate([pts, verts, (verts + cornell.vertices[cornell.triangles[:200, 1]]) / 2])
    brute = thicket.build(cornell, "brute")
    want = brute.compute_closest_points(pts)
    variants = next(a for a in thicket.accels() if a["name"] == "bvh8")["variants"]
    isas = [v for v in variants if v.startswith("bvh8:isa=") and "," not in v]  # every level this CPU runs
    for spec in ["bvh8", "kdtree"] + isas:
        accel = thicket.build(cornell, spec)
        for nthreads in (0, 1, 3):
            got = accel.compute_closest_points(pts, nthreads=nthreads)
            for key in want:
                assert np.array_equal(got[key], want[key]), (spec, nthreads, key)
        assert np.array_equal(accel.compute_distance(pts), brute.compute_distance(pts)), spec
        assert np.array_equal(accel.compute_signed_distance(pts), brute.compute_signed_distance(pts)), spec


def test_bvh8_closest_points_agree_with_bvh_on_a_shared_scene():
    path = SHARED_SCENES / "sponza-dabrovic.ply"
    if not path.exists():
        pytest.skip(f"shared scene {path} absent")
    scene = thicket.load_scene(str(path))
    rng = np.random.default_rng(3)
    lo, hi = (np.array(b) for b in scene.bounds)
    pts = (lo + rng.random((5000, 3)) * (hi - lo)).astype(np.float32)
    got = thicket.build(scene, "bvh8").compute_closest_points(pts)
    ref = thicket.build(scene, "bvh").compute_closest_points(pts)
    d, dref = (np.linalg.norm(o["points"] - pts, axis=1) for o in (got, ref))
    assert np.allclose(d, dref, rtol=1e-5, atol=0)
    assert (got["primitive_ids"] == ref["primitive_ids"]).mean() > 0.99


def test_occupancy_and_signed_distance(cube_accel):
    # Inside, outside, and points level with the cube's vertices and edges, where a ray along an
    # axis or a diagonal would run through shared edges.
    pts = np.array([[0.5, 0.5, 0.5], [0.1, 0.9, 0.5], [1.5, 0.5, 0.5], [-0.5, -0.5, -0.5], [0.5, 0.5, -1],
                    [0, 0, 0.5], [2, 2, 2]], np.float32)
    want = [1, 1, 0, 0, 0, None, 0]  # a point on an edge is on the surface: either answer
    for n in (1, 3, 5):
        occ = cube_accel.compute_occupancy(pts, nsamples=n)
        assert occ.dtype == np.float32
        assert [o for o, w in zip(occ, want) if w is not None] == [w for w in want if w is not None]
    sd = cube_accel.compute_signed_distance(pts)
    assert np.allclose(sd[[0, 1, 2, 4]], [-0.5, -0.1, 0.5, 1])
    rng = np.random.default_rng(2)
    many = rng.random((2000, 3)).astype(np.float32) * 3 - 1
    inside = np.all((many > 0) & (many < 1), axis=1)
    assert np.array_equal(cube_accel.compute_occupancy(many) == 1, inside)
    assert np.array_equal(cube_accel.compute_signed_distance(many, nsamples=3) < 0, inside)
    with pytest.raises(ValueError, match="nsamples must be odd, between 1 and 5, got 2"):
        cube_accel.compute_occupancy(pts, nsamples=2)


@pytest.mark.parametrize("points, message", [
    (np.zeros((4, 2), np.float32), r"query_points: expected shape \(\.\.\., 3\), got shape \(4, 2\) float32"),
    (np.zeros((4, 3), np.float64), r"expected dtype float32, got shape \(4, 3\) float64"),
    (np.array([[0, 0, 0], [0, np.inf, 0]], np.float32), r"point 1 \(in row order\) is not finite"),
    ("points", r"got str"),
])
def test_point_query_errors(cube_accel, points, message):
    for query in (cube_accel.compute_closest_points, cube_accel.compute_distance,
                  cube_accel.compute_signed_distance, cube_accel.compute_occupancy):
        with pytest.raises(ValueError, match=message):
            query(points)


def test_ray_query_errors(cube_accel):
    for query in (cube_accel.count_intersections, cube_accel.list_intersections):
        with pytest.raises(ValueError, match=r"got shape \(3, 5\) float32"):
            query(np.zeros((3, 5), np.float32))


def test_closest_points_refused_for_shapes():
    accel = thicket.build(thicket.load_scene("teapot-patches"), "bvh")
    with pytest.raises(thicket.Error, match="closest-point queries"):
        accel.compute_distance(np.zeros((2, 3), np.float32))
    # Counting crossings works with shapes: a patch may be crossed twice.
    assert accel.count_intersections(np.array([[0, 1, 10, 0, 0, -1]], np.float32))[0] >= 2
