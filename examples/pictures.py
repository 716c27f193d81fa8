"""Pictures of a scene as numpy arrays, notebook style: the preview views (depth, normals, the work
per ray) and a path-traced image, each saved as a PNG and its numbers as .npy.

    PYTHONPATH=build/python python3 examples/pictures.py [scene] [out-dir] [spp]

scene: any file or built-in name thicket.load_scene takes (default: the built-in Cornell box).
In a notebook, show any of the arrays with matplotlib: plt.imshow(depth), plt.imshow(radiance ** (1 / 2.2)).
"""

import pathlib
import sys

import numpy as np
import numpy.typing as npt

import thicket


def grey(depth: npt.NDArray[np.float32]) -> npt.NDArray[np.uint8]:
    """Near white, far dark grey, a miss black: as `thicket render --view depth` draws it."""
    seen = np.isfinite(depth)
    out = np.zeros(depth.shape, np.uint8)
    if seen.any():
        near, far = float(depth[seen].min()), float(depth[seen].max())
        fraction = (depth[seen] - near) / max(far - near, 1e-30)
        out[seen] = np.round(255 * (1 - 0.8 * fraction)).astype(np.uint8)
    return out


def main(argv: list[str]) -> None:
    scene = thicket.load_scene(argv[1] if len(argv) > 1 else "cornell")
    out = pathlib.Path(argv[2] if len(argv) > 2 else "pictures")
    spp = int(argv[3]) if len(argv) > 3 else 16
    out.mkdir(parents=True, exist_ok=True)
    width, height = 160, 120

    # %% One structure answers every view; without eye/center the camera frames the scene.
    accel = thicket.build(scene, "bvh8")

    # %% Depth: hit distance per pixel (inf where nothing is hit).
    depth = accel.render("depth", width, height)
    np.save(out / "depth.npy", depth)
    thicket.save_png(out / "depth.png", grey(depth), overwrite=True)

    # %% Normals: unit vectors facing the camera, shown as 0.5 * n + 0.5 (a miss, (0, 0, 0), black).
    normal = accel.render("normal", width, height)
    np.save(out / "normal.npy", normal)
    hit = np.isfinite(depth)
    colour = np.where(hit[..., None], 0.5 * normal + 0.5, 0.0)
    thicket.save_png(out / "normal.png", np.round(255 * colour).astype(np.uint8), overwrite=True)

    # %% Work: nodes each ray visited, as counts and on the CLI's colour ramp.
    nodes = accel.render("heatmap", width, height)
    np.save(out / "nodes.npy", nodes)
    thicket.save_png(out / "heatmap.png", thicket.heat_colours(nodes), overwrite=True)

    # %% Light: linear radiance from the path tracer, sRGB-encoded for the PNG.
    radiance = thicket.path_trace(accel, spp=spp, width=width, height=height, seed=1)
    np.save(out / "radiance.npy", radiance)
    thicket.save_png(out / "path.png", radiance, overwrite=True)

    print(f"{out}: depth.png normal.png heatmap.png path.png ({width}x{height}); "
          f"{hit.mean():.0%} of pixels hit, {nodes.mean():.1f} nodes per ray (at most {nodes.max()}), "
          f"mean radiance {radiance.mean():.3f} at {spp} spp")


if __name__ == "__main__":
    main(sys.argv)
