"""The Python examples of examples/, run as a user runs them, their outputs checked by content."""

import os
import pathlib
import subprocess
import sys

import numpy as np

import thicket

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def test_pinhole_depth(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(thicket.__file__).parents[1]))
    out = subprocess.run([sys.executable, str(EXAMPLES / "pinhole_depth.py"), "cornell", str(tmp_path / "d")],
                         env=env, capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    depth = np.load(tmp_path / "d.npy")
    assert depth.shape == (120, 160) and depth.dtype == np.float32
    # The Cornell box is open towards the camera and framed inside the picture: the middle sees its
    # back wall (farther than its front edge seen at the border), the corners see nothing.
    assert np.isfinite(depth[60, 80]) and not np.isfinite(depth[0, 0]) and not np.isfinite(depth[-1, -1])
    assert 0.5 < np.isfinite(depth).mean() < 1.0
    pgm = (tmp_path / "d.pgm").read_bytes()
    header = b"P5 160 120 255\n"
    assert pgm.startswith(header) and len(pgm) == len(header) + 160 * 120
    image = np.frombuffer(pgm[len(header):], np.uint8).reshape(120, 160)
    assert image[0, 0] == 0 and image[60, 80] > 0
    assert "pixels hit" in out.stdout


def test_pictures(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(thicket.__file__).parents[1]))
    out = subprocess.run([sys.executable, str(EXAMPLES / "pictures.py"), "cornell", str(tmp_path / "p"), "4"],
                         env=env, capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    p = tmp_path / "p"
    for name in ("depth", "normal", "heatmap", "path"):
        png = (p / f"{name}.png").read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and int.from_bytes(png[16:20], "big") == 160
    # The saved numbers are the module's answers for the same arguments.
    cornell = thicket.load_scene("cornell")
    accel = thicket.build(cornell, "bvh8")
    depth = np.load(p / "depth.npy")
    assert np.array_equal(depth, accel.render("depth", 160, 120)) and 0.3 < np.isfinite(depth).mean() < 1
    normal = np.load(p / "normal.npy")
    assert np.allclose(np.linalg.norm(normal[np.isfinite(depth)], axis=-1), 1, atol=1e-5)
    nodes = np.load(p / "nodes.npy")
    assert nodes.dtype == np.uint32 and nodes.max() > 1
    thicket.save_png(tmp_path / "heat.png", thicket.heat_colours(nodes))
    assert (tmp_path / "heat.png").read_bytes() == (p / "heatmap.png").read_bytes()
    radiance = np.load(p / "radiance.npy")
    assert np.array_equal(radiance, thicket.path_trace(cornell, spp=4, width=160, height=120, seed=1))
    assert radiance.mean() > 0.01
    assert "of pixels hit" in out.stdout and "at 4 spp" in out.stdout
