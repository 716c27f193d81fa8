"""The compiled half of `pip install .`: CMake builds the `thicket_python` target of this tree and
the module it writes is copied where setuptools expects the extension thicket._thicket.

Environment: CMAKE_ARGS (extra configure arguments, split as a shell would), CMAKE_BUILD_PARALLEL_LEVEL
(build jobs; one per core otherwise), CMAKE_CXX_COMPILER_LAUNCHER (e.g. ccache) and CMAKE_GENERATOR
are read by CMake itself; THICKET_CMAKE_BUILD_DIR names the CMake build tree to configure and build
(kept across installs; a fresh one under setuptools' build_temp otherwise)."""

import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    """An extension whose sources CMake knows: setuptools only names it."""

    def __init__(self, name, target):
        super().__init__(name, sources=[])
        self.target = target


class CMakeBuild(build_ext):
    """Configures a build tree of its own (Release; no tests, no CLI) and builds one target."""

    def run(self):
        if shutil.which("cmake") is None:
            raise RuntimeError("building thicket needs cmake on PATH (Debian: apt-get install cmake)")
        super().run()

    def build_extension(self, ext):
        build_dir = pathlib.Path(os.environ.get("THICKET_CMAKE_BUILD_DIR") or pathlib.Path(self.build_temp) / "cmake").resolve()
        build_dir.mkdir(parents=True, exist_ok=True)
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DTHICKET_BUILD_TESTS=OFF", "-DTHICKET_BUILD_TOOLS=OFF",
            "-DTHICKET_BUILD_PYTHON=ON", "-DTHICKET_REQUIRE_PYTHON=ON",
            # The interpreter pip runs: the module's ABI suffix and headers are its own.
            f"-DPython3_EXECUTABLE={sys.executable}",
        ] + shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        build = ["cmake", "--build", str(build_dir), "--target", ext.target]
        if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
            build += ["-j", str(self.parallel if isinstance(self.parallel, int) and self.parallel > 0 else os.cpu_count() or 1)]
        subprocess.run(build, check=True)
        built = sorted((build_dir / "python" / "thicket").glob("_thicket*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one _thicket*.so in {build_dir / 'python' / 'thicket'}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(ext_modules=[CMakeExtension("thicket._thicket", "thicket_python")], cmdclass={"build_ext": CMakeBuild})
