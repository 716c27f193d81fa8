"""thicket.create_rays_pinhole: the formula Open3D's RaycastingScene.create_rays_pinhole documents
(checked here by hand, always), the very numbers Open3D gives where Debian's python3-open3d is
importable, rays that see what they should, and errors that name the argument."""

import math

import numpy as np
import pytest

import thicket

VIEWS = [  # fov_deg, center, eye, up, width_px, height_px
    (90.0, [0, 0, 0], [0, 0, -5], [0, 1, 0], 4, 2),
    (60.0, [1, 2, 3], [-4, 5, 9], [0, 0, 1], 7, 5),
    (30.5, [0.25, -1, 0], [3, 3, 3], [0.2, 1, 0.1], 16, 9),
    (120.0, [1e3, 0, 0], [0, 0, 0], [0, -2, 0.5], 3, 11),
]

MATRICES = [  # intrinsic, extrinsic, width_px, height_px
    ([[100, 0, 2], [0, 100, 1], [0, 0, 1]], np.eye(4), 4, 2),
    ([[500, 3, 320.5], [0, 480, 240], [0, 0, 1]],
     [[0, -1, 0, 1], [0, 0, -1, 2], [1, 0, 0, 3], [0, 0, 0, 1]], 13, 6),
    # R not a rotation: Open3D applies R^T, not R^-1, and so must we.
    ([[50, 7, 2], [0, 25, 1], [0, 0, 1]], np.diag([2.0, 1.0, 1.0, 1.0]), 5, 3),
]


def view_formula(fov_deg, center, eye, up, w, h):
    """Open3D's construction written out per pixel, in the simplest terms."""
    center, eye, up = (np.array(v, np.float64) for v in (center, eye, up))
    z = (center - eye) / np.linalg.norm(center - eye)
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    f = 0.5 * w / math.tan(math.radians(fov_deg) / 2)
    out = np.empty((h, w, 6))
    for row in range(h):
        for col in range(w):
            cam = np.array([(col + 0.5 - 0.5 * w) / f, (row + 0.5 - 0.5 * h) / f, 1.0])
            out[row, col, :3] = eye
            out[row, col, 3:] = cam[0] * x + cam[1] * y + cam[2] * z
    return out


def matrices_formula(k, e, w, h):
    k, e = np.array(k, np.float64), np.array(e, np.float64)
    r, t = e[:3, :3], e[:3, 3]
    out = np.empty((h, w, 6))
    for row in range(h):
        for col in range(w):
            out[row, col, :3] = -r.T @ t
            out[row, col, 3:] = r.T @ np.linalg.solve(k, [col + 0.5, row + 0.5, 1.0])
    return out


def close(a, b):
    scale = max(1.0, float(np.abs(b).max()))
    return np.allclose(a, b, rtol=2e-6, atol=2e-6 * scale)


@pytest.mark.parametrize("view", VIEWS)
def test_view_form_is_the_formula(view):
    rays = thicket.create_rays_pinhole(*view)
    assert rays.dtype == np.float32 and rays.shape == (view[5], view[4], 6)
    assert close(rays, view_formula(*view))


@pytest.mark.parametrize("case", MATRICES)
def test_matrix_form_is_the_formula(case):
    rays = thicket.create_rays_pinhole(*case)
    assert rays.dtype == np.float32 and rays.shape == (case[3], case[2], 6)
    assert close(rays, matrices_formula(*case))


def test_keywords_as_open3d_names_them():
    fov, center, eye, up, w, h = VIEWS[1]
    by_name = thicket.create_rays_pinhole(fov_deg=fov, center=center, eye=eye, up=up, width_px=w, height_px=h)
    assert np.array_equal(by_name, thicket.create_rays_pinhole(*VIEWS[1]))
    k, e, w, h = MATRICES[1]
    by_name = thicket.create_rays_pinhole(intrinsic_matrix=k, extrinsic_matrix=e, width_px=w, height_px=h)
    assert np.array_equal(by_name, thicket.create_rays_pinhole(*MATRICES[1]))


def test_the_view_form_is_the_matrix_form_of_its_camera():
    # Open3D defines one by the other: K from fov and width, [R | -R eye] from the look-at frame.
    fov, center, eye, up, w, h = VIEWS[2]
    f = 0.5 * w / math.tan(math.radians(fov) / 2)
    k = [[f, 0, w / 2], [0, f, h / 2], [0, 0, 1]]
    z = np.subtract(center, eye) / np.linalg.norm(np.subtract(center, eye))
    x = np.cross(up, z) / np.linalg.norm(np.cross(up, z))
    r = np.array([x, np.cross(z, x), z])
    e = np.eye(4)
    e[:3, :3], e[:3, 3] = r, -r @ np.array(eye, np.float64)
    assert close(thicket.create_rays_pinhole(fov, center, eye, up, w, h), thicket.create_rays_pinhole(k, e, w, h))


def test_rays_see_the_scene_where_they_should():
    # A unit square at z = 0 seen from z = -5: the centre pixels hit it at depth 5 (t along the
    # unnormalized direction is the depth), the corners miss, and the hit is where the ray points.
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]], np.float32)
    accel = thicket.build(thicket.Scene(v, np.array([[0, 1, 2], [0, 2, 3]], np.int32)), "bvh")
    rays = thicket.create_rays_pinhole(20.0, [0, 0, 0], [0, 0, -5], [0, 1, 0], 9, 9)
    hits = accel.cast_rays(rays)
    assert hits["t_hit"].shape == (9, 9)
    assert hits["t_hit"][4, 4] == pytest.approx(5.0, rel=1e-6)
    assert math.isinf(hits["t_hit"][0, 0]) and math.isinf(hits["t_hit"][8, 8])
    seen = np.isfinite(hits["t_hit"])
    hit_points = rays[..., :3] + np.where(seen, hits["t_hit"], 0)[..., None] * rays[..., 3:]
    assert seen.sum() > 9 and np.allclose(hit_points[seen][:, 2], 0, atol=1e-5)
    # Open3D's orientation: row 0 looks down (-y, along -up), column 0 to the viewer's right (-x here).
    assert rays[0, 4, 4] < 0 and rays[4, 0, 3] < 0


BAD = [
    ((0.0, [0, 0, 0], [0, 0, -1], [0, 1, 0], 4, 4), ValueError, "fov_deg must be in"),
    ((180.0, [0, 0, 0], [0, 0, -1], [0, 1, 0], 4, 4), ValueError, "fov_deg must be in"),
    ((float("nan"), [0, 0, 0], [0, 0, -1], [0, 1, 0], 4, 4), ValueError, "fov_deg"),
    (("wide", [0, 0, 0], [0, 0, -1], [0, 1, 0], 4, 4), TypeError, "fov_deg must be a number"),
    ((60.0, [0, 0, 0], [0, 0, 0], [0, 1, 0], 4, 4), ValueError, "center and eye are the same point"),
    ((60.0, [0, 0, 0], [0, 0, -1], [0, 0, 3], 4, 4), ValueError, "up \\[0.0, 0.0, 3.0\\] is parallel"),
    ((60.0, [0, 0, 0], [0, 0, -1], [0, 0, 0], 4, 4), ValueError, "up is the zero vector"),
    ((60.0, [0, 0], [0, 0, -1], [0, 1, 0], 4, 4), ValueError, "center must have shape \\(3,\\), got \\(2,\\)"),
    ((60.0, [0, 0, 0], [0, np.inf, -1], [0, 1, 0], 4, 4), ValueError, "eye must be finite"),
    ((60.0, [0, 0, 0], [0, 0, -1], [0, 1, 0], 0, 4), ValueError, "width_px must be at least 1, got 0"),
    ((60.0, [0, 0, 0], [0, 0, -1], [0, 1, 0], 4, 2.5), TypeError, "height_px must be an int"),
    ((60.0, [0, 0, 0], [0, 0, -1], [0, 1, 0], True, 4), TypeError, "width_px must be an int, not bool"),
    (([[1, 0, 0], [0, 1, 0], [0, 0, 0]], np.eye(4), 4, 4), ValueError, "intrinsic_matrix is singular"),
    (([[1, 0, 0], [0, 1, 0], [0, 0, 1]], np.eye(3), 4, 4), ValueError, "extrinsic_matrix must have shape \\(4, 4\\)"),
    (([[1, 0, 0], [0, 1, 0], [0, 0, np.nan]], np.eye(4), 4, 4), ValueError, "intrinsic_matrix must be finite"),
]


@pytest.mark.parametrize("args,error,message", BAD)
def test_bad_arguments_are_named(args, error, message):
    with pytest.raises(error, match=message):
        thicket.create_rays_pinhole(*args)


def test_a_wrong_call_names_the_form_it_was_taken_for():
    with pytest.raises(TypeError, match=r"create_rays_pinhole\(fov_deg, center, eye, up, width_px, height_px\): "
                                        r"missing a required argument: 'height_px'"):
        thicket.create_rays_pinhole(60.0, [0, 0, 0], [0, 0, 1], [0, 1, 0], 4)
    with pytest.raises(TypeError, match=r"create_rays_pinhole\(intrinsic_matrix, extrinsic_matrix, width_px, "
                                        r"height_px\): got an unexpected keyword argument 'fov_deg'"):
        thicket.create_rays_pinhole(np.eye(3), np.eye(4), 4, 4, fov_deg=3)


def open3d_scene_class():
    try:
        import open3d  # python3-open3d, scripts/setup
    except ImportError as e:
        pytest.skip(f"Open3D is not importable ({e}); the formula tests above still ran")
    return open3d.t.geometry.RaycastingScene  # an attribute: open3d.t is no importable module


@pytest.mark.parametrize("view", VIEWS)
def test_view_form_equals_open3d(view):
    import open3d.core as o3c
    scene = open3d_scene_class()
    fov, center, eye, up, w, h = view
    theirs = scene.create_rays_pinhole(fov, *(o3c.Tensor(np.array(v, np.float32)) for v in (center, eye, up)), w, h)
    theirs = theirs.numpy()
    ours = thicket.create_rays_pinhole(*view)
    assert theirs.dtype == ours.dtype and theirs.shape == ours.shape
    assert close(ours, theirs)


@pytest.mark.parametrize("case", MATRICES)
def test_matrix_form_equals_open3d(case):
    import open3d.core as o3c
    scene = open3d_scene_class()
    k, e, w, h = case
    theirs = scene.create_rays_pinhole(o3c.Tensor(np.array(k, np.float64)), o3c.Tensor(np.array(e, np.float64)), w, h)
    theirs = theirs.numpy()
    ours = thicket.create_rays_pinhole(*case)
    assert theirs.dtype == ours.dtype and theirs.shape == ours.shape
    assert close(ours, theirs)
    # Open3D tensors are taken as they are, too.
    assert np.array_equal(thicket.create_rays_pinhole(o3c.Tensor(np.array(k, np.float64)),
                                                      o3c.Tensor(np.array(e, np.float64)), w, h), ours)
