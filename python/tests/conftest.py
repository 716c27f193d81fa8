"""Shared fixtures: small scenes with answers known by hand, and reproducible random rays."""

import os
import pathlib

import numpy as np
import pytest

import thicket

SHARED_SCENES = pathlib.Path(os.environ.get("THICKET_SHARED_SCENES", pathlib.Path(__file__).parents[2] / "../shared/scenes"))


def cube_arrays():
    """The unit cube [0,1]^3 as 8 vertices and 12 outward-wound triangles (2 per face)."""
    v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    # vertex index = 4x + 2y + z
    quads = [(0, 1, 3, 2), (4, 6, 7, 5),   # x = 0 (normal -x), x = 1 (+x)
             (0, 4, 5, 1), (2, 3, 7, 6),   # y = 0, y = 1
             (0, 2, 6, 4), (1, 5, 7, 3)]   # z = 0, z = 1
    t = []
    for a, b, c, d in quads:
        t += [(a, b, c), (a, c, d)]
    return v, np.array(t, np.int32)


@pytest.fixture(scope="session")
def cube():
    return thicket.Scene(*cube_arrays())


@pytest.fixture(scope="session")
def cornell():
    return thicket.load_scene("cornell")


def random_rays(scene, n, seed=1, width=8):
    """Rays from random points around the scene's bounds towards random points inside them, so that
    most hit; columns 6 and 7 are [0, inf) when width is 8."""
    rng = np.random.default_rng(seed)
    lo, hi = (np.array(b, np.float64) for b in scene.bounds)
    size = hi - lo
    org = lo - 0.5 * size + rng.random((n, 3)) * 2 * size
    target = lo + rng.random((n, 3)) * size
    rays = np.zeros((n, width), np.float32)
    rays[:, 0:3] = org
    rays[:, 3:6] = target - org
    if width == 8:
        rays[:, 7] = np.inf
    return rays


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """THICKET_REFUSE_SKIPS=1 (CI, as for the ctest entries: scripts/ctest-checked) turns a skip
    into a failure that says why it skipped: a missing ../shared or an unset THICKET_CLI must not
    pass as green."""
    outcome = yield
    report = outcome.get_result()
    if report.skipped and os.environ.get("THICKET_REFUSE_SKIPS") == "1" and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        report.outcome = "failed"
        report.longrepr = f"skipped ({reason}), and this run refuses skips (THICKET_REFUSE_SKIPS=1)"
