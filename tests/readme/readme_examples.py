#!/usr/bin/env python3
"""The README's examples, as users copy them: the fenced blocks marked `<!-- tested: NAME -->`.

  readme_examples.py extract README.md NAME OUT      write block NAME to OUT (the build does this)
  readme_examples.py run-cpp EXE                      run the compiled C++ example, check its answers
  readme_examples.py run-python README.md PYTHONPATH  run the Python example in a scratch directory

The examples trace the built-in Cornell box (floor y=0, back wall z=-1.04, right wall x=1), so
the answers are known: a ray from (0, 1.5, 3) along -z meets the back wall at t = 4.04 and
crosses nothing else; the point (0.9, 1, 0.5) is 0.1 from the right wall.
"""
import os
import re
import subprocess
import sys
import tempfile

BACK_WALL_T = 4.04
RIGHT_WALL_DISTANCE = 0.1


def block(readme, name):
    """The text of the fenced block after `<!-- tested: name`; exits naming README and name if absent."""
    lines = open(readme, encoding="utf-8").read().split("\n")
    marker = "<!-- tested: " + name
    for i, line in enumerate(lines):
        if line.startswith(marker):
            if i + 1 >= len(lines) or not lines[i + 1].startswith("```"):
                sys.exit(f"{readme}:{i + 1}: the marker for {name} is not followed by a fenced block")
            end = next((j for j in range(i + 2, len(lines)) if lines[j].startswith("```")), None)
            if end is None:
                sys.exit(f"{readme}:{i + 2}: the block {name} is never closed")
            return "\n".join(lines[i + 2:end]) + "\n"
    sys.exit(f"{readme}: no block marked '{marker} -->'")


def numbers(output, key):
    """Every float printed as `key=VALUE` or `key VALUE` in output."""
    return [float(v) for v in re.findall(re.escape(key) + r"[= ]([-+0-9.eE]+|inf|nan)", output)]


def expect(output, key, want, count=None):
    got = numbers(output, key)
    if not got or (count is not None and len(got) != count):
        sys.exit(f"expected {count or 'some'} '{key}' value(s) in the example's output, got {got}:\n{output}")
    for v in got:
        if abs(v - want) > 1e-4:
            sys.exit(f"'{key}' is {v}, expected {want}:\n{output}")


def run(cmd, cwd=None, env=None):
    done = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} exited with {done.returncode}:\n{done.stdout}{done.stderr}")
    print(done.stdout, end="")
    return done.stdout


def main(argv):
    if len(argv) == 5 and argv[1] == "extract":
        text = block(argv[2], argv[3])
        # Rewritten only when it changed, so that the build does not recompile an unchanged example.
        if not os.path.exists(argv[4]) or open(argv[4], encoding="utf-8").read() != text:
            os.makedirs(os.path.dirname(os.path.abspath(argv[4])), exist_ok=True)
            open(argv[4], "w", encoding="utf-8").write(text)
        return
    if len(argv) == 3 and argv[1] == "run-cpp":
        with tempfile.TemporaryDirectory() as work:
            out = run([argv[2]], cwd=work)
        expect(out, "hit t", BACK_WALL_T, 1)
        expect(out, "batch t", BACK_WALL_T, 1)
        expect(out, "rows t", BACK_WALL_T, 1)
        expect(out, "occluded", 1, 1)
        expect(out, "crossings", 1, 1)
        expect(out, "closest", RIGHT_WALL_DISTANCE, 2)
        return
    if len(argv) == 4 and argv[1] == "run-python":
        with tempfile.TemporaryDirectory() as work:
            script = os.path.join(work, "readme_example.py")
            open(script, "w", encoding="utf-8").write(block(argv[2], "readme_example.py"))
            env = dict(os.environ, PYTHONPATH=os.path.abspath(argv[3]), PYTHONDONTWRITEBYTECODE="1")
            out = run([sys.executable, script], cwd=work, env=env)
        if "bvh8:" not in out:
            sys.exit(f"the example's loaded structure did not print its bvh8 spec:\n{out}")
        expect(out, "t_hit", BACK_WALL_T, 1)
        expect(out, "distance", RIGHT_WALL_DISTANCE, 1)
        # RaycastingScene: the triangle added second (geometry 1, its triangle 0) at z = 2, then 1,
        # in front of the back wall.
        expect(out, "geometry", 1, 1)
        expect(out, "triangle", 0, 1)
        expect(out, "own t", 1.0, 1)
        expect(out, "moved t", 2.0, 1)
        return
    sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
