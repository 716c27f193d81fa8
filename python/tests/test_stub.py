"""The type stub (thicket/__init__.pyi) and the module agree name for name; every public function,
class, method and property has a docstring; mypy passes on the code that uses the module."""

import ast
import inspect
import os
import pathlib
import subprocess
import sys

import pytest

import thicket

PACKAGE = pathlib.Path(thicket.__file__).parent
ROOT = pathlib.Path(__file__).resolve().parents[2]


def stub_tree():
    return ast.parse((PACKAGE / "__init__.pyi").read_text())


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_names(body):
    """Public names a stub body defines: functions, classes, annotated or assigned names."""
    out = set()
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out.add(node.target.id)
        elif isinstance(node, ast.Assign):
            out |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return public(out)


def module_names():
    """The package's public names, less its submodules (thicket.dask is imported on demand)."""
    return {n for n in public(dir(thicket)) if not inspect.ismodule(getattr(thicket, n))}


def test_the_stub_and_the_module_have_the_same_names():
    in_stub = stub_names(stub_tree().body) - {"__all__"}
    missing, extra = module_names() - in_stub, in_stub - module_names()
    assert not missing, f"in the module but not in thicket/__init__.pyi: {sorted(missing)}"
    assert not extra, f"in thicket/__init__.pyi but not in the module: {sorted(extra)}"
    assert set(thicket.__all__) == module_names()


@pytest.mark.parametrize("cls", ["Scene", "Accel", "RaycastingScene"])
def test_the_stub_and_the_classes_have_the_same_members(cls):
    node = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == cls)
    in_stub = stub_names(node.body) | ({"__init__"} & {n.name for n in node.body if isinstance(n, ast.FunctionDef)})
    in_module = public(vars(getattr(thicket, cls))) | ({"__init__"} if cls in ("Scene", "RaycastingScene") else set())
    assert in_module - in_stub == set(), f"{cls} members missing from the stub"
    assert in_stub - in_module == set(), f"{cls} members in the stub but not in the module"


def documented_objects():
    for name in sorted(module_names()):
        obj = getattr(thicket, name)
        if callable(obj):
            yield name, obj
        if inspect.isclass(obj):
            for member, value in vars(obj).items():
                if not member.startswith("_") or member == "__init__":
                    yield f"{name}.{member}", value


def test_everything_public_has_a_docstring_with_its_shapes_or_types():
    undocumented = [name for name, obj in documented_objects() if len((inspect.getdoc(obj) or "").strip()) < 20]
    assert not undocumented, f"no usable docstring: {undocumented}"
    # Array arguments and answers name their shape and dtype.
    for name in ("Accel.cast_rays", "Accel.compute_distance", "Scene.__init__", "create_rays_pinhole"):
        obj = dict(documented_objects())[name]
        doc = inspect.getdoc(obj)
        assert "(" in doc and ("float32" in doc or "float" in doc), f"{name}: {doc}"


def test_compiled_functions_state_their_signature():
    # pybind11's own signatures are off (they would call the checked arguments "handle"): each
    # compiled function's docstring must begin with its own, as Python's help shows for .py ones.
    for name, obj in documented_objects():
        if inspect.isbuiltin(obj) or type(obj).__name__ == "instancemethod":
            short = name.split(".")[-1] if not name.endswith("__init__") else name.split(".")[0]
            assert inspect.getdoc(obj).startswith(short + "("), f"{name}: {inspect.getdoc(obj)[:60]}"


def test_help_is_a_usable_page():
    page = subprocess.run([sys.executable, "-c", "import thicket; help(thicket)"], capture_output=True, text=True,
                          env=dict(os.environ, PAGER="cat", TERM="dumb"), check=True).stdout
    for name in sorted(module_names() - {"INVALID_ID"}):
        assert name in page, name


@pytest.fixture(scope="module")
def mypy_cache(tmp_path_factory):
    """One cache for this file's mypy runs: numpy's stubs are analysed once, not per run."""
    return tmp_path_factory.mktemp("mypy_cache")


def mypy(cache, *args):
    """mypy with the package the tests import (PYTHONPATH's thicket and its stub) and pyproject.toml's
    settings (Open3D and Dask have no types); python3-mypy is installed by scripts/setup: a missing
    mypy is a failure here, not a skip."""
    env = dict(os.environ, MYPYPATH=str(PACKAGE.parent))
    return subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
                           "--cache-dir", str(cache), *map(str, args)],
                          capture_output=True, text=True, env=env, cwd=ROOT)


def test_mypy_passes_on_the_code_that_uses_the_module(mypy_cache):
    # Typed code over the whole API and the examples: --strict (every call and answer checked).
    p = mypy(mypy_cache, "--strict", ROOT / "python" / "tests" / "mypy_usage.py", *sorted((ROOT / "examples").glob("*.py")))
    assert p.returncode == 0, f"mypy --strict:\n{p.stdout}{p.stderr}"
    # The tests and the bench, mostly untyped: mypy's defaults (their calls to typed code checked;
    # test_inputs passes wrong types on purpose inside untyped functions, which is not).
    p = mypy(mypy_cache, *sorted((ROOT / "python" / "tests").glob("*.py")), *sorted((ROOT / "python" / "bench").glob("*.py")),
             *sorted((ROOT / "python" / "install_tests").glob("*.py")))
    assert p.returncode == 0, f"mypy:\n{p.stdout}{p.stderr}"


def test_mypy_catches_a_misuse(mypy_cache):
    # The check above could pass by seeing nothing (Any everywhere): a wrong call must fail it.
    bad = "import thicket\nrays = thicket.create_rays_pinhole(60.0, [0, 0, 0], [0, 0, 1], [0, 1, 0], 4)\n" \
          "hits = thicket.build(thicket.load_scene('cornell')).cast_rays(rays)\nx: str = hits['t_hit']\n"
    p = mypy(mypy_cache, "-c", bad)
    assert p.returncode == 1, p.stdout + p.stderr
    assert "No overload variant" in p.stdout and "incompatible types in assignment" in p.stdout.lower(), p.stdout


def test_the_typed_usage_runs(tmp_path):
    # What mypy checked is also what the module answers (a stub can lie; running it cannot).
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    try:
        import mypy_usage
    finally:
        sys.path.pop(0)
    assert mypy_usage.use_everything(str(tmp_path)) == pytest.approx(2.0 + 1.0)
