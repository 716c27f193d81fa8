"""Scenes, structures, the registry listing, save/load and the errors each raises."""

import numpy as np
import pytest

import thicket
from conftest import cube_arrays, random_rays


def test_load_builtin_and_properties(cornell):
    assert cornell.name == "cornell"
    assert cornell.triangle_count == cornell.primitive_count > 0
    assert cornell.vertices.shape[1] == 3 and cornell.vertices.dtype == np.float32
    assert cornell.triangles.shape == (cornell.triangle_count, 3) and cornell.triangles.dtype == np.uint32
    lo, hi = cornell.bounds
    assert all(a < b for a, b in zip(lo, hi))


def test_load_shapes_scene():
    scene = thicket.load_scene("teapot-patches")
    assert scene.shape_count == 32 and scene.triangle_count == 0


def test_scene_from_arrays_round_trips(cube):
    v, t = cube_arrays()
    assert np.array_equal(cube.vertices, v) and np.array_equal(cube.triangles, t)
    assert cube.bounds == ((0, 0, 0), (1, 1, 1))
    # float64 vertices and uint64 indices are converted; the answers do not change.
    other = thicket.Scene(v.astype(np.float64), t.astype(np.uint64))
    assert np.array_equal(other.vertices, v)


@pytest.mark.parametrize("vertices, triangles, message", [
    (np.zeros((4, 2), np.float32), np.zeros((1, 3), np.int32), r"vertices: .*\(V, 3\), got shape \(4, 2\)"),
    (np.zeros((4, 3), np.int32), np.zeros((1, 3), np.int32), r"vertices: .*got shape \(4, 3\) int32"),
    (np.zeros((4, 3), np.float32), np.zeros((1, 4), np.int32), r"triangles: .*got shape \(1, 4\)"),
    (np.zeros((4, 3), np.float32), np.zeros((1, 3), np.float32), r"triangles: .*got shape \(1, 3\) float32"),
    (np.zeros((4, 3), np.float32), np.array([[0, 1, 4]]), r"triangles: row 0 has vertex index 4, outside 0..3"),
    (np.zeros((4, 3), np.float32), np.array([[0, -1, 2]]), r"vertex index -1"),
    (np.array([[0, 0, 0], [np.nan, 0, 0], [1, 1, 1]], np.float32), np.array([[0, 1, 2]]), r"row 1 is not finite"),
])
def test_scene_from_arrays_errors(vertices, triangles, message):
    with pytest.raises(ValueError, match=message):
        thicket.Scene(vertices, triangles)


def test_load_scene_errors(tmp_path):
    with pytest.raises(OSError, match="no such file"):
        thicket.load_scene(tmp_path / "missing.ply")
    with pytest.raises(OSError, match="is a directory"):
        thicket.load_scene(str(tmp_path) + "/")  # a directory named like no format: still a file error
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex oops\n")
    with pytest.raises(thicket.Error, match="bad.ply"):
        thicket.load_scene(bad)
    (tmp_path / "scene.xyz").write_text("1 2 3\n")
    with pytest.raises(thicket.Error, match="unknown scene format '.xyz'"):
        thicket.load_scene(tmp_path / "scene.xyz")
    assert issubclass(thicket.Error, RuntimeError) and not issubclass(thicket.Error, OSError)


def test_accels_lists_every_structure():
    infos = {a["name"]: a for a in thicket.accels()}
    assert {"brute", "bvh", "bvh8", "grid", "kdtree"} <= set(infos)
    builders = next(o for o in infos["bvh"]["options"] if o["key"] == "builder")
    assert "sweep-sah" in builders["choices"] and builders["default"] in builders["choices"]
    leaf = next(o for o in infos["bvh"]["options"] if o["key"] == "max-leaf")
    assert leaf["min"] == 1 and leaf["max"] == 255
    assert all(a["variants"] for a in infos.values())


def test_build_and_stats(cube):
    accel = thicket.build(cube, "bvh:builder=binned-sah")
    s = accel.stats()
    assert s["spec"] == accel.spec and s["spec"].startswith("bvh:")
    assert s["primitives"] == 12 and s["nodes"] >= 1 and s["bytes"] > 0 and s["build_ms"] >= 0
    assert isinstance(s["extra"], dict)
    assert accel.bounds == ((0, 0, 0), (1, 1, 1))
    assert thicket.build(cube).spec.startswith("bvh8")  # the default, as the CLI's
    assert accel.scene.primitive_count == 12


@pytest.mark.parametrize("spec, message", [
    ("nope", "nope"), ("bvh:builder=best", "builder=best"), ("bvh:max-leaf=0", "max-leaf"), ("bvh:colour=red", "colour")])
def test_build_refuses_bad_specs(cube, spec, message):
    with pytest.raises(thicket.Error, match=message):
        thicket.build(cube, spec)


def test_save_and_load(tmp_path, cube, cornell):
    rays = random_rays(cube, 500)
    accel = thicket.build(cube, "bvh")
    path = tmp_path / "cube.bvh"
    accel.save(path)
    loaded = thicket.load(path, cube)
    assert loaded.spec == accel.spec
    a, b = accel.cast_rays(rays), loaded.cast_rays(rays)
    assert all(np.array_equal(a[k], b[k]) for k in a)
    with pytest.raises(thicket.Error, match="scene"):
        thicket.load(path, cornell)  # saved for another scene
    with pytest.raises(OSError):
        thicket.load(tmp_path / "missing.bvh", cube)
    with pytest.raises(OSError):
        accel.save(tmp_path / "no-such-dir" / "cube.bvh")
    path.write_bytes(b"garbage")
    with pytest.raises(thicket.Error):
        thicket.load(path, cube)
