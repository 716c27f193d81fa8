"""float64 arrays in every query (issue 28): on the Cornell box moved 1e7 from the origin (float's
spacing there is 1, wider than the box), a precision=double bvh answers cast_rays,
test_occlusions, count_intersections and list_intersections on float64 rays exactly as double
brute force does, in float64 and on the triangles' planes; float structures refuse float64 rays
naming precision=double, and the point queries, which no structure answers in double, refuse
float64 points naming the float32 they need."""

import numpy as np
import pytest

import thicket

OFFSET = 1e7


@pytest.fixture(scope="module")
def far_box():
    """The Cornell box moved to OFFSET, its vertices kept in float64, and float64 rays from inside
    it (so that nearly every one hits), a fifth with a short tmax and a few without meaning."""
    cornell = thicket.load_scene("cornell")
    vertices = cornell.vertices.astype(np.float64) + OFFSET
    scene = thicket.Scene(vertices, cornell.triangles)
    rng = np.random.default_rng(28)
    n = 600
    rays = np.zeros((n, 8), np.float64)
    rays[:, 0:2] = OFFSET + 0.05 + 0.9 * rng.random((n, 2))
    rays[:, 2] = OFFSET - 0.05 - 0.9 * rng.random(n)
    rays[:, 3:6] = rng.random((n, 3)) * 2 - 1
    rays[:, 7] = np.where(np.arange(n) % 5 == 0, 0.3, np.inf)
    rays[::97, 3:6] = 0  # no direction: a miss, no crossings
    return vertices, cornell.triangles, scene, rays


@pytest.fixture(scope="module")
def structures(far_box):
    scene = far_box[2]
    return thicket.build(scene, "bvh:precision=double"), thicket.build(scene, "brute:precision=double")


def on_their_triangles(vertices, triangles, rays, t, prim, uv):
    """Largest distance between each hit point computed from the ray (origin + t * direction) and
    from its triangle (the double vertices and uv): float rounding on the way (1 unit apart here)
    would show as up to a unit."""
    a, b, c = (vertices[triangles[prim, k]] for k in range(3))
    from_ray = rays[:, 0:3] + t[:, None] * rays[:, 3:6]
    from_triangle = a + (b - a) * uv[:, 0:1] + (c - a) * uv[:, 1:2]
    return np.abs(from_ray - from_triangle).max()


def test_cast_rays_and_occlusions_answer_as_double_brute_force(far_box, structures):
    vertices, triangles, _, rays = far_box
    bvh, brute = structures
    got, want = bvh.cast_rays(rays), brute.cast_rays(rays)
    assert got["t_hit"].dtype == np.float64 and got["primitive_uvs"].dtype == np.float64
    for key in want:
        assert np.array_equal(got[key], want[key]), key
    hit = got["primitive_ids"] != thicket.INVALID_ID
    assert 0.5 < hit.mean() < 1.0  # the short rays miss some
    assert on_their_triangles(vertices, triangles, rays[hit], got["t_hit"][hit], got["primitive_ids"][hit],
                              got["primitive_uvs"][hit]) < 1e-6
    assert np.array_equal(bvh.test_occlusions(rays), hit)
    assert np.array_equal(bvh.test_occlusions(rays), brute.test_occlusions(rays))
    # Rows of 6 take tnear/tfar (given in float, widened); rows of 8 carry their own and refuse them.
    six = np.ascontiguousarray(rays[:, :6])
    assert np.array_equal(bvh.test_occlusions(six, tfar=0.3), brute.test_occlusions(six, tfar=0.3))
    assert bvh.test_occlusions(six, tfar=0.3).sum() < bvh.test_occlusions(six).sum()
    with pytest.raises(ValueError, match="tnear/tfar apply only to rays of 6 columns"):
        bvh.test_occlusions(rays, tfar=1.0)


def test_count_and_list_intersections_answer_as_double_brute_force(far_box, structures):
    vertices, triangles, _, rays = far_box
    bvh, brute = structures
    counts = bvh.count_intersections(rays)
    assert counts.dtype == np.int32 and counts.shape == (len(rays),)
    assert np.array_equal(counts, brute.count_intersections(rays))
    # Shapes keep their leading axes, as for float32 rays.
    assert np.array_equal(bvh.count_intersections(rays.reshape(20, -1, 8)), counts.reshape(20, -1))
    got, want = bvh.list_intersections(rays), brute.list_intersections(rays)
    for key in want:
        assert np.array_equal(got[key], want[key]), key
    assert got["t_hit"].dtype == np.float64 and got["primitive_uvs"].dtype == np.float64
    assert np.array_equal(np.diff(got["ray_splits"]), counts)
    assert counts.sum() > len(rays)  # rays out through the blocks cross several surfaces
    assert counts[::97].sum() == 0
    # The first crossing of each ray is its closest hit, in double; every crossing lies on its triangle.
    cast = bvh.cast_rays(rays)
    first = got["ray_splits"][:-1][counts > 0]
    assert np.array_equal(got["t_hit"][first], cast["t_hit"][counts > 0])
    assert on_their_triangles(vertices, triangles, rays[got["ray_ids"]], got["t_hit"], got["primitive_ids"],
                              got["primitive_uvs"]) < 1e-6


def test_float_structures_refuse_float64_rays_naming_precision_double(far_box):
    _, _, scene, rays = far_box
    for spec in ("bvh", "bvh8", "brute"):
        accel = thicket.build(scene, spec)
        for query in (accel.cast_rays, accel.test_occlusions, accel.count_intersections, accel.list_intersections):
            with pytest.raises(ValueError, match=r"float64 rays are traced by structures built with precision=double"):
                query(rays)


def test_point_queries_refuse_float64_points_on_every_structure(far_box):
    _, _, scene, _ = far_box
    points = np.full((4, 3), OFFSET + 0.5)
    for spec in ("bvh:precision=double", "bvh"):
        accel = thicket.build(scene, spec)
        for query in ("compute_closest_points", "compute_distance", "compute_occupancy", "compute_signed_distance"):
            with pytest.raises(ValueError, match=r"query_points: expected dtype float32, got shape \(4, 3\) float64: "
                                                 rf"{query} takes float32 points only .*precision=double ones included"):
                getattr(accel, query)(points)
    # The same points as float32 are answered (by the float32 path every structure has).
    assert thicket.build(scene, "bvh:precision=double").compute_distance(points.astype(np.float32)).shape == (4,)


def test_float64_arrays_are_checked_as_float32_ones(structures):
    bvh, _ = structures
    with pytest.raises(ValueError, match=r"rays: expected shape \(\.\.\., 6\) or \(\.\.\., 8\), got shape \(3, 7\) float64"):
        bvh.count_intersections(np.zeros((3, 7)))
    # A strided float64 array is copied, not misread.
    wide = np.zeros((10, 16))
    wide[:, 0:3] = OFFSET + 0.5
    wide[:, 5] = -1
    wide[:, 7] = np.inf
    assert np.array_equal(bvh.count_intersections(wide[:, :8]), bvh.count_intersections(np.ascontiguousarray(wide[:, :8])))
    assert bvh.count_intersections(wide[:, :8]).min() >= 1


def test_dask_takes_float64_rays_for_a_precision_double_spec(far_box, structures, tmp_path):
    da = pytest.importorskip("dask.array")
    import thicket.dask
    vertices, triangles, _, rays = far_box
    # The scene as a file the tasks load (here on the calling process's threads: the cluster is
    # test_dask's); PLY float64 vertices keep their doubles.
    ply = tmp_path / "far.ply"
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty double x\n"
              f"property double y\nproperty double z\nelement face {len(triangles)}\n"
              "property list uchar uint vertex_indices\nend_header\n")
    faces = np.zeros(len(triangles), [("n", "u1"), ("v", "<u4", 3)])
    faces["n"], faces["v"] = 3, triangles
    ply.write_bytes(header.encode() + vertices.astype("<f8").tobytes() + faces.tobytes())
    lazy = da.from_array(rays, chunks=(150, 8))
    hits = thicket.dask.cast_rays(lazy, str(ply), spec="bvh:precision=double")
    got = dict(zip(hits, da.compute(*hits.values(), scheduler="threads")))
    want = structures[0].cast_rays(rays)
    for key in want:
        assert got[key].dtype == want[key].dtype and np.array_equal(got[key], want[key]), key
    counts = thicket.dask.count_intersections(lazy, str(ply), spec="bvh:precision=double").compute(scheduler="threads")
    assert np.array_equal(counts, structures[0].count_intersections(rays))
    for spec, saved in (("bvh", None), ("bvh:precision=double", str(ply))):
        with pytest.raises(ValueError, match="float64 rays are taken with a spec built with precision=double"):
            thicket.dask.cast_rays(lazy, str(ply), spec=spec, saved=saved)
