"""Bad arguments get the CLI's answers: a MemoryError naming the argument before a too-large
allocation (checked in a child process whose address space is capped, so that a failing check
can never take this machine's memory), counts and indices quoted as given, paths as open()
takes them, NUL bytes refused, nthreads as -j, and Accel.save refusing its inputs and, without
overwrite=True, existing files."""

import os
import subprocess
import sys
import textwrap

import dask.array as da
import numpy as np
import pytest

import thicket
import thicket.dask
from conftest import cube_arrays, random_rays

GIB = 1 << 30


def run_capped(code, limit_bytes):
    """Runs `code` in a fresh interpreter whose address space is capped at `limit_bytes`
    (RLIMIT_AS, before thicket is imported); returns its stdout. The child prints what it saw."""
    prelude = textwrap.dedent(f"""
        import resource
        resource.setrlimit(resource.RLIMIT_AS, ({limit_bytes}, {limit_bytes}))
        import numpy as np, thicket
        def report(f):
            try:
                f()
                print("no error")
            except BaseException as e:
                print(type(e).__name__ + ": " + str(e))
    """)
    result = subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


def tiny_scene_code():
    return "v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)\n"


def test_broadcast_index_array_is_a_memory_error_before_allocating():
    out = run_capped(tiny_scene_code() + """
report(lambda: thicket.Scene(v, np.broadcast_to(np.array([0, 1, 2]), (10**9, 3))))
""", GIB)
    assert out.startswith("MemoryError: Scene(vertices of shape (3, 3), triangles of shape (1000000000, 3))"), out
    assert "needs 11.2 GiB of memory" in out, out


@pytest.mark.parametrize("query, width", [
    ("cast_rays", 8), ("test_occlusions", 6), ("count_intersections", 8), ("list_intersections", 6),
    ("compute_closest_points", 3), ("compute_distance", 3), ("compute_occupancy", 3), ("compute_signed_distance", 3),
])
def test_broadcast_rows_are_a_memory_error_naming_the_argument(query, width):
    what = "query_points" if width == 3 else "rays"
    out = run_capped(tiny_scene_code() + f"""
accel = thicket.build(thicket.Scene(v, np.array([[0, 1, 2]])))
rows = np.broadcast_to(np.ones({width}, np.float32), (10**9, {width}))
report(lambda: accel.{query}(rows))
""", GIB)
    assert out.startswith(f"MemoryError: {what}: a contiguous float32 copy of the array of shape (1000000000, {width})"), out


def test_answers_too_large_for_memory_are_a_memory_error():
    # 40M rays of 6 floats (960 MB, never touched: calloc'd pages) fit under 1 GiB; cast_rays'
    # 32 bytes of answers per ray (1.28 GB) do not.
    out = run_capped(tiny_scene_code() + """
accel = thicket.build(thicket.Scene(v, np.array([[0, 1, 2]])))
rays = np.zeros((40_000_000, 6), np.float32)
report(lambda: accel.cast_rays(rays))
""", GIB)
    assert out.startswith("MemoryError: cast_rays: answering an array of shape (40000000, 6) needs 1.2 GiB"), out


def test_numpy_memory_error_reaches_the_caller_with_its_message():
    # The copy (488 MiB) passes the check against the 512 MiB cap, but the interpreter already
    # holds some of it: numpy's own allocation fails, and its MemoryError must come through.
    out = run_capped(tiny_scene_code() + """
accel = thicket.build(thicket.Scene(v, np.array([[0, 1, 2]])))
report(lambda: accel.cast_rays(np.broadcast_to(np.ones(8, np.float32), (16_000_000, 8))))
""", 512 << 20)
    assert out.startswith("MemoryError: "), out
    assert "Unable to allocate" in out or "needs" in out, out
    assert "error_already_set" not in out


@pytest.mark.parametrize("vertices, triangles, message", [
    # Broadcast views: nothing is allocated, and the count is refused before memory is asked.
    (np.zeros((3, 3), np.float32), np.broadcast_to(np.array([0, 1, 2]), (2**32, 3)),
     r"triangles: 4294967296 rows; a scene holds at most 4294967294 triangles"),
    (np.broadcast_to(np.zeros(3, np.float32), (2**32 + 1, 3)), np.array([[0, 1, 2]]),
     r"vertices: 4294967297 rows; 32-bit indices name at most 4294967296"),
    (np.zeros((3, 3), np.float32), np.array([[0, 1, 2**64 - 1]], np.uint64),
     r"row 0 has vertex index 18446744073709551615, outside 0..2"),
    (np.zeros((3, 3), np.float32), np.array([[0, 1, 2**63]], np.uint64), r"vertex index 9223372036854775808,"),
])
def test_counts_and_indices_out_of_range_are_quoted_as_given(vertices, triangles, message):
    with pytest.raises(ValueError, match=message):
        thicket.Scene(vertices, triangles)


def test_strided_and_broadcast_arrays_are_read_in_blocks():
    v, t = cube_arrays()
    # Fortran-ordered float64 vertices, every other row of a doubled index array, and a
    # broadcast triangle list longer than one block: the same scene as the plain arrays.
    doubled = np.repeat(t.astype(np.uint16), 2, axis=0)[::2]
    scene = thicket.Scene(np.asfortranarray(v.astype(np.float64)), doubled)
    assert np.array_equal(scene.vertices, v) and np.array_equal(scene.triangles, t)
    many = thicket.Scene(v, np.broadcast_to(t[0], (200_000, 3)))
    assert many.triangle_count == 200_000 and np.array_equal(many.triangles[-1], t[0])


@pytest.mark.parametrize("nthreads, error, message", [
    (-1, ValueError, r"^nthreads must be 0 \(one thread per core\) or a thread count up to 4294967295, got -1$"),
    (2**32, ValueError, r"got 4294967296$"),
    (2**70, ValueError, r"got 1180591620717411303424$"),
    (1.5, TypeError, r"^nthreads must be an integer, got float$"),
    ("4", TypeError, r"got str$"),
])
@pytest.mark.parametrize("query", ["cast_rays", "test_occlusions", "count_intersections", "list_intersections",
                                   "compute_closest_points", "compute_distance", "compute_occupancy",
                                   "compute_signed_distance"])
def test_bad_thread_counts_are_short_errors(cube, query, nthreads, error, message):
    accel = thicket.build(cube, "bvh")
    rows = np.zeros((1000, 3 if query.startswith("compute") else 6), np.float32)
    with pytest.raises(error, match=message):
        getattr(accel, query)(rows, nthreads=nthreads)


def test_other_arguments_of_the_wrong_type_are_short_errors(cube):
    accel = thicket.build(cube, "bvh")
    rays = np.zeros((1000, 6), np.float32)
    with pytest.raises(TypeError, match=r"^coherent must be True or False, got str$"):
        accel.cast_rays(rays, coherent="yes")
    with pytest.raises(TypeError, match=r"^tfar must be a number or None, got str$"):
        accel.test_occlusions(rays, tfar="1")
    assert accel.test_occlusions(rays, tnear=np.float64(0.5), tfar=2, coherent=np.bool_(False)).shape == (1000,)


def test_coherent_is_refused_where_no_packet_path_would_take_it(cube):
    # Any-hit rays have no packet path: the hint is refused, not ignored; closest hits take it.
    accel = thicket.build(cube, "bvh8")
    rays = np.zeros((1000, 6), np.float32)
    rays[:, 5] = -1.0
    with pytest.raises(thicket.Error, match=r"test_occlusions batch: coherent .* refused rather than ignored"):
        accel.test_occlusions(rays, coherent=True)
    assert accel.cast_rays(rays, coherent=np.bool_(True))["t_hit"].shape == (1000,)
    double = thicket.build(cube, "bvh:precision=double")
    with pytest.raises(thicket.Error, match=r"float64 cast_rays batch: coherent"):
        double.cast_rays(rays.astype(np.float64), coherent=True)


def test_thread_counts_in_range_answer_alike(cube):
    accel = thicket.build(cube, "bvh")
    rays = random_rays(cube, 300)
    want = accel.cast_rays(rays)["t_hit"]
    for n in (0, 1, np.int64(3), True, 2**32 - 1):  # more threads than chunks: only as many start
        assert np.array_equal(accel.cast_rays(rays, nthreads=n)["t_hit"], want), n
    with pytest.raises(ValueError, match=r"^nsamples must be an odd count up to 5, got 1267650600228229401496703205376$"):
        accel.compute_occupancy(np.zeros((2, 3), np.float32), nsamples=2**100)


def test_nul_bytes_are_refused_where_they_are(cube, tmp_path):
    with pytest.raises(ValueError, match=r"^spec contains a NUL byte at position 3: 'bvh\\x00:leaf=2'$"):
        thicket.build(cube, "bvh\0:leaf=2")
    with pytest.raises(ValueError, match=r"^path contains a NUL byte at position 5: 'cube\.\\x00ply'$"):
        thicket.load_scene("cube.\0ply")
    accel = thicket.build(cube, "bvh")
    with pytest.raises(ValueError, match=r"NUL byte at position 1"):
        accel.save(b"x\0.bvh")
    with pytest.raises(ValueError, match=r"NUL byte at position 2"):
        thicket.load("ab\0", cube)
    assert os.listdir(tmp_path) == []


def write_ply(path, vertices, triangles):
    """An ASCII PLY of the mesh, as the loader reads it."""
    lines = ["ply", "format ascii 1.0", f"element vertex {len(vertices)}", "property float x", "property float y",
             "property float z", f"element face {len(triangles)}", "property list uchar int vertex_indices",
             "end_header"]
    lines += [" ".join(str(float(c)) for c in p) for p in vertices]
    lines += ["3 " + " ".join(str(int(i)) for i in t) for t in triangles]
    path.write_text("\n".join(lines) + "\n")


def test_paths_may_be_str_bytes_or_pathlike(cube, tmp_path):
    write_ply(tmp_path / "cube.ply", *cube_arrays())
    by_bytes = thicket.load_scene(os.fsencode(tmp_path / "cube.ply"))
    assert np.array_equal(by_bytes.triangles, cube.triangles)
    accel = thicket.build(cube, "bvh")
    accel.save(os.fsencode(tmp_path / "x.bin"))
    assert sorted(os.listdir(tmp_path)) == ["cube.ply", "x.bin"]  # not a file named "b'x.bin'"
    assert thicket.load(tmp_path / "x.bin", cube).spec == accel.spec
    assert thicket.load(str(tmp_path / "x.bin"), cube).spec == accel.spec
    with pytest.raises(TypeError):
        accel.save(42)


def test_save_refuses_the_scene_file_under_any_name(tmp_path):
    ply = tmp_path / "cube.ply"
    write_ply(ply, *cube_arrays())
    before = ply.read_bytes()
    os.link(ply, tmp_path / "hard.ply")
    os.symlink(ply, tmp_path / "soft.ply")
    accel = thicket.build(thicket.load_scene(ply), "bvh")
    for name in ("cube.ply", "hard.ply", "soft.ply"):
        for overwrite in (False, True):
            with pytest.raises(ValueError, match=r"is the scene file .*cube\.ply this structure was made from: saving "
                                                 r"there would destroy it; choose another path"):
                accel.save(tmp_path / name, overwrite=overwrite)
    assert ply.read_bytes() == before
    # The scene file renamed after loading: still the same file.
    os.rename(ply, tmp_path / "moved.ply")
    with pytest.raises(ValueError, match="is the scene file"):
        accel.save(tmp_path / "moved.ply", overwrite=True)
    # A new file at the scene's path after loading: the path named as the input, still refused.
    write_ply(ply, *cube_arrays())
    with pytest.raises(ValueError, match="is the scene file"):
        accel.save(ply, overwrite=True)
    (tmp_path / "other.ply").write_bytes(before)  # equal bytes, but another file: replaced
    accel.save(tmp_path / "other.ply", overwrite=True)
    accel.save(tmp_path / "cube.bvh")  # another path is fine


def test_save_refuses_the_structure_it_was_loaded_from(cube, tmp_path):
    thicket.build(cube, "bvh").save(tmp_path / "cube.bvh")
    loaded = thicket.load(tmp_path / "cube.bvh", cube)
    with pytest.raises(ValueError, match=r"is the saved structure .*cube\.bvh"):
        loaded.save(tmp_path / "cube.bvh", overwrite=True)
    loaded.save(tmp_path / "copy.bvh")
    assert (tmp_path / "copy.bvh").read_bytes() == (tmp_path / "cube.bvh").read_bytes()


def test_save_replaces_an_existing_file_only_when_asked(cube, tmp_path):
    path = tmp_path / "out.bvh"
    path.write_bytes(b"keep me")
    accel = thicket.build(cube, "bvh")
    with pytest.raises(FileExistsError, match=r"out\.bvh already exists \(pass overwrite=True to replace it\)"):
        accel.save(path)
    assert path.read_bytes() == b"keep me"
    accel.save(path, overwrite=True)
    assert thicket.load(path, cube).spec == accel.spec
    accel.save(os.devnull)  # a special file is written through, as the CLI does


def test_dask_notices_a_replaced_scene_file(tmp_path):
    v, t = cube_arrays()
    ply = tmp_path / "scene.ply"
    write_ply(ply, v, t)
    rays = random_rays(thicket.Scene(v, t), 200, seed=3)
    first = thicket.dask.cast_rays(da.from_array(rays, chunks=(100, 8)), ply, spec="bvh")["t_hit"]
    assert np.array_equal(first.compute(scheduler="synchronous"), thicket.build(thicket.Scene(v, t)).cast_rays(rays)["t_hit"])
    # Replaced by a cube twice as large (a new file renamed over the old one), same process.
    write_ply(tmp_path / "new.ply", 2 * v, t)
    os.replace(tmp_path / "new.ply", ply)
    want = thicket.build(thicket.Scene(2 * v, t)).cast_rays(rays)["t_hit"]
    again = thicket.dask.cast_rays(da.from_array(rays, chunks=(100, 8)), ply, spec="bvh")["t_hit"]
    assert np.array_equal(again.compute(scheduler="synchronous"), want)
    # Rewritten in place (same inode): noticed by its size and time.
    write_ply(ply, v, t)
    counts = thicket.dask.count_intersections(rays, ply, spec="bvh").compute(scheduler="synchronous")
    assert np.array_equal(counts, thicket.build(thicket.Scene(v, t)).count_intersections(rays))


def test_dask_takes_numpy_arrays_and_bytes_paths(cornell):
    rays = random_rays(cornell, 500, seed=5)
    want = thicket.build(cornell, "bvh8").cast_rays(rays)
    got = thicket.dask.cast_rays(rays, b"cornell")
    for key in want:
        assert np.array_equal(got[key].compute(scheduler="synchronous"), want[key]), key
    with pytest.raises(TypeError, match=r"rays: expected a dask array \(or a numpy array\) .*got list"):
        thicket.dask.cast_rays(rays.tolist(), "cornell")
    with pytest.raises(ValueError, match="nthreads must be"):
        thicket.dask.test_occlusions(rays, "cornell", nthreads=-1)
