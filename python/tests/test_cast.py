"""cast_rays and test_occlusions: answers known by hand, Open3D's keys, dtypes and shapes, the
per-ray interval, invalid rays, threads, the GIL, and every shape or dtype error."""

import sys
import threading
import time

import numpy as np
import pytest

import thicket
from conftest import random_rays

KEYS = {"t_hit": (np.float32, ()), "geometry_ids": (np.uint32, ()), "primitive_ids": (np.uint32, ()),
        "primitive_uvs": (np.float32, (2,)), "primitive_normals": (np.float32, (3,))}


@pytest.fixture(scope="module")
def cube_bvh(cube):
    return thicket.build(cube, "bvh8")


def test_known_answers(cube_bvh):
    rays = np.array([[0.25, 0.5, 3, 0, 0, -1],    # top face z = 1 at t = 2
                     [0.25, 0.5, 3, 0, 0, -2],    # t in units of the direction's length: 1
                     [0.5, 0.5, 0.5, 1, 0, 0],    # from inside: face x = 1 at 0.5
                     [5, 5, 5, 0, 0, 1]], np.float32)  # miss
    h = cube_bvh.cast_rays(rays)
    assert np.array_equal(h["t_hit"], np.array([2, 1, 0.5, np.inf], np.float32))
    assert set(h["primitive_ids"][:2]) <= {10, 11} and h["primitive_ids"][2] in (2, 3)
    assert h["primitive_ids"][3] == thicket.INVALID_ID == h["geometry_ids"][3]
    assert np.array_equal(h["geometry_ids"][:3], [0, 0, 0])
    assert np.array_equal(h["primitive_normals"], [[0, 0, 1], [0, 0, 1], [1, 0, 0], [0, 0, 0]])
    assert np.array_equal(h["primitive_uvs"][3], [0, 0])


def test_keys_dtypes_and_shapes_follow_open3d(cube_bvh, cube):
    for lead in [(7,), (2, 3), (2, 1, 4), ()]:
        rays = random_rays(cube, int(np.prod(lead)), width=6).reshape(lead + (6,))
        h = cube_bvh.cast_rays(rays)
        assert set(h) == set(KEYS)
        for key, (dtype, tail) in KEYS.items():
            assert h[key].dtype == dtype and h[key].shape == lead + tail, key
        occ = cube_bvh.test_occlusions(rays)
        assert occ.dtype == np.bool_ and occ.shape == lead
        assert np.array_equal(occ, np.isfinite(h["t_hit"]))


def test_uvs_are_barycentrics_of_the_hit_point(cube, cornell):
    for scene in (cube, cornell):
        rays = random_rays(scene, 2000, width=6)
        h = thicket.build(scene, "bvh").cast_rays(rays)
        hit = np.isfinite(h["t_hit"])
        assert hit.mean() > 0.5
        tri = scene.vertices[scene.triangles[h["primitive_ids"][hit]]]  # (n, 3 corners, 3)
        u, v = h["primitive_uvs"][hit].T
        point = (1 - u - v)[:, None] * tri[:, 0] + u[:, None] * tri[:, 1] + v[:, None] * tri[:, 2]
        expected = rays[hit, :3] + h["t_hit"][hit, None] * rays[hit, 3:6]
        scale = np.abs(scene.vertices).max()
        assert np.abs(point - expected).max() < 1e-4 * scale
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        assert np.allclose(h["primitive_normals"][hit], n, atol=1e-5)


def test_interval_columns_and_tnear_tfar(cube_bvh):
    base = [0.25, 0.5, 3, 0, 0, -1]
    rays = np.array([base + [0, np.inf], base + [0, 1.5], base + [2.5, np.inf], base + [2, 2]], np.float32)
    t = cube_bvh.cast_rays(rays)["t_hit"]
    assert np.array_equal(t, [2, np.inf, 3, 2])
    assert np.array_equal(cube_bvh.test_occlusions(rays), [True, False, True, True])
    six = rays[:, :6]
    assert np.array_equal(cube_bvh.test_occlusions(six, tfar=1.5), [False] * 4)
    assert np.array_equal(cube_bvh.test_occlusions(six, tnear=3.5), [False] * 4)
    assert np.array_equal(cube_bvh.test_occlusions(six, tnear=2.5, tfar=3.5), [True] * 4)
    with pytest.raises(ValueError, match="tnear/tfar"):
        cube_bvh.test_occlusions(rays, tfar=1.0)


def test_invalid_rays_are_misses(cube_bvh):
    good = [0.25, 0.5, 3, 0, 0, -1, 0, np.inf]
    rays = np.array([good,
                     [np.nan, 0.5, 3, 0, 0, -1, 0, np.inf],   # NaN origin
                     [0.25, 0.5, 3, 0, 0, 0, 0, np.inf],      # zero direction
                     [0.25, 0.5, 3, np.inf, 0, -1, 0, np.inf],  # infinite direction
                     [0.25, 0.5, 3, 0, 0, -1, 5, 1],          # tmin > tmax
                     good], np.float32)
    h = cube_bvh.cast_rays(rays)
    assert np.array_equal(h["t_hit"], [2, np.inf, np.inf, np.inf, np.inf, 2])
    assert np.array_equal(h["primitive_ids"][1:5], [thicket.INVALID_ID] * 4)
    assert np.array_equal(h["primitive_normals"][1:5], np.zeros((4, 3)))
    assert np.array_equal(cube_bvh.test_occlusions(rays), [True, False, False, False, False, True])


def test_strided_input_and_threads_and_coherent_give_the_same_answers(cornell):
    accel = thicket.build(cornell, "bvh8")
    rays = random_rays(cornell, 5000)
    ref = accel.cast_rays(rays)
    wide = np.zeros((5000, 16), np.float32)
    wide[:, ::2] = rays  # every other column: not contiguous
    for answer in (accel.cast_rays(wide[:, ::2]), accel.cast_rays(rays, nthreads=1),
                   accel.cast_rays(rays, nthreads=3, coherent=True)):
        assert all(np.array_equal(ref[k], answer[k]) for k in ref)
    assert np.array_equal(accel.test_occlusions(rays, nthreads=1), np.isfinite(ref["t_hit"]))
    assert rays.flags.writeable and rays.dtype == np.float32  # the input is not touched


@pytest.mark.parametrize("rays, message", [
    (np.zeros((4, 7), np.float32), r"rays: expected shape \(\.\.\., 6\) or \(\.\.\., 8\), got shape \(4, 7\) float32"),
    (np.zeros((4,), np.float32), r"got shape \(4,\)"),
    (np.ones((), np.float32), r"got shape \(\)"),
    # float64 is refused by float structures with the way out named (issue 28: precision=double).
    (np.zeros((4, 6), np.float64), r"float64 rays are traced by structures built with precision=double .*"
                                   r"astype\(numpy\.float32\)"),
    (np.zeros((2, 3, 8), np.int32), r"expected dtype float32, got shape \(2, 3, 8\) int32"),
    (np.zeros((4, 6), np.float16), r"float16"),
    ([[0, 0, 0, 1, 0, 0]], r"rays: expected a numpy float32 array .* got list"),
    (None, r"got NoneType"),
])
def test_shape_and_dtype_errors(cube_bvh, rays, message):
    for query in (cube_bvh.cast_rays, cube_bvh.test_occlusions):
        with pytest.raises(ValueError, match=message):
            query(rays)


def test_empty_batches(cube_bvh):
    h = cube_bvh.cast_rays(np.zeros((0, 6), np.float32))
    assert h["t_hit"].shape == (0,) and h["primitive_uvs"].shape == (0, 2)
    assert cube_bvh.test_occlusions(np.zeros((3, 0, 8), np.float32)).shape == (3, 0)


def test_gil_is_released_while_tracing(cornell):
    """Another Python thread runs while a cast is in C++.

    Counted, not timed: with the switch interval raised to 10 s, the main thread never hands the
    GIL over while it runs Python, so the other thread can add to its count only inside calls that
    release the GIL. The casts are repeated until it has counted 10 wake-ups (a fast machine needs
    more casts, a loaded one fewer); held, it would count none however many casts ran.
    """
    accel = thicket.build(cornell, "brute")  # slow on purpose: each cast gives the thread time to run
    rays = random_rays(cornell, 20_000)
    wakeups, done = [0], threading.Event()
    started = threading.Event()

    def wake_up_and_count():
        started.set()
        while not done.is_set():
            time.sleep(0.0005)  # releases the GIL; waking needs it back
            wakeups[0] += 1

    old_interval = sys.getswitchinterval()
    sys.setswitchinterval(10.0)
    t = threading.Thread(target=wake_up_and_count)
    try:
        t.start()
        started.wait()
        before = wakeups[0]
        casts = 0
        while wakeups[0] - before < 10 and casts < 2000:
            accel.test_occlusions(rays, nthreads=1)
            accel.cast_rays(rays, nthreads=1)
            casts += 2
        counted = wakeups[0] - before
    finally:
        done.set()
        t.join()
        sys.setswitchinterval(old_interval)
    assert counted >= 10, (counted, casts)


def test_large_outputs_reusing_freed_memory_hold_every_answer(cornell):
    """Outputs of 1 MiB and more live in huge-page mappings that are kept for the next arrays of the
    same size once their arrays die: every element must be written again, misses included."""
    accel = thicket.build(cornell, "bvh8")
    rays = random_rays(cornell, 300_000, seed=4)   # normals: 3.6 MB
    rays[::7, 3:6] = 0                             # invalid rows: misses
    first = accel.cast_rays(np.ascontiguousarray(rays[::-1]))
    assert np.isfinite(first["t_hit"]).mean() > 0.5
    del first                                      # its memory is kept, then handed to `second`
    second = accel.cast_rays(rays)
    third = accel.cast_rays(rays)                  # fresh memory while `second` lives
    for key in second:
        assert np.array_equal(second[key], third[key]), key
    assert np.all(np.isinf(second["t_hit"][::7])) and np.all(second["primitive_ids"][::7] == thicket.INVALID_ID)
    assert np.all(second["primitive_normals"][::7] == 0)
    occluded = accel.test_occlusions(rays)
    assert np.array_equal(occluded, np.isfinite(second["t_hit"]))


@pytest.mark.parametrize("width", [8, 6])
def test_large_batches_answer_as_small_ones_and_as_rows_one_by_one(cornell, width):
    """A large batch's answers are written four rows at a time with non-temporal stores, a small
    batch's through the cache, and a chunk that holds a row without a ray one row at a time: the
    three must agree bit for bit, misses included."""
    accel = thicket.build(cornell, "bvh8")
    rays = random_rays(cornell, 300_000, seed=5, width=width)   # t_hit: 1.2 MB, streamed
    rays[::5, :3] = rays[::5, :3] - 4 * rays[::5, 3:6]          # more misses: rays turned around
    rays[::5, 3:6] *= -1
    big = accel.cast_rays(rays)
    assert 0.2 < np.isfinite(big["t_hit"]).mean() < 0.9
    miss = ~np.isfinite(big["t_hit"])
    assert np.all(big["primitive_ids"][miss] == thicket.INVALID_ID) and np.all(big["geometry_ids"][miss] == thicket.INVALID_ID)
    assert np.all(big["geometry_ids"][~miss] == 0)
    assert np.all(big["primitive_uvs"][miss] == 0) and np.all(big["primitive_normals"][miss] == 0)
    small = [accel.cast_rays(rays[i:i + 1000]) for i in range(0, len(rays), 1000)]
    gaps = np.arange(0, len(rays), 251)                         # a row without a ray in every chunk
    invalid = np.zeros(width, np.float32)
    with_gaps = np.insert(rays, gaps, invalid, axis=0)
    kept = np.ones(len(with_gaps), bool)
    kept[gaps + np.arange(len(gaps))] = False
    one_by_one = accel.cast_rays(with_gaps)
    for key in big:
        assert np.array_equal(big[key], np.concatenate([s[key] for s in small])), key
        assert np.array_equal(big[key], one_by_one[key][kept]), key
    occluded = accel.test_occlusions(rays)
    assert np.array_equal(occluded, ~miss)
    assert np.array_equal(accel.test_occlusions(with_gaps)[kept], occluded)
