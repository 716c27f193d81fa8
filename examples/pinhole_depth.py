"""A depth picture of a scene through Open3D-style pinhole rays, saved as .npy (float32 depth,
inf where nothing is hit) and as a greyscale PGM that any image viewer opens.

    PYTHONPATH=build/python python3 examples/pinhole_depth.py [scene] [out-prefix]

scene: any file or built-in name thicket.load_scene takes (default: the built-in Cornell box).
"""

import sys

import numpy as np
import numpy.typing as npt

import thicket


def depth_image(scene: thicket.Scene, width: int, height: int) -> npt.NDArray[np.float32]:
    """Depth along the optical axis (t_hit of the unnormalized pinhole rays), float32 (height, width),
    upright (Open3D's rays come turned half a turn: see create_rays_pinhole)."""
    lo, hi = (np.array(b, np.float64) for b in scene.bounds)
    center = 0.5 * (lo + hi)
    eye = center + np.array([0.0, 0.0, 1.3 * float(np.linalg.norm(hi - lo))])
    rays = thicket.create_rays_pinhole(40.0, center, eye, [0.0, 1.0, 0.0], width, height)
    hits = thicket.build(scene, "bvh8").cast_rays(rays)
    depth: npt.NDArray[np.float32] = hits["t_hit"][::-1, ::-1]
    return depth


def grey(depth: npt.NDArray[np.float32]) -> npt.NDArray[np.uint8]:
    """Near is bright, far dark, a miss black."""
    seen = np.isfinite(depth)
    out = np.zeros(depth.shape, np.uint8)
    if seen.any():
        near, far = float(depth[seen].min()), float(depth[seen].max())
        out[seen] = (255 - 200 * (depth[seen] - near) / max(far - near, 1e-12)).astype(np.uint8)
    return out


def main(argv: list[str]) -> None:
    scene = thicket.load_scene(argv[1] if len(argv) > 1 else "cornell")
    prefix = argv[2] if len(argv) > 2 else "depth"
    depth = depth_image(scene, 160, 120)
    np.save(prefix + ".npy", depth)
    image = grey(depth)
    with open(prefix + ".pgm", "wb") as f:
        f.write(b"P5 %d %d 255\n" % (image.shape[1], image.shape[0]))
        f.write(image.tobytes())
    print(f"{prefix}.npy and {prefix}.pgm: {int(np.isfinite(depth).sum())} of {depth.size} pixels hit")


if __name__ == "__main__":
    main(sys.argv)
