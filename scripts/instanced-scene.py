#!/usr/bin/env python3
"""Writes a JSON scene of COUNT instances of a few meshes (docs/shapes.md, "Instances"): the
instanced figure of the bench (README, "Repeating geometry: instances").

    python3 scripts/instanced-scene.py OUT.json --count 10000 \
        ../shared/scenes/dragon.ply:1 ../shared/scenes/bunny.ply:3

Each MESH[:WEIGHT] is one shape entry (its geometry held once); instances take the meshes in
proportion to their weights, in a fixed round-robin order. Every mesh is scaled to a largest
extent of 1 and centred (from its PLY's vertices), then each instance gets a cell of a square
grid, a rotation about y, a scale of 0.6 to 1, a shear on every 7th and a mirror in x on every
5th (so both kinds of transform are measured). Deterministic for a given --seed.
"""
import argparse
import json
import math
import os
import random
import struct
import sys

_PLY_TYPES = {"char": "b", "uchar": "B", "int8": "b", "uint8": "B", "short": "h", "ushort": "H", "int16": "h",
              "uint16": "H", "int": "i", "uint": "I", "int32": "i", "uint32": "I", "float": "f", "float32": "f",
              "double": "d", "float64": "d"}


def ply_bounds(path):
    """(min, max) of a binary or ASCII PLY's vertices (its x, y, z properties)."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                sys.exit(f"{path}: no end_header")
            line = line.decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
        fmt = next((l.split()[1] for l in header if l.startswith("format")), None)
        count, props, in_vertex = 0, [], False
        for l in header:
            w = l.split()
            if w[:1] == ["element"]:
                in_vertex = w[1] == "vertex"
                if in_vertex:
                    count = int(w[2])
            elif w[:1] == ["property"] and in_vertex:
                if w[1] == "list":
                    sys.exit(f"{path}: a list property among the vertex properties")
                props.append((w[2], _PLY_TYPES[w[1]]))
        names = [p[0] for p in props]
        ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
        lo, hi = [math.inf] * 3, [-math.inf] * 3
        if fmt == "ascii":
            rows = (f.readline().split() for _ in range(count))
            values = ([float(r[ix]), float(r[iy]), float(r[iz])] for r in rows)
        else:
            order = "<" if fmt == "binary_little_endian" else ">"
            record = struct.Struct(order + "".join(p[1] for p in props))
            data = f.read(record.size * count)
            values = ((v[ix], v[iy], v[iz]) for v in record.iter_unpack(data))
        for v in values:
            for a in range(3):
                lo[a] = min(lo[a], v[a])
                hi[a] = max(hi[a], v[a])
        return lo, hi


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("meshes", nargs="+", metavar="MESH[:WEIGHT]")
    ap.add_argument("--count", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    if args.count < 1:
        sys.exit("--count must be at least 1")
    shapes, cycle = [], []
    for i, spec in enumerate(args.meshes):
        path, _, weight = spec.rpartition(":") if spec.rpartition(":")[2].isdigit() else (spec, "", "1")
        if not os.path.isfile(path):
            sys.exit(f"{path}: no such mesh file")
        lo, hi = ply_bounds(path)
        size = max(h - l for l, h in zip(lo, hi))
        if not size > 0:
            sys.exit(f"{path}: the mesh has no extent")
        s = 1.0 / size
        c = [(l + h) / 2 for l, h in zip(lo, hi)]
        # Normalized in the prototype, so that an instance's transform is only its placement.
        shapes.append({"type": "mesh", "file": os.path.abspath(path),
                       "transform": [s, 0, 0, -s * c[0], 0, s, 0, -s * c[1], 0, 0, s, -s * c[2], 0, 0, 0, 1]})
        cycle += [i] * int(weight)
    rng = random.Random(args.seed)
    side = math.ceil(math.sqrt(args.count))
    instances = []
    for k in range(args.count):
        gx, gz = k % side, k // side
        angle = rng.uniform(0, 2 * math.pi)
        scale = rng.uniform(0.6, 1.0)
        ca, sa = math.cos(angle) * scale, math.sin(angle) * scale
        m = [[ca, 0, sa], [0, scale, 0], [-sa, 0, ca]]
        if k % 7 == 3:
            m[0][1] += 0.3 * scale  # shear x by y
        if k % 5 == 2:
            m[0] = [-x for x in m[0]]  # mirror in x
        t = [1.2 * (gx - side / 2), 0.0, 1.2 * (gz - side / 2)]
        instances.append({"shape": cycle[k % len(cycle)],
                          "transform": [round(v, 6) for r in range(3) for v in (m[r] + [t[r]])]})
    with open(args.out, "w") as f:
        json.dump({"shapes": shapes, "instances": instances}, f, separators=(",", ":"))
    print(f"wrote {args.out}: {len(shapes)} meshes, {args.count} instances")


if __name__ == "__main__":
    main()
