"""Figures for BENCHMARKS.md: the module against the C++ batch API, and against Open3D's
RaycastingScene on the same rays and points. Prints Markdown.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/module_bench.py SCENE.ply RAYS.npy [--reps N]

RAYS.npy: (N, 8) float32 rays, e.g. `thicket rays SCENE --set primary --size 1000x1000 -o RAYS.npy`.
The C++ figures time the batch call alone over the same rays or points (Accel::intersect /
occluded / count_hits / closest_points, the rows already converted, the answers' vector already
touched): in this process on the module's own structure (thicket._thicket._batch_seconds), and
`thicket trace`'s (or `thicket closest`'s) own timing in a fresh process (one cold batch after
loading and building); the module's is the Python call end to end (checks, conversion, tracing,
output arrays). They take turns, as do Open3D and thicket, so that all see the same load; the
median over the passes of module / in-process batch call, each pair a moment apart, moves less
between runs than the ratio of the two best times.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import thicket
from thicket import _thicket  # type: ignore[attr-defined]  # private: not in the stub


def timed(f):
    """Seconds one call of f takes, and its result."""
    start = time.perf_counter()
    result = f()
    return time.perf_counter() - start, result


def best_of_pair(reps, f, g):
    """f and g, each returning (seconds, result), run in turns, `reps` times each: the fastest time
    of each (the least disturbed by other work on a shared machine; taking turns exposes both to
    the same load) and their last results."""
    bf = bg = float("inf")
    rf = rg = None
    for _ in range(reps):
        t, rf = f()
        bf = min(bf, t)
        t, rg = g()
        bg = min(bg, t)
    return bf, rf, bg, rg


def duration(text, pattern):
    """The duration `thicket` printed after `pattern` ("in 1.23 s", "in 456 ms"), in seconds."""
    m = re.search(pattern + r" in ([0-9.]+) (ms|s)\b", text)
    return float(m.group(1)) / (1000 if m.group(2) == "ms" else 1)


def cli_seconds(cli, args, pattern):
    """`thicket`'s own timing of its batch call (the rows already converted to rays)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run([cli] + args + ["-o", os.path.join(tmp, "h.npy")], check=True, capture_output=True,
                             text=True).stdout
    return duration(out, pattern)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("rays")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--cli", default="build/thicket")
    ap.add_argument("--points", type=int, default=100_000)
    args = ap.parse_args()

    rays = np.load(args.rays).astype(np.float32)
    scene = thicket.load_scene(args.scene)
    accel = thicket.build(scene, "bvh8")
    n = len(rays)
    rng = np.random.default_rng(1)
    lo, hi = (np.array(b) for b in scene.bounds)
    pts = (lo + rng.random((args.points, 3)) * (hi - lo)).astype(np.float32)
    print(f"scene {args.scene}: {scene.primitive_count} triangles; {n} rays, {len(pts)} points in the scene's box; "
          f"best of {args.reps}, taking turns; load {os.getloadavg()[0]:.2f}\n")

    print("| query | C++ batch API, in process | module | overhead | overhead, median of pairs | "
          "C++ batch API, `thicket` | overhead |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        pts_path = os.path.join(tmp, "points.npy")
        np.save(pts_path, pts)
        trace = ["trace", args.scene, "--rays", args.rays, "--accel", "bvh8"]
        for name, cli_args, pattern, query, data, kind in (
                ("closest hit", trace, "rays", accel.cast_rays, rays, "closest"),
                ("any hit", trace + ["--any-hit"], "rays", accel.test_occlusions, rays, "any"),
                ("count", trace + ["--count"], "rays", accel.count_intersections, rays, "count"),
                ("closest point", ["closest", args.scene, "--points", pts_path, "--accel", "bvh8"], "points",
                 accel.compute_closest_points, pts, "closest_point")):
            inproc = module = cli = float("inf")
            ratios = []
            for _ in range(args.reps):  # in turns, so that all three see the same load
                pair = _thicket._batch_seconds(accel, data, kind), timed(lambda: query(data))[0]
                inproc, module = min(inproc, pair[0]), min(module, pair[1])
                ratios.append(pair[1] / pair[0])  # two calls a moment apart: the steadier figure
                cli = min(cli, cli_seconds(args.cli, cli_args, pattern))
            count = len(data)
            print(f"| {name} | {inproc * 1e3:.0f} ms ({count / inproc / 1e6:.2f} M/s) | {module * 1e3:.0f} ms "
                  f"({count / module / 1e6:.2f} M/s) | {100 * (module / inproc - 1):+.1f}% | "
                  f"{100 * (statistics.median(ratios) - 1):+.1f}% | {cli * 1e3:.0f} ms | {100 * (module / cli - 1):+.1f}% |")
    print(f"\n(load {os.getloadavg()[0]:.2f} after the table)")

    try:
        import open3d as o3d
    except ImportError:
        print("\nOpen3D is not installed: no comparison")
        return
    o3 = o3d.t.geometry.RaycastingScene()
    o3.add_triangles(o3d.core.Tensor(scene.vertices), o3d.core.Tensor(scene.triangles))
    six = np.ascontiguousarray(rays[:, :6])
    pts_t = o3d.core.Tensor(pts)
    six_t = o3d.core.Tensor(six)
    print(f"\nOpen3D {o3d.__version__} RaycastingScene against thicket (bvh8, closest points by its own point "
          f"traversal), {n} rays, {len(pts)} points in the scene's box, load {os.getloadavg()[0]:.2f}:\n")
    print("| query | Open3D | thicket | speed-up | agreement |")
    print("|---|---|---|---|---|")
    rows = [
        ("cast_rays", lambda: o3.cast_rays(six_t)["t_hit"].numpy(), lambda: accel.cast_rays(six)["t_hit"]),
        ("test_occlusions", lambda: o3.test_occlusions(six_t).numpy(), lambda: accel.test_occlusions(six)),
        ("count_intersections", lambda: o3.count_intersections(six_t).numpy(),
         lambda: accel.count_intersections(six)),
        ("compute_closest_points", lambda: o3.compute_closest_points(pts_t)["points"].numpy(),
         lambda: accel.compute_closest_points(pts)["points"]),
        ("compute_distance", lambda: o3.compute_distance(pts_t).numpy(), lambda: accel.compute_distance(pts)),
    ]
    for name, theirs, ours in rows:
        to, a, tt, b = best_of_pair(args.reps, lambda: timed(theirs), lambda: timed(ours))
        if a.dtype == np.bool_ or a.dtype.kind in "iu":
            agree = f"{np.mean(a == b) * 100:.2f}% equal"
        else:
            close = np.isclose(a, b, rtol=1e-4, atol=1e-5 * float(np.abs(hi - lo).max()))
            agree = f"{np.mean(close) * 100:.2f}% within 1e-4"
        extra = ""
        if name in ("cast_rays", "test_occlusions", "count_intersections"):
            hits = np.isfinite(a).mean() if a.dtype.kind == "f" else (a != 0).mean()
            mine = np.isfinite(b).mean() if b.dtype.kind == "f" else (b != 0).mean()
            extra = f" (hits: Open3D {hits * 100:.1f}%, thicket {mine * 100:.1f}%)"
        print(f"| {name} | {to * 1e3:.0f} ms | {tt * 1e3:.0f} ms | {to / tt:.2f}x | {agree}{extra} |")
    print(f"\n(load {os.getloadavg()[0]:.2f} after the table)")


if __name__ == "__main__":
    sys.exit(main())
