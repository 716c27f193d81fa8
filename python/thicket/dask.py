"""Casting a Dask array of rays on a Dask cluster.

    from dask.distributed import Client
    import dask.array as da, thicket.dask
    client = Client("tcp://scheduler:8786")
    hits = thicket.dask.cast_rays(da.from_zarr("rays.zarr"), "/data/scene.ply", saved="/data/scene.bvh")

Each worker process loads the scene and the structure once (saved with Accel.save, or built from
`spec` when `saved` is None) and keeps them for every chunk it is given, until either file is
replaced or changed (a different inode, size or modification time): then the next chunk loads them
again. The paths (str, bytes or os.PathLike) must be readable on the workers. A numpy array of
rays is taken as one too (wrapped with dask.array.from_array). Rays are chunked along their leading axes only (the last axis, 6 or 8 columns, is
made one chunk). The results are Dask arrays with the rays' leading chunks, as the single-process
queries answer them: the same values, ray for ray. float64 rays are taken with a `spec` built with
precision=double (t_hit and primitive_uvs then float64, as Accel.cast_rays answers them); with any
other spec, or a saved structure (always float), they are refused before any work.
"""

import numbers
import os
import threading

import dask.array as da
import numpy as np

import thicket

__all__ = ["cast_rays", "test_occlusions", "count_intersections", "load_count"]

_cache: dict = {}  # (scene_path, spec, saved) -> (the files' states, Accel)
_lock = threading.Lock()
_loads = 0


def _file_state(path):
    """What tells a replaced or rewritten file from the one read before: (device, inode, size,
    mtime in ns); None for a built-in scene name or a path that is not there (load says why)."""
    if path is None:
        return None
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def _accel(scene_path, spec, saved):
    """The structure for these paths in this process: loaded on first use, then reused while
    both files are the ones it was loaded from (a path alone would answer for an old scene after
    the file is replaced)."""
    global _loads
    key = (scene_path, spec, saved)
    with _lock:  # a worker's threads share one copy; only one of them loads it
        state = (_file_state(scene_path), _file_state(saved))
        entry = _cache.get(key)
        if entry is None or entry[0] != state:
            scene = thicket.load_scene(scene_path)
            accel = thicket.load(saved, scene) if saved is not None else thicket.build(scene, spec)
            _cache[key] = entry = (state, accel)  # the old structure, if any, is dropped
            _loads += 1
        return entry[1]


def load_count():
    """How many structures this process has loaded or built (the test checks: once per worker)."""
    return _loads


# cast_rays' answers packed in one block per chunk, of the rays' dtype, so one task casts each chunk
# once and the five outputs are views of it: t, primitive id and geometry id (their bits in float32;
# their values, exact, in float64), u, v, normal x, y, z.
_PACKED = 8


def _cast_block(block, scene_path, spec, saved, nthreads):
    block = np.ascontiguousarray(block)
    hits = _accel(scene_path, spec, saved).cast_rays(block, nthreads=nthreads)
    out = np.empty(block.shape[:-1] + (_PACKED,), block.dtype)
    out[..., 0] = hits["t_hit"]
    wide = block.dtype == np.float64
    out[..., 1] = hits["primitive_ids"] if wide else hits["primitive_ids"].view(np.float32)
    out[..., 2] = hits["geometry_ids"] if wide else hits["geometry_ids"].view(np.float32)
    out[..., 3:5] = hits["primitive_uvs"]
    out[..., 5:8] = hits["primitive_normals"]
    return out


def _path(path, what):
    """A path argument as the str the workers open: bytes decoded as open() would, not str()'d."""
    if path is None:
        return None
    try:
        return os.fsdecode(path)
    except TypeError:
        raise TypeError(f"{what}: expected a str, bytes or os.PathLike path, got {type(path).__name__}") from None


def _check_nthreads(nthreads):
    """The module's rule (the CLI's -j), checked here so that a bad count fails before any work."""
    if not isinstance(nthreads, numbers.Integral):
        raise TypeError(f"nthreads must be an integer, got {type(nthreads).__name__}")
    if not 0 <= nthreads <= 2**32 - 1:
        raise ValueError(f"nthreads must be 0 (one thread per core) or a thread count up to 4294967295, got {nthreads}")


def _one_chunk_last_axis(rays, spec, saved):
    if isinstance(rays, np.ndarray):
        rays = da.from_array(rays)
    elif not isinstance(rays, da.Array):
        raise TypeError(f"rays: expected a dask array (or a numpy array) of shape (..., 6) or (..., 8), "
                        f"got {type(rays).__name__}")
    if rays.ndim < 1 or rays.shape[-1] not in (6, 8):
        raise ValueError(f"rays: expected a dask array of shape (..., 6) or (..., 8), got shape {rays.shape}")
    double = saved is None and "precision=double" in str(spec)
    if rays.dtype != np.float32 and not (double and rays.dtype == np.float64):
        raise ValueError(f"rays: expected dtype float32, got shape {rays.shape} {rays.dtype} (float64 rays are taken "
                         f"with a spec built with precision=double, e.g. 'bvh:precision=double', and no saved structure; "
                         f"else convert with .astype(numpy.float32))")
    return rays.rechunk({rays.ndim - 1: -1}) if len(rays.chunks[-1]) > 1 else rays


def cast_rays(rays, scene_path, spec=thicket.DEFAULT_SPEC, saved=None, nthreads=0):
    """Closest hits of a Dask array of rays (a numpy array is wrapped with dask.array.from_array;
    anything else is a TypeError): a dict of Dask arrays with cast_rays' keys."""
    rays = _one_chunk_last_axis(rays, spec, saved)
    _check_nthreads(nthreads)
    packed = rays.map_blocks(_cast_block, _path(scene_path, "scene_path"), spec, _path(saved, "saved"), nthreads,
                             dtype=rays.dtype, chunks=rays.chunks[:-1] + ((_PACKED,),))
    wide = rays.dtype == np.float64
    ids = (lambda b: b.astype(np.uint32)) if wide else (lambda b: b.view(np.uint32))
    return {
        "t_hit": packed[..., 0],
        "geometry_ids": packed[..., 2].map_blocks(ids, dtype=np.uint32),
        "primitive_ids": packed[..., 1].map_blocks(ids, dtype=np.uint32),
        "primitive_uvs": packed[..., 3:5],
        "primitive_normals": packed[..., 5:8].astype(np.float32) if wide else packed[..., 5:8],
    }


def _per_ray(rays, scene_path, spec, saved, query, dtype, **kwargs):
    rays = _one_chunk_last_axis(rays, spec, saved)
    _check_nthreads(kwargs.get("nthreads", 0))
    scene_path, saved = _path(scene_path, "scene_path"), _path(saved, "saved")

    def block(b):
        return getattr(_accel(scene_path, spec, saved), query)(np.ascontiguousarray(b), **kwargs)

    return rays.map_blocks(block, dtype=dtype, drop_axis=rays.ndim - 1)


def test_occlusions(rays, scene_path, spec=thicket.DEFAULT_SPEC, saved=None, nthreads=0):
    """Whether anything is hit, a bool Dask array of the rays' leading shape (rays as cast_rays takes them)."""
    return _per_ray(rays, scene_path, spec, saved, "test_occlusions", np.bool_, nthreads=nthreads)


def count_intersections(rays, scene_path, spec=thicket.DEFAULT_SPEC, saved=None, nthreads=0):
    """Surface crossings per ray, an int32 Dask array of the rays' leading shape (rays as cast_rays takes them)."""
    return _per_ray(rays, scene_path, spec, saved, "count_intersections", np.int32, nthreads=nthreads)

