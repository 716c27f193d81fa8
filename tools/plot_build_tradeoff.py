#!/usr/bin/env python3
"""Build time against trace speed, one panel per scene, from a `thicket bench --json` file.

    build/thicket bench SCENES... --accel bvh8:quality=low --accel bvh8 --accel bvh8:quality=high \\
        --sets primary,diffuse --json builders.json
    tools/plot_build_tradeoff.py builders.json docs/images/builders-tradeoff.svg [--set diffuse] [--threads 1]

Each point is one structure (or Embree build quality): x = its build time in ms (log scale), y =
its Mrays/s on the chosen ray set and thread count. The trade-off a user picks from: points up
and to the left are better. Scenes whose builds all take under 0.5 ms are left out (their
timings are noise). Plain SVG, no dependencies beyond Python 3.
"""
import argparse
import json
import math
import os
import sys

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"]


def load_rows(path):
    with open(path) as f:
        data = json.load(f)
    return data["rows"] if isinstance(data, dict) else data


def nice_ticks(lo, hi):
    """Powers of ten and their 2x and 5x between lo and hi (log axis)."""
    ticks = []
    e = math.floor(math.log10(lo))
    while 10 ** e <= hi * 1.0001:
        for m in (1, 2, 5):
            v = m * 10 ** e
            if lo <= v <= hi:
                ticks.append(v)
        e += 1
    return ticks


def fmt(v):
    return f"{v:g}" if v >= 1 else f"{v:.2g}"


def panel(out, x0, y0, w, h, scene, points, accels):
    """One scene: axes, ticks and a labelled marker per point (accel, build ms, Mrays/s)."""
    xs = [p[1] for p in points]
    ys = [p[2] for p in points]
    xlo, xhi = min(xs) / 1.5, max(xs) * 1.5
    yhi = max(ys) * 1.15
    lx, ly, pw, ph = x0 + 50, y0 + 25, w - 65, h - 65

    def px(v):
        return lx + pw * (math.log10(v) - math.log10(xlo)) / (math.log10(xhi) - math.log10(xlo))

    def py(v):
        return ly + ph - ph * v / yhi

    out.append(f'<text x="{x0 + w / 2}" y="{y0 + 15}" text-anchor="middle" font-weight="bold">{scene}</text>')
    out.append(f'<rect x="{lx}" y="{ly}" width="{pw}" height="{ph}" fill="none" stroke="#888"/>')
    for t in nice_ticks(xlo, xhi):
        out.append(f'<line x1="{px(t):.1f}" y1="{ly + ph}" x2="{px(t):.1f}" y2="{ly + ph + 4}" stroke="#888"/>')
        out.append(f'<text x="{px(t):.1f}" y="{ly + ph + 16}" text-anchor="middle" font-size="10">{fmt(t)}</text>')
    step = 10 ** math.floor(math.log10(yhi / 4))
    step *= 5 if yhi / step > 20 else (2 if yhi / step > 8 else 1)
    t = 0.0
    while t <= yhi:
        out.append(f'<line x1="{lx - 4}" y1="{py(t):.1f}" x2="{lx}" y2="{py(t):.1f}" stroke="#888"/>')
        out.append(f'<text x="{lx - 6}" y="{py(t) + 3:.1f}" text-anchor="end" font-size="10">{t:g}</text>')
        t += step
    out.append(f'<text x="{lx + pw / 2}" y="{y0 + h - 8}" text-anchor="middle" font-size="10">build ms (log)</text>')
    for accel, x, y in points:
        c = COLOURS[accels.index(accel) % len(COLOURS)]
        out.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="4" fill="{c}"><title>{accel}: '
                   f'{x:.3g} ms, {y:.3g} Mrays/s</title></circle>')


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("json", help="rows written by thicket bench --json")
    ap.add_argument("svg", help="output SVG (refused if it exists, unless --force)")
    ap.add_argument("--set", default="diffuse", help="ray set for the speed axis (default diffuse)")
    ap.add_argument("--threads", type=int, default=1, help="thread count of the rows to plot (default 1)")
    ap.add_argument("--force", action="store_true", help="overwrite an existing SVG")
    args = ap.parse_args()
    if os.path.exists(args.svg) and not args.force:
        sys.exit(f"plot_build_tradeoff: {args.svg} exists; pass --force to overwrite it")
    try:
        rows = load_rows(args.json)
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"plot_build_tradeoff: cannot read {args.json}: {e}")
    scenes, accels, by_scene = [], [], {}
    for r in rows:
        if r.get("set") != args.set or r.get("threads") != args.threads or not r.get("mrays"):
            continue
        if r["scene"] not in by_scene:
            scenes.append(r["scene"])
            by_scene[r["scene"]] = []
        if r["accel"] not in accels:
            accels.append(r["accel"])
        by_scene[r["scene"]].append((r["accel"], max(float(r["build_ms"]), 1e-3), float(r["mrays"])))
    scenes = [s for s in scenes if max(p[1] for p in by_scene[s]) >= 0.5]
    if not scenes:
        sys.exit(f"plot_build_tradeoff: no rows of set {args.set} on {args.threads} thread(s) in {args.json}")
    cols, pw, ph = 3, 300, 240
    rows_n = (len(scenes) + cols - 1) // cols
    width, height = cols * pw, rows_n * ph + 30 + 18 * ((len(accels) + 3) // 4)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="10" y="18">Build time against {args.set} Mrays/s, both on {args.threads} '
           f'thread(s): up and left is better</text>']
    for i, s in enumerate(scenes):
        panel(out, (i % cols) * pw, 25 + (i // cols) * ph, pw, ph, s, by_scene[s], accels)
    ly = 30 + rows_n * ph
    for i, a in enumerate(accels):
        x, y = 10 + (i % 4) * (width // 4), ly + 18 * (i // 4)
        out.append(f'<circle cx="{x + 5}" cy="{y - 4}" r="4" fill="{COLOURS[i % len(COLOURS)]}"/>')
        out.append(f'<text x="{x + 14}" y="{y}">{a}</text>')
    out.append("</svg>")
    with open(args.svg, "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"wrote {args.svg}: {len(scenes)} scenes, {len(accels)} structures")


if __name__ == "__main__":
    main()
