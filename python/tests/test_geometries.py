"""geometry_ids: a scene's geometries (one per mesh or shape entry of a JSON scene, in file order)
are what every query reports, as Open3D numbers the meshes added to a RaycastingScene."""

import json

import numpy as np
import pytest

import thicket


@pytest.fixture(scope="module")
def two_quads_path(tmp_path_factory):
    """A JSON scene of the same unit quad twice: geometry 0 at z = 0, geometry 1 at z = 2."""
    d = tmp_path_factory.mktemp("geometries")
    (d / "quad.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    shapes = [{"type": "mesh", "file": "quad.obj"},
              {"type": "mesh", "file": "quad.obj", "transform": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 2, 0, 0, 0, 1]}]
    (d / "scene.json").write_text(json.dumps({"shapes": shapes}))
    return str(d / "scene.json")


@pytest.fixture(scope="module")
def two_quads(two_quads_path):
    return thicket.load_scene(two_quads_path)


RAYS = np.array([[0.3, 0.6, 5, 0, 0, -1]] * 4 + [[0.6, 0.3, -5, 0, 0, 1]] * 4 + [[5, 5, 5, 0, 0, 1]] * 4, np.float32)
WANT = [1] * 4 + [0] * 4 + [thicket.INVALID_ID] * 4


@pytest.mark.parametrize("spec", ["bvh", "bvh8", "kdtree", "brute"])
def test_every_query_names_the_geometry_it_hit(two_quads, spec):
    accel = thicket.build(two_quads, spec)
    # From above (hits z = 2 first), from below (z = 0 first), and a miss; 4 rows of each so that
    # the module's four-rows-at-once writer has whole groups.
    rays = RAYS
    hits = accel.cast_rays(rays)
    assert hits["geometry_ids"].tolist() == WANT
    assert np.array_equal(hits["primitive_ids"][:4] >= 2, [True] * 4)  # the second quad's triangles

    listed = accel.list_intersections(rays[:1])
    assert listed["geometry_ids"].tolist() == [1, 0]  # sorted by t: the upper quad first

    # Closest points: every structure answers them (others through a bvh8 built on first use).
    near = accel.compute_closest_points(np.array([[0.5, 0.5, 1.9], [0.5, 0.5, 0.1], [0.5, 0.5, 0.5]], np.float32))
    assert near["geometry_ids"].tolist() == [1, 0, 0]


def test_a_scene_from_arrays_is_one_geometry():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], np.float32)
    scene = thicket.Scene(vertices, np.array([[0, 1, 2], [3, 4, 5]], np.int32))
    hits = thicket.build(scene, "bvh").cast_rays(np.array([[0.2, 0.2, 5, 0, 0, -1], [0.2, 0.2, -5, 0, 0, 1]], np.float32))
    assert hits["primitive_ids"].tolist() == [1, 0]
    assert hits["geometry_ids"].tolist() == [0, 0]


def test_dask_reports_the_same_geometry_ids(two_quads_path):
    thicket_dask = pytest.importorskip("thicket.dask")
    hits = thicket_dask.cast_rays(RAYS, two_quads_path, spec="bvh")
    assert hits["geometry_ids"].compute().tolist() == WANT
    assert hits["t_hit"].compute()[:4].tolist() == pytest.approx([3.0] * 4)
