"""The suite's skip refusal (conftest.py): with THICKET_REFUSE_SKIPS=1 a skipped test fails and
names its reason; without it, it is a skip."""

import os
import pathlib
import subprocess
import sys

import thicket

HERE = pathlib.Path(__file__).parent


def run(refuse):
    # The child imports the same package (conftest.py does), wherever the parent found it.
    package_dir = str(pathlib.Path(thicket.__file__).resolve().parents[1])
    env = dict(os.environ, THICKET_REFUSE_SKIPS="1" if refuse else "0", PYTHONPATH=package_dir)
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(HERE / "skip_fixture.py")],
                          cwd=HERE, env=env, capture_output=True, text=True)


def test_a_skip_fails_when_skips_are_refused():
    refused = run(True)
    assert refused.returncode == 1, refused.stdout
    assert "a planted skip" in refused.stdout and "refuses skips" in refused.stdout
    allowed = run(False)
    assert allowed.returncode == 0, allowed.stdout
    assert "1 skipped" in allowed.stdout
