"""Accel.render and thicket.heat_colours by content: depth is cast_rays' t on the same rays (and the
distance along Open3D's pinhole rays), normals are the hit faces' turned to the camera, and the
work counts are the structure's own counters, pixel for pixel what `thicket render` draws."""

import math
import os
import re
import subprocess

import numpy as np
import pytest

import thicket

CLI = os.environ.get("THICKET_CLI", "")
EYE, CENTER = (0.4, 1.3, 3.2), (0.0, 0.8, 0.0)


def square(z=0.0, half=1.0, flip=False):
    """A square [-half, half]^2 at height z facing +z (-z when flip): two triangles."""
    v = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]], np.float32)
    t = np.array([[0, 1, 2], [0, 2, 3]])
    return thicket.Scene(v, t[:, ::-1] if flip else t)


def test_depth_is_the_t_of_cast_rays_on_the_same_rays(cornell):
    accel = thicket.build(cornell)
    depth = accel.render("depth", width=40, height=30, eye=EYE, center=CENTER, vfov_deg=50)
    assert depth.dtype == np.float32 and depth.shape == (30, 40)
    rays = thicket.rays(cornell, "primary", width=40, height=30, eye=EYE, center=CENTER, vfov_deg=50)["rays"]
    t = accel.cast_rays(rays)["t_hit"].reshape(30, 40)
    assert 0.3 < np.isfinite(depth).mean() < 1.0  # both hits and misses (inf) are in the picture
    assert np.array_equal(depth, t)


def test_depth_is_the_distance_along_open3d_pinhole_rays(cornell):
    # An independent camera: Open3D's formula (horizontal field of view, the picture turned half a
    # turn, unnormalized directions), so a flipped or transposed image cannot agree with it.
    width, height, vfov = 40, 30, 50.0
    hfov = math.degrees(2 * math.atan(math.tan(math.radians(vfov / 2)) * width / height))
    rays = thicket.create_rays_pinhole(hfov, CENTER, EYE, (0, 1, 0), width, height)[::-1, ::-1]
    hits = thicket.build(cornell, "kdtree").cast_rays(np.ascontiguousarray(rays))
    distance = hits["t_hit"] * np.linalg.norm(rays[..., 3:], axis=-1)
    depth = thicket.build(cornell).render("depth", width, height, eye=EYE, center=CENTER, vfov_deg=vfov)
    assert np.array_equal(np.isinf(depth), np.isinf(distance))
    seen = np.isfinite(depth)
    assert np.allclose(depth[seen], distance[seen], rtol=1e-4)


def test_the_normal_of_a_plane_facing_the_camera_is_everywhere_it_hits():
    view = dict(width=24, height=16, eye=(-0.8, -0.7, 2.0), center=(-0.8, -0.7, 0.0), vfov_deg=60)
    for flip in (False, True):  # wound either way, the normal shown faces the camera
        accel = thicket.build(square(flip=flip), "bvh")
        normal = accel.render("normal", **view)
        assert normal.dtype == np.float32 and normal.shape == (16, 24, 3)
        hit = np.isfinite(accel.render("depth", **view))
        assert 0.25 < hit.mean() < 0.5
        assert np.array_equal(normal[hit], np.broadcast_to(np.float32([0, 0, 1]), normal[hit].shape))
        assert (normal[~hit] == 0).all()
        # The camera looks at the square's lower left part: it fills the picture's right and top
        # (row 0 is the top), and the left columns and the bottom rows miss.
        assert hit[0, -1] and not hit[:, 0].any() and not hit[-1, :].any()


def test_normals_are_cast_rays_normals_turned_to_the_camera(cornell):
    accel = thicket.build(cornell)
    normal = accel.render("normal", width=40, height=30, eye=EYE, center=CENTER, vfov_deg=50)
    rays = thicket.rays(cornell, "primary", width=40, height=30, eye=EYE, center=CENTER, vfov_deg=50)["rays"]
    hits = accel.cast_rays(rays)
    n = hits["primitive_normals"]
    faced = np.where((np.sum(n * rays[:, 3:], axis=1) > 0)[:, None], -n, n)
    faced[~np.isfinite(hits["t_hit"])] = 0
    assert np.array_equal(normal.reshape(-1, 3), faced)
    assert len(np.unique(normal.reshape(-1, 3), axis=0)) >= 5  # walls, floor, ceiling, boxes


def test_brute_force_tests_every_primitive_for_every_pixel(cornell):
    brute = thicket.build(cornell, "brute")
    prims = brute.render("heatmap", width=20, height=15, counter="prims")
    assert prims.dtype == np.uint32 and prims.shape == (15, 20)
    assert (prims == cornell.primitive_count).all()


def test_work_is_larger_where_the_rays_meet_the_scene(cornell):
    view = dict(width=40, height=30, eye=EYE, center=CENTER, vfov_deg=50)
    accel = thicket.build(cornell, "bvh")
    nodes = accel.render("heatmap", **view)
    prims = accel.render("heatmap", counter="prims", **view)
    # Rays that miss the scene's box are refused at the root (one node, no primitive); those that
    # enter it visit more, and those that hit test primitives.
    rays = thicket.rays(cornell, "primary", **view)["rays"]
    lo, hi = (np.array(b, np.float64) for b in cornell.bounds)
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (lo - rays[:, :3]) / rays[:, 3:], (hi - rays[:, :3]) / rays[:, 3:]
    enter = np.minimum(t0, t1).max(axis=1) <= np.maximum(t0, t1).min(axis=1)
    enter = enter.reshape(30, 40)
    assert 0.1 < enter.mean() < 0.9
    assert (nodes[~enter] <= 1).all() and (prims[~enter] == 0).all()
    hit = np.isfinite(accel.render("depth", **view))
    assert (nodes[enter] > 1).all() and (prims[hit] >= 1).all()
    assert nodes[hit].mean() > 3 * nodes[~enter].mean()
    assert not np.array_equal(nodes, prims)


def test_heat_colours_are_the_cli_ramp():
    colours = thicket.heat_colours(np.array([[0, 5, 10]], np.uint32))
    assert colours.dtype == np.uint8 and colours.shape == (1, 3, 3)
    assert colours[0, 0].tolist() == [0, 0, 0] and colours[0, 2].tolist() == [255, 255, 255]
    ramp = thicket.heat_colours(np.arange(101), heat_max=100).astype(float)
    lightness = ramp @ [0.2126, 0.7152, 0.0722]
    assert (np.diff(lightness) >= 0).all() and lightness[50] > 0
    assert thicket.heat_colours([0, 50, 100, 200], heat_max=100)[3].tolist() == [255, 255, 255]  # clamped


@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
def test_heatmap_is_thicket_render_heatmap(tmp_path, cornell):
    out = subprocess.run([CLI, "render", "cornell", "--view", "heatmap", "--no-legend", "--size", "64x48",
                          "-o", str(tmp_path / "cli.png")], check=True, capture_output=True, text=True)
    accel = thicket.build(cornell)  # bvh8, the CLI's default too
    nodes = accel.render("heatmap", 64, 48)
    prims = accel.render("heatmap", 64, 48, counter="prims")
    thicket.save_png(tmp_path / "ours.png", thicket.heat_colours(nodes))
    assert (tmp_path / "ours.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    m = re.search(r"nodes visited per ray: ([\d.]+) average, (\d+) max; primitives tested per ray: ([\d.]+) average",
                  out.stdout)
    assert m, out.stdout
    assert f"{nodes.mean():.2f}" == m[1] and int(nodes.max()) == int(m[2]) and f"{prims.mean():.2f}" == m[3]


def test_render_arguments_are_checked(cornell):
    accel = thicket.build(cornell)
    with pytest.raises(ValueError, match="unknown view 'colour'"):
        accel.render("colour")
    with pytest.raises(ValueError, match="counter chooses what the heatmap view counts"):
        accel.render("depth", counter="nodes")
    with pytest.raises(ValueError, match="counter must be 'nodes'.*got 'leaves'"):
        accel.render("heatmap", counter="leaves")
    with pytest.raises(ValueError, match="height must be a pixel count from 1 to 32768, got 0"):
        accel.render("depth", 10, 0)
    with pytest.raises(ValueError, match="vfov_deg must be .* between 0 and 180"):
        accel.render("depth", 10, 10, eye=(0, 0, 5), center=(0, 0, 0), vfov_deg=180)
    with pytest.raises(ValueError, match="eye and center are the same point"):
        accel.render("depth", 10, 10, eye=(0, 0, 5), center=(0, 0, 5))
    with pytest.raises(TypeError, match="center must be three numbers"):
        accel.render("depth", 10, 10, eye=(0, 0, 5), center="origin")
    with pytest.raises(ValueError, match="counts: every count must be a finite number >= 0"):
        thicket.heat_colours([1.0, -2.0])
