"""thicket.path_trace by content: a Lambertian plane under a point light has radiance
albedo / pi * I * cos / r^2 pixel for pixel; a seed gives the same floats twice and `thicket render
--integrator path`'s picture; more samples converge."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import thicket

CLI = os.environ.get("THICKET_CLI", "")
ALBEDO = 0.8  # the renderer's default material (make_render_scene)


def plane(half=10.0):
    v = np.array([[-half, -half, 0], [half, -half, 0], [half, half, 0], [-half, half, 0]], np.float32)
    return thicket.Scene(v, np.array([[0, 1, 2], [0, 2, 3]]))


def test_a_lambertian_plane_under_a_point_light_matches_the_closed_form():
    scene = plane()
    light, intensity = np.array([1.0, 1.5, 3.0]), 20.0
    view = dict(width=24, height=16, eye=(0.0, 0.0, 6.0), center=(0.0, 0.0, 0.0), vfov_deg=50)
    image = thicket.path_trace(scene, spp=64, seed=3, lights=[(light, intensity)], **view)
    assert image.dtype == np.float32 and image.shape == (16, 24, 3)
    # The closed form at each pixel centre's hit point (the tracer jitters within the pixel, where
    # the radiance changes by a few percent at most): direct light only, since whatever leaves the
    # plane never comes back.
    rays = thicket.rays(scene, "primary", **view)["rays"]
    t = thicket.build(scene).cast_rays(rays)["t_hit"]
    assert np.isfinite(t).all()
    p = rays[:, :3] + rays[:, 3:] * t[:, None]
    to_light = light - p
    r = np.linalg.norm(to_light, axis=1)
    expected = (ALBEDO / np.pi * intensity * (to_light[:, 2] / r) / r**2).reshape(16, 24)
    for c in range(3):  # a white light on a grey surface: every channel alike
        assert np.allclose(image[..., c], expected, rtol=0.03)
    assert abs(image[..., 0].mean() / expected.mean() - 1) < 0.005
    # The brightest pixel is under the light: right of the middle and above it (row 0 is the top).
    row, col = np.unravel_index(np.argmax(image[..., 0]), (16, 24))
    assert col > 12 and row < 8


def test_a_light_of_colour_lights_each_channel_by_its_own_intensity():
    scene = plane()
    view = dict(width=8, height=6, eye=(0.0, 0.0, 6.0), center=(0.0, 0.0, 0.0))
    image = thicket.path_trace(scene, spp=4, lights=[((0, 0, 3), (10.0, 5.0, 0.0))], **view)
    assert np.allclose(image[..., 1], 0.5 * image[..., 0], rtol=1e-5) and (image[..., 2] == 0).all()


def test_the_same_seed_gives_the_same_floats_and_another_seed_others(cornell):
    view = dict(width=32, height=24, spp=2)
    a = thicket.path_trace(cornell, seed=11, **view)
    b = thicket.path_trace(thicket.build(cornell, "bvh"), seed=11, nthreads=1, **view)
    c = thicket.path_trace(cornell, seed=12, **view)
    assert a.mean() > 0.01
    assert np.array_equal(a, b)  # whatever the structure and the thread count
    assert not np.array_equal(a, c)


def test_more_samples_converge(cornell):
    view = dict(width=24, height=18)
    def spread(spp):
        x, y = (thicket.path_trace(cornell, spp=spp, seed=s, **view) for s in (1, 2))
        return float(np.sqrt(np.mean((x - y) ** 2)))
    few, many = spread(2), spread(32)
    # Monte Carlo noise falls as 1 / sqrt(spp): 16 times the samples, a quarter of the noise.
    assert many < 0.4 * few


@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
def test_the_picture_is_thicket_render_integrator_path(tmp_path):
    # A file scene (the CLI reads files) lit by the CLI's automatic light, seen from a given camera.
    obj = tmp_path / "scene.obj"
    obj.write_text("v -3 -1 -3\nv 3 -1 -3\nv 3 -1 3\nv -3 -1 3\nv 0 -1 0\nv 1 0.5 0\nv -1 0.5 0.5\nv 0 2 -1\n"
                   "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 6 8 7\n")
    args = dict(spp=4, seed=5, width=40, height=30, eye=(0.5, 1.5, 6.0), center=(0.0, 0.0, 0.0), vfov_deg=40)
    subprocess.run([CLI, "render", str(obj), "--integrator", "path", "--spp", "4", "--seed", "5", "--size", "40x30",
                    "--camera", "0.5,1.5,6,0,0,0,40", "-o", str(tmp_path / "cli.png")], check=True, capture_output=True)
    image = thicket.path_trace(thicket.load_scene(obj), **args)
    assert image.mean() > 0.01
    thicket.save_png(tmp_path / "ours.png", image)
    assert (tmp_path / "ours.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
@pytest.mark.parametrize("integrator", ["path", "whitted"])
def test_a_json_scene_brings_its_materials_lights_and_camera_as_in_the_cli(tmp_path, integrator):
    # Glass, chrome, copper, an emitting sphere and a point light, seen from the file's camera.
    json_scene = pathlib.Path(__file__).resolve().parents[2] / "examples" / "materials.json"
    subprocess.run([CLI, "render", str(json_scene), "--integrator", integrator, "--spp", "2", "--seed", "3",
                    "--size", "40x30", "-o", str(tmp_path / "cli.png")], check=True, capture_output=True)
    image = thicket.path_trace(thicket.load_scene(json_scene), spp=2, seed=3, width=40, height=30,
                               integrator=integrator)
    thicket.save_png(tmp_path / "ours.png", image)
    assert (tmp_path / "ours.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_path_trace_arguments_are_checked(cornell, tmp_path):
    with pytest.raises(TypeError, match="must be a thicket.Scene or a thicket.Accel, got NoneType"):
        thicket.path_trace(None)
    with pytest.raises(ValueError, match="spp must be a sample count from 1"):
        thicket.path_trace(cornell, spp=0)
    with pytest.raises(ValueError, match="seed must be an integer from 0 to 2\\^64 - 1"):
        thicket.path_trace(cornell, seed=-1)
    with pytest.raises(ValueError, match="unknown integrator 'photon'"):
        thicket.path_trace(cornell, integrator="photon")
    with pytest.raises(ValueError, match=r"lights\[0\] must be a \(position, intensity\) pair"):
        thicket.path_trace(cornell, lights=[(0, 1, 2)])
    with pytest.raises(ValueError, match=r"lights\[1\] intensity must be from 0 to 1e20"):
        thicket.path_trace(cornell, lights=[((0, 1, 2), 1.0), ((0, 1, 2), -1.0)])
    # save_png refuses to replace a file unless told, and names what it cannot write.
    thicket.save_png(tmp_path / "x.png", np.zeros((2, 3), np.uint8))
    with pytest.raises(FileExistsError):
        thicket.save_png(tmp_path / "x.png", np.zeros((2, 3), np.uint8))
    with pytest.raises(ValueError, match=r"image: expected uint8 \(H, W\) or \(H, W, 3\).*\(2, 3, 4\)"):
        thicket.save_png(tmp_path / "y.png", np.zeros((2, 3, 4), np.float32))
    with pytest.raises(ValueError, match="exposure scales float radiance"):
        thicket.save_png(tmp_path / "z.png", np.zeros((2, 3), np.uint8), exposure=2.0)


def test_save_png_writes_the_pixels_given(tmp_path):
    image = np.zeros((3, 5, 3), np.uint8)
    image[0, 4] = (255, 0, 0)
    thicket.save_png(tmp_path / "a.png", image)
    data = (tmp_path / "a.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    assert int.from_bytes(data[16:20], "big") == 5 and int.from_bytes(data[20:24], "big") == 3
    # Float radiance goes through the sRGB curve: 0.5 linear is 188 (0.5 ** (1 / 2.4) * 1.055 - 0.055).
    thicket.save_png(tmp_path / "b.png", np.full((3, 5, 3), 0.5, np.float32))
    thicket.save_png(tmp_path / "c.png", np.full((3, 5, 3), 188, np.uint8))
    assert (tmp_path / "b.png").read_bytes() == (tmp_path / "c.png").read_bytes()
    thicket.save_png(tmp_path / "d.png", np.full((3, 5, 3), 0.25, np.float32), exposure=2.0)
    assert (tmp_path / "d.png").read_bytes() == (tmp_path / "b.png").read_bytes()
