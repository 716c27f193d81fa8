"""Scene.set_vertices and Accel.refit: after moving a geometry's vertices and refitting, a structure
answers exactly as a fresh build (and brute force) over the moved scene; what cannot be moved or
refitted is refused with a message, leaving the scene and the structure as they were."""

import gc
import json

import numpy as np
import pytest

import thicket
from conftest import random_rays

REFITTABLE = ["bvh", "bvh8", "obb"]
GRID = 9  # vertices per side of the sheet: 8 x 8 quads, 128 triangles per geometry


def sheet_obj():
    """A unit sheet in the plane z = 0 as GRID^2 vertices and its quads (split in two by the loader)."""
    lines = [f"v {x / (GRID - 1)} {y / (GRID - 1)} 0" for y in range(GRID) for x in range(GRID)]
    for y in range(GRID - 1):
        for x in range(GRID - 1):
            a = y * GRID + x + 1  # OBJ counts from 1
            lines.append(f"f {a} {a + 1} {a + GRID + 1} {a + GRID}")
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def two_sheets_path(tmp_path_factory):
    """Geometry 0: the sheet at z = 0; geometry 1: the same sheet at z = 1 (scene.json); the same
    and geometry 2, a sphere (with_sphere.json: closest points need triangles only)."""
    d = tmp_path_factory.mktemp("refit")
    (d / "sheet.obj").write_text(sheet_obj())
    lifted = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1]
    shapes = [{"type": "mesh", "file": "sheet.obj"}, {"type": "mesh", "file": "sheet.obj", "transform": lifted}]
    (d / "scene.json").write_text(json.dumps({"shapes": shapes}))
    sphere = {"type": "sphere", "center": [3, 3, 3], "radius": 0.25}
    (d / "with_sphere.json").write_text(json.dumps({"shapes": shapes + [sphere]}))
    return str(d / "scene.json")


def moved(vertices):
    """Geometry 1's vertices translated and bent: z rises along x (a sine), so that the boxes change shape."""
    out = vertices.astype(np.float64) + [0.2, -0.15, 0.1]
    out[:, 2] += 0.4 * np.sin(3.0 * out[:, 0])
    return out


def second_sheet(scene):
    """Geometry 1's vertices: the second of the two equal sheets (the sphere has none)."""
    return scene.vertices[GRID * GRID:2 * GRID * GRID]


def rays_through(scene):
    """Rays from all around, and from above and below towards both sheets' places before and after the move."""
    rng = np.random.default_rng(7)
    n = 1000
    origins = np.column_stack((rng.uniform(-0.2, 1.4, 2 * n), rng.uniform(-0.4, 1.2, 2 * n), np.repeat([5.0, -5.0], n)))
    targets = np.column_stack((rng.uniform(-0.2, 1.4, 2 * n), rng.uniform(-0.4, 1.2, 2 * n), rng.uniform(0, 1.5, 2 * n)))
    vertical = np.column_stack((origins, targets - origins)).astype(np.float32)
    return np.concatenate((vertical, random_rays(scene, n, seed=7, width=6)))


def answers(accel, rays):
    hits = accel.cast_rays(rays, nthreads=2)
    return hits["t_hit"], hits["primitive_ids"], hits["geometry_ids"], hits["primitive_normals"]


def assert_same(got, want):
    for name, a, b in zip(("t_hit", "primitive_ids", "geometry_ids", "primitive_normals"), got, want):
        assert np.array_equal(a, b), f"{name}: {np.count_nonzero(a != b)} rows differ"


@pytest.mark.parametrize("spec", REFITTABLE)
def test_a_refitted_structure_answers_as_a_fresh_build_of_the_moved_scene(two_sheets_path, spec):
    scene = thicket.load_scene(two_sheets_path)
    accel = thicket.build(scene, spec)
    assert accel.refittable is True
    rays = rays_through(scene)
    before = answers(accel, rays)  # also fills the module's cache of triangle normals
    points = np.array([[0.5, 0.5, 0.6], [0.1, 0.9, 2.0], [0.7, 0.2, -0.5]], np.float32)
    accel.compute_closest_points(points)  # and builds the fallback closest-point structure if any

    # Another Scene object, so that the refit has to read the scene it is given, not its own.
    moving = thicket.load_scene(two_sheets_path)
    moving.set_vertices(1, moved(second_sheet(moving)))
    assert np.array_equal(second_sheet(moving), moved(second_sheet(scene)).astype(np.float32))
    assert np.array_equal(moving.vertices[:GRID * GRID], scene.vertices[:GRID * GRID])  # geometry 0 stays

    fresh = thicket.build(moving, spec)
    brute = thicket.build(moving, "brute")
    want = answers(brute, rays)
    assert_same(answers(fresh, rays), want)
    # The move matters: the structure as built answers otherwise.
    assert not np.array_equal(before[0], want[0])
    assert np.count_nonzero(want[2] == 1) > 500  # many rays see the moved sheet

    accel.refit(moving, nthreads=0 if spec == "bvh" else 1)
    assert accel.scene is moving
    assert_same(answers(accel, rays), want)
    near, near_brute = accel.compute_closest_points(points), brute.compute_closest_points(points)
    for key in ("points", "primitive_ids", "geometry_ids"):
        assert np.array_equal(near[key], near_brute[key]), key


@pytest.mark.parametrize("spec", REFITTABLE)
def test_moving_the_scene_in_place_then_refitting_it(two_sheets_path, spec):
    scene = thicket.load_scene(two_sheets_path)
    accel = thicket.build(scene, spec)
    rays = rays_through(scene)
    want = moved(second_sheet(scene)).astype(np.float32)
    scene.set_vertices(1, want)
    assert np.array_equal(second_sheet(scene), want)
    accel.refit(scene)
    assert_same(answers(accel, rays), answers(thicket.build(scene, "brute"), rays))
    # And back again: a second refit follows a second move.
    scene.set_vertices(1, second_sheet(thicket.load_scene(two_sheets_path)))
    accel.refit(scene)
    assert_same(answers(accel, rays), answers(thicket.build(scene, "brute"), rays))


def test_set_vertices_refuses_what_does_not_fit_and_leaves_the_scene_as_it_was(two_sheets_path):
    scene = thicket.load_scene(two_sheets_path.replace("scene.json", "with_sphere.json"))
    original = scene.vertices
    sheet = second_sheet(scene)
    with pytest.raises(ValueError, match=r"vertices: 80 rows given, geometry 1 has 81 vertices"):
        scene.set_vertices(1, sheet[:-1])
    with pytest.raises(ValueError, match=r"geometry_id must be a geometry id in 0\.\.2, got 3"):
        scene.set_vertices(3, sheet)
    with pytest.raises(ValueError, match=r"geometry_id must be .* got -1"):
        scene.set_vertices(-1, sheet)
    with pytest.raises(TypeError, match="geometry_id must be an integer"):
        scene.set_vertices(1.0, sheet)
    with pytest.raises(ValueError, match=r"vertices: expected a float array of shape \(N, 3\), got shape \(81, 2\)"):
        scene.set_vertices(1, sheet[:, :2])
    with pytest.raises(ValueError, match="vertices: expected a float array .* int64"):
        scene.set_vertices(1, sheet.astype(np.int64))
    bad = sheet.copy()
    bad[40, 1] = np.nan
    with pytest.raises(ValueError, match="vertices: row 40 is not finite"):
        scene.set_vertices(1, bad)
    with pytest.raises(ValueError, match="vertices: row 3 is not finite as float32"):
        scene.set_vertices(1, np.where(np.arange(81)[:, None] == 3, 1e300, sheet.astype(np.float64)))
    with pytest.raises(ValueError, match="vertices: geometry 2 has no vertices to move"):
        scene.set_vertices(2, sheet[:1])
    assert np.array_equal(scene.vertices, original)
    # float64 and lists are vertices as Scene(V, T) takes them, stored as float32.
    scene.set_vertices(1, (sheet + 1).astype(np.float64).tolist())
    assert np.array_equal(second_sheet(scene), sheet + np.float32(1))


def test_structures_that_cannot_refit_say_so_and_stay_as_they_were(two_sheets_path):
    scene = thicket.load_scene(two_sheets_path)
    kdtree = thicket.build(scene, "kdtree")
    assert kdtree.refittable is False
    scene.set_vertices(1, moved(second_sheet(scene)))
    with pytest.raises(thicket.Error, match="kdtree.*rebuild"):
        kdtree.refit(scene)
    assert kdtree.scene is scene
    with pytest.raises(AttributeError):
        kdtree.refittable = True  # read-only


@pytest.mark.parametrize("spec", REFITTABLE)
def test_refit_refuses_a_scene_of_another_topology(two_sheets_path, spec):
    scene = thicket.load_scene(two_sheets_path)
    accel = thicket.build(scene, spec)
    rays = rays_through(scene)
    before = answers(accel, rays)
    other = thicket.Scene(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32), np.array([[0, 1, 2]], np.int32))
    with pytest.raises(thicket.Error, match="refit.*rebuild"):
        accel.refit(other)
    with pytest.raises(ValueError, match="refit: scene is None"):
        accel.refit(None)
    with pytest.raises(ValueError, match="nthreads must be"):
        accel.refit(scene, nthreads=-1)
    assert accel.scene is scene
    assert_same(answers(accel, rays), before)


def test_the_scene_built_over_may_go_once_the_structure_is_refitted_to_another(two_sheets_path):
    # The structure holds copies of its primitives and the module the scene it was given: the
    # first scene gone, every query reads the second.
    first = thicket.load_scene(two_sheets_path)
    accel = thicket.build(first, "obb")
    second = thicket.load_scene(two_sheets_path)
    second.set_vertices(1, moved(second_sheet(second)))
    accel.refit(second)
    del first
    gc.collect()
    rays = rays_through(second)
    brute = thicket.build(second, "brute")
    assert_same(answers(accel, rays), answers(brute, rays))
    points = np.array([[0.5, 0.5, 0.6]], np.float32)
    assert np.array_equal(accel.compute_distance(points), brute.compute_distance(points))
