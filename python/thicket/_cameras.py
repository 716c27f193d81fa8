"""Camera rays as Open3D's RaycastingScene.create_rays_pinhole makes them: same arguments, same
(height_px, width_px, 6) float32 layout, same numbers (origin, then the unnormalized direction)."""

import inspect
import math

import numpy as np

from ._arguments import count

__all__ = ["create_rays_pinhole"]


def _pixels(width_px, height_px):
    """width_px and height_px as positive ints (ValueError/TypeError naming the one at fault)."""
    return [count(value, f"create_rays_pinhole: {name}", "at least 1", least=1)
            for name, value in (("width_px", width_px), ("height_px", height_px))]


def _matrix(value, name, shape):
    """value as a finite float64 array of the given shape (ValueError quoting what was given)."""
    try:
        a = np.array(value.numpy() if hasattr(value, "numpy") else value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"create_rays_pinhole: {name} must be numbers of shape {shape}: {e}") from None
    if a.shape != shape:
        raise ValueError(f"create_rays_pinhole: {name} must have shape {shape}, got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"create_rays_pinhole: {name} must be finite, got {a.tolist()}")
    return a


def _rays(intrinsic, rotation, translation, width_px, height_px):
    """Open3D's construction: pixel centres (x + 0.5, y + 0.5, 1) taken through K^-1 and R^T (the
    transpose, as Open3D does, not the inverse), from the origin -R^T t; computed in float64."""
    try:
        k_inv = np.linalg.inv(intrinsic)
    except np.linalg.LinAlgError:
        raise ValueError(f"create_rays_pinhole: intrinsic_matrix is singular: {intrinsic.tolist()}") from None
    x = np.arange(width_px, dtype=np.float64) + 0.5
    y = np.arange(height_px, dtype=np.float64) + 0.5
    pixels = np.empty((height_px, width_px, 3))
    pixels[..., 0] = x[None, :]
    pixels[..., 1] = y[:, None]
    pixels[..., 2] = 1.0
    to_world = rotation.T @ k_inv
    rays = np.empty((height_px, width_px, 6), np.float32)
    rays[..., 0:3] = -rotation.T @ translation
    rays[..., 3:6] = pixels @ to_world.T
    return rays


def _from_matrices(intrinsic_matrix, extrinsic_matrix, width_px, height_px):
    width_px, height_px = _pixels(width_px, height_px)
    k = _matrix(intrinsic_matrix, "intrinsic_matrix", (3, 3))
    e = _matrix(extrinsic_matrix, "extrinsic_matrix", (4, 4))
    return _rays(k, e[:3, :3], e[:3, 3], width_px, height_px)


def _from_view(fov_deg, center, eye, up, width_px, height_px):
    width_px, height_px = _pixels(width_px, height_px)
    try:
        fov = float(fov_deg)
    except (TypeError, ValueError):
        raise TypeError(f"create_rays_pinhole: fov_deg must be a number, got {fov_deg!r}") from None
    if not 0.0 < fov < 180.0:
        raise ValueError(f"create_rays_pinhole: fov_deg must be in (0, 180) degrees, got {fov_deg!r}")
    center = _matrix(center, "center", (3,))
    eye = _matrix(eye, "eye", (3,))
    up = _matrix(up, "up", (3,))
    forward = center - eye
    if not np.linalg.norm(forward) > 0:
        raise ValueError(f"create_rays_pinhole: center and eye are the same point {eye.tolist()}")
    if not np.linalg.norm(up) > 0:
        raise ValueError("create_rays_pinhole: up is the zero vector")
    side = np.cross(up, forward)
    if not np.linalg.norm(side) > 1e-12 * np.linalg.norm(up) * np.linalg.norm(forward):
        raise ValueError(f"create_rays_pinhole: up {up.tolist()} is parallel to the view direction "
                         f"center - eye = {forward.tolist()}")
    # Open3D's frame: rows x = up x forward, y = forward x x (so +y is along up, and x to the
    # viewer's left: the image is an upright camera's turned half a turn), z = forward.
    r = np.empty((3, 3))
    r[2] = forward / np.linalg.norm(forward)
    r[0] = side / np.linalg.norm(side)
    r[1] = np.cross(r[2], r[0])
    focal = 0.5 * width_px / math.tan(math.radians(0.5 * fov))
    k = np.array([[focal, 0.0, 0.5 * width_px], [0.0, focal, 0.5 * height_px], [0.0, 0.0, 1.0]])
    return _rays(k, r, -r @ eye, width_px, height_px)


def create_rays_pinhole(*args, **kwargs):
    """Rays of a pinhole camera, as Open3D's RaycastingScene.create_rays_pinhole; two forms:

    create_rays_pinhole(fov_deg, center, eye, up, width_px, height_px)
        fov_deg: horizontal field of view in degrees, in (0, 180); center: the point looked at,
        eye: the camera position, up: the up vector, each 3 numbers (array-like or an Open3D
        Tensor); up must not be parallel to center - eye.
    create_rays_pinhole(intrinsic_matrix, extrinsic_matrix, width_px, height_px)
        intrinsic_matrix: (3, 3) K, invertible (fx, skew, cx / 0, fy, cy / 0, 0, 1);
        extrinsic_matrix: (4, 4) world-to-camera [R | t] (R is applied transposed, as Open3D does).

    width_px, height_px: positive ints. Returns float32 (height_px, width_px, 6): the origin (the
    eye, -R^T t) then the direction R^T K^-1 (x + 0.5, y + 0.5, 1) of pixel (x, y), NOT normalized
    (its camera-space z is 1, so t_hit is the depth along the optical axis). Like Open3D, +y of the
    camera is the up vector: row 0 looks below the centre and column 0 to the viewer's right, so an
    image of the hits is turned half a turn (image[::-1, ::-1] is upright). The rays
    pass to Accel.cast_rays as they are. Computed in float64, rounded once to float32.
    Raises TypeError or ValueError naming the argument at fault.
    """
    if "intrinsic_matrix" in kwargs or (args and np.ndim(args[0].numpy() if hasattr(args[0], "numpy") else args[0]) == 2):
        form = _from_matrices
    else:
        form = _from_view
    signature = inspect.signature(form)
    try:
        bound = signature.bind(*args, **kwargs)
    except TypeError as e:  # named after the public function and the form it was taken for
        raise TypeError(f"create_rays_pinhole{signature}: {e}") from None
    return form(*bound.args)
