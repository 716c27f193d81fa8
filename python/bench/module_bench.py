"""Figures for BENCHMARKS.md: the module against the C++ batch API, and against Open3D's
RaycastingScene on the same rays and points. Prints Markdown.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/module_bench.py SCENE.ply RAYS.npy [--reps N]

RAYS.npy: (N, 8) float32 rays, e.g. `thicket rays SCENE --set primary --size 1000x1000 -o RAYS.npy`.
The C++ figure is `thicket trace`'s own timing of Accel::intersect over the same rays (the batch
call alone); the module's is cast_rays end to end (checks, conversion, tracing, output arrays).
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

import thicket


def best_of(reps, f):
    """The fastest of `reps` runs, in seconds (the least disturbed by other work), and the result."""
    best, result = float("inf"), None
    for _ in range(reps):
        start = time.perf_counter()
        result = f()
        best = min(best, time.perf_counter() - start)
    return best, result


def cli_seconds(cli, scene, rays_path, spec, extra, reps):
    """`thicket trace`'s own timing of the batch call ("in 1.23 s"), best of `reps`."""
    best = float("inf")
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(reps):
            out = subprocess.run([cli, "trace", scene, "--rays", rays_path, "-o", os.path.join(tmp, "h.npy"),
                                  "--accel", spec] + extra, check=True, capture_output=True, text=True).stdout
            m = re.search(r"rays in ([0-9.]+) (ms|s)", out)
            best = min(best, float(m.group(1)) / (1000 if m.group(2) == "ms" else 1))
    return best


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
    print(f"scene {args.scene}: {scene.primitive_count} triangles; {n} rays; best of {args.reps}; "
          f"load {os.getloadavg()[0]:.2f}\n")

    print("| query | C++ batch API (`thicket trace`) | module | overhead |")
    print("|---|---|---|---|")
    for name, extra, query in (("closest hit", [], accel.cast_rays), ("any hit", ["--any-hit"], accel.test_occlusions),
                               ("count", ["--count"], accel.count_intersections)):
        c = cli_seconds(args.cli, args.scene, args.rays, "bvh8", extra, args.reps)
        p, _ = best_of(args.reps, lambda: query(rays))
        print(f"| {name} | {c * 1e3:.0f} ms ({n / c / 1e6:.2f} Mrays/s) | {p * 1e3:.0f} ms ({n / p / 1e6:.2f} Mrays/s) "
              f"| {100 * (p / c - 1):+.1f}% |")

    try:
        import open3d as o3d
    except ImportError:
        print("\nOpen3D is not installed: no comparison")
        return
    o3 = o3d.t.geometry.RaycastingScene()
    o3.add_triangles(o3d.core.Tensor(scene.vertices), o3d.core.Tensor(scene.triangles))
    six = np.ascontiguousarray(rays[:, :6])
    rng = np.random.default_rng(1)
    lo, hi = (np.array(b) for b in scene.bounds)
    pts = (lo + rng.random((args.points, 3)) * (hi - lo)).astype(np.float32)
    pts_t = o3d.core.Tensor(pts)
    six_t = o3d.core.Tensor(six)
    print(f"\nOpen3D {o3d.__version__} RaycastingScene against thicket (bvh8; closest points through its bvh), "
          f"{n} rays, {len(pts)} points in the scene's box:\n")
    print("| query | Open3D | thicket | speed-up | agreement |")
    print("|---|---|---|---|---|")
    rows = [
        ("cast_rays", lambda: o3.cast_rays(six_t)["t_hit"].numpy(), lambda: accel.cast_rays(six)["t_hit"], "t_hit"),
        ("test_occlusions", lambda: o3.test_occlusions(six_t).numpy(), lambda: accel.test_occlusions(six), "occluded"),
        ("count_intersections", lambda: o3.count_intersections(six_t).numpy(),
         lambda: accel.count_intersections(six), "count"),
        ("compute_closest_points", lambda: o3.compute_closest_points(pts_t)["points"].numpy(),
         lambda: accel.compute_closest_points(pts)["points"], "points"),
        ("compute_distance", lambda: o3.compute_distance(pts_t).numpy(), lambda: accel.compute_distance(pts),
         "distance"),
    ]
    accel.compute_distance(pts[:1])  # the BVH for closest points is built on first use: not timed
    for name, theirs, ours, what in rows:
        to, a = best_of(args.reps, theirs)
        tt, b = best_of(args.reps, ours)
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


if __name__ == "__main__":
    sys.exit(main())
