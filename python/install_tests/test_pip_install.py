"""`pip install .` and `pip install -e .` as the README says, offline, into fresh venvs made with
--system-site-packages (Debian's numpy, CMake and pybind11 serve the build), then the module used
from outside the source tree. Slow when the compiler cache is cold (the library is compiled once
more); the ctest entry python.pip_install points the CMake tree and launcher so that it is warm."""

import os
import pathlib
import subprocess
import sys
import textwrap

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]

# Run by the venv's python from a directory outside the source: the installed package, not
# python/thicket, must answer; prints where it came from.
USE = textwrap.dedent("""
    import pathlib, numpy as np, thicket
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    accel = thicket.build(thicket.Scene(v, np.array([[0, 1, 2]], np.int32)), "bvh")
    hits = accel.cast_rays(np.array([[0.25, 0.25, 2, 0, 0, -1]], np.float32))
    assert hits["t_hit"][0] == 2.0 and hits["primitive_ids"][0] == 0, hits
    rays = thicket.create_rays_pinhole(40.0, [0.25, 0.25, 0], [0.25, 0.25, 2], [0, 1, 0], 3, 3)
    assert abs(accel.cast_rays(rays)["t_hit"][1, 1] - 2.0) < 1e-6
    # The pictures link the renderer and the bench's ray sets in too.
    view = dict(eye=(0.25, 0.25, 2), center=(0.25, 0.25, 0))
    assert accel.render("depth", 3, 3, **view)[1, 1] == 2.0 and thicket.rays(accel.scene, "primary", 3, 3, **view)["rays"].shape == (9, 6)
    assert thicket.path_trace(accel, spp=1, width=3, height=3, **view).shape == (3, 3, 3)
    package = pathlib.Path(thicket.__file__).parent
    for f in ("py.typed", "__init__.pyi"):
        assert (package / f).is_file(), f + " was not installed"
    print(package)
""")


def run(cmd, env, cwd):
    """cmd's output; a failure shows all of it (the build's errors)."""
    p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert p.returncode == 0, f"{' '.join(map(str, cmd))} exited {p.returncode}:\n{p.stdout[-20000:]}"
    return p.stdout


@pytest.fixture
def venv(tmp_path):
    """A fresh venv seeing Debian's packages, and the environment pip builds in: setuptools'
    build and egg-info folders in tmp_path (nothing written to the source tree), the CMake tree and
    compiler launcher and unity directory the ctest entry names, no index (offline)."""
    run([sys.executable, "-m", "venv", "--system-site-packages", tmp_path / "V"], dict(os.environ), tmp_path)
    cfg = tmp_path / "setup.cfg"
    cfg.write_text(f"[build]\nbuild_base = {tmp_path / 'build'}\n[egg_info]\negg_base = {tmp_path}\n")
    env = dict(os.environ, DIST_EXTRA_CONFIG=str(cfg), PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    if os.environ.get("THICKET_PIP_CMAKE_DIR"):
        env["THICKET_CMAKE_BUILD_DIR"] = os.environ["THICKET_PIP_CMAKE_DIR"]
    if os.environ.get("THICKET_PIP_LAUNCHER"):
        env["CMAKE_CXX_COMPILER_LAUNCHER"] = os.environ["THICKET_PIP_LAUNCHER"]
    if os.environ.get("THICKET_PIP_UNITY_DIR"):  # the ctest tree's units: same paths, ccache hits
        env["CMAKE_ARGS"] = (env.get("CMAKE_ARGS", "") + f" -DTHICKET_UNITY_DIR={os.environ['THICKET_PIP_UNITY_DIR']}").strip()
    env.setdefault("CMAKE_BUILD_PARALLEL_LEVEL", "2")
    return tmp_path / "V" / "bin", env, tmp_path


def test_pip_install(venv):
    bin_dir, env, tmp = venv
    run([bin_dir / "pip", "install", "--no-build-isolation", str(SOURCE)], env, tmp)
    where = pathlib.Path(run([bin_dir / "python", "-c", USE], env, tmp).strip().splitlines()[-1])
    assert where == pathlib.Path(run([bin_dir / "python", "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                                     env, tmp).strip()) / "thicket"
    assert not list((SOURCE / "python").glob("*.egg-info")), "the build wrote egg-info into the source tree"


def test_pip_install_editable(venv):
    bin_dir, env, tmp = venv
    package = SOURCE / "python" / "thicket"
    # A module left there by the developer's own editable install is set aside and put back.
    kept = {f: tmp / f.name for f in package.glob("_thicket*.so")}
    for f, aside in kept.items():
        f.rename(aside)
    try:
        run([bin_dir / "pip", "install", "--no-build-isolation", "-e", str(SOURCE)], env, tmp)
        # Editable: the package is the source folder itself (its module built in place).
        where = pathlib.Path(run([bin_dir / "python", "-c", USE], env, tmp).strip().splitlines()[-1])
        assert where == package
    finally:
        for f in package.glob("_thicket*.so"):
            f.unlink()
        for f, aside in kept.items():
            aside.rename(f)


def test_the_package_version_is_the_projects():
    import re
    import tomllib

    project = tomllib.loads((SOURCE / "pyproject.toml").read_text())["project"]
    cmake = re.search(r"project\(thicket VERSION ([0-9.]+)", (SOURCE / "CMakeLists.txt").read_text())
    assert cmake and project["version"] == cmake.group(1), (project["version"], cmake and cmake.group(1))
