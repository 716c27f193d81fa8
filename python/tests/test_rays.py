"""thicket.rays: the bench's ray sets are the very rays `thicket rays` writes, bit for bit, and
each set is what ray_sets.h says it is (camera origins, shadow rays ending at the light, ...)."""

import os
import subprocess

import numpy as np
import pytest

import thicket

CLI = os.environ.get("THICKET_CLI", "")
SETS = ["primary", "shadow", "diffuse", "random"]


@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
@pytest.mark.parametrize("camera", [None, (0.3, 1.2, 3.0, 0.0, 0.9, 0.0, 50.0)])
@pytest.mark.parametrize("name", SETS)
def test_the_sets_are_thicket_rays_output(tmp_path, cornell, name, camera):
    command = [CLI, "rays", "cornell", "--set", name, "--size", "48x32", "-o", str(tmp_path / "r.npy")]
    kwargs = {}
    if camera:
        command += ["--camera", ",".join(str(c) for c in camera)]
        kwargs = dict(eye=camera[0:3], center=camera[3:6], vfov_deg=camera[6])
    subprocess.run(command, check=True, capture_output=True)
    cli = np.load(tmp_path / "r.npy")
    ours = thicket.rays(cornell, name, width=48, height=32, **kwargs)
    assert len(cli) > 100
    assert ours["rays"].dtype == np.float32 and ours["rays"].shape == (len(cli), 6)
    # Bit for bit, every column: origin, direction, tmin, tmax.
    assert np.array_equal(ours["rays"], cli[:, :6])
    assert np.array_equal(ours["tmin"], cli[:, 6]) and np.array_equal(ours["tmax"], cli[:, 7])
    assert ours["any_hit"] == (name == "shadow")


def test_primary_rays_leave_the_camera_row_by_row(cornell):
    eye, center = (0.0, 1.0, 3.5), (0.0, 1.0, 0.0)
    s = thicket.rays(cornell, "primary", width=9, height=5, eye=eye, center=center, vfov_deg=40.0)
    rays = s["rays"]
    assert rays.shape == (45, 6) and np.array_equal(s["pixel"], np.arange(45))
    assert np.allclose(rays[:, :3], eye)
    assert np.allclose(np.linalg.norm(rays[:, 3:], axis=1), 1.0, atol=1e-6)
    d = rays[:, 3:].reshape(5, 9, 3)
    # The middle pixel looks at the centre; the first row is the top (y falls down the rows) and
    # x grows along a row (the camera looks down -z, so the image's right is +x).
    assert np.allclose(d[2, 4], (0, 0, -1), atol=1e-6)
    assert (np.diff(d[:, 4, 1]) < 0).all() and (np.diff(d[2, :, 0]) > 0).all()
    # The top row's centre ray is 40 * (4/5) / 2 degrees above the axis (pixel centre 0.5 of 5).
    half = np.radians(20.0)
    assert np.isclose(d[0, 4, 1] / -d[0, 4, 2], np.tan(half) * (1 - 1 / 5), rtol=1e-5)
    assert np.isinf(s["tmax"]).all() and (s["tmin"] == 0).all()
    assert s["eye"] == pytest.approx(eye) and s["center"] == pytest.approx(center) and s["vfov_deg"] == 40.0


def test_shadow_rays_stop_just_short_of_the_light(cornell):
    s = thicket.rays(cornell, "shadow", width=32, height=24)
    rays, light = s["rays"], np.array(s["light"])
    assert s["any_hit"] and len(rays) > 100
    end = rays[:, :3] + rays[:, 3:] * s["tmax"][:, None]
    gap = np.linalg.norm(light - end, axis=1)
    reach = np.linalg.norm(light - rays[:, :3], axis=1)
    assert np.allclose(gap, reach * 1e-4, rtol=1e-2, atol=1e-6)
    # Every shadow ray starts at a primary hit: on the primary ray of its pixel.
    primary = thicket.rays(cornell, "primary", width=32, height=24)["rays"]
    p = primary[s["pixel"]]
    hits = thicket.build(cornell).cast_rays(p)
    on_surface = p[:, :3] + p[:, 3:] * hits["t_hit"][:, None]
    assert np.allclose(rays[:, :3], on_surface, atol=1e-3)


def test_diffuse_and_random_sets(cornell):
    d = thicket.rays(cornell, "diffuse", width=32, height=24)
    assert not d["any_hit"] and np.isinf(d["tmax"]).all()
    assert np.allclose(np.linalg.norm(d["rays"][:, 3:], axis=1), 1.0, atol=1e-5)
    r = thicket.rays(cornell, "random", width=32, height=24)
    assert len(r["rays"]) == 32 * 24 and "pixel" not in r
    lo, hi = (np.array(b, np.float32) for b in cornell.bounds)
    assert ((r["rays"][:, :3] >= lo) & (r["rays"][:, :3] <= hi)).all()
    # Uniform on the sphere: no direction preferred (the mean of 768 unit vectors is near 0).
    assert np.linalg.norm(r["rays"][:, 3:].mean(axis=0)) < 0.15
    # Fixed seeds: the same arguments give the same rays.
    assert np.array_equal(r["rays"], thicket.rays(cornell, "random", width=32, height=24)["rays"])


def test_bad_arguments_are_named(cornell):
    with pytest.raises(ValueError, match="unknown ray set 'sideways'.*primary"):
        thicket.rays(cornell, "sideways")
    with pytest.raises(ValueError, match="set takes one set name"):
        thicket.rays(cornell, "primary,shadow")
    with pytest.raises(ValueError, match="width must be a pixel count from 1 to 16384, got 0"):
        thicket.rays(cornell, "primary", width=0)
    with pytest.raises(ValueError, match="eye and center go together"):
        thicket.rays(cornell, "primary", eye=(0, 0, 1))
    with pytest.raises(ValueError, match="vfov_deg shapes a camera given by eye and center"):
        thicket.rays(cornell, "primary", vfov_deg=30)
    with pytest.raises(ValueError, match="eye must be finite"):
        thicket.rays(cornell, "primary", eye=(0, float("nan"), 1), center=(0, 0, 0))
