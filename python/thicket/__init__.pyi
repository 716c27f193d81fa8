# Type stub of the thicket package (the compiled thicket._thicket and the pure Python files), for
# IDEs and mypy. python/tests/test_stub.py checks that its names are the module's, and the module's
# its own. Arrays are numpy arrays; shapes are in the docstrings (numpy's types do not carry them).
import os
from typing import (Any, Dict, Generic, List, Literal, NotRequired, Optional, Sequence, Tuple, TypedDict, TypeVar, Union,
                    overload)

import numpy as np
import numpy.typing as npt

_Path = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]
_Bounds = Tuple[Tuple[float, float, float], Tuple[float, float, float]]
_Float32Array = npt.NDArray[np.float32]
_Float64Array = npt.NDArray[np.float64]  # rays for precision=double structures, and their t and uv
_UInt32Array = npt.NDArray[np.uint32]
_Vector3 = Union[npt.ArrayLike, Any]  # 3 numbers: a list, a numpy array, an Open3D Tensor
_Triple = Tuple[float, float, float]
_Light = Tuple[_Vector3, Union[float, _Vector3]]  # (position, intensity in W/sr: one number or r, g, b)

DEFAULT_SPEC: str
"""The spec build() and RaycastingScene use when given none: "bvh8", the fastest (the CLI's default too)."""
INVALID_ID: int
"""primitive_ids and geometry_ids of a miss (Open3D's RaycastingScene.INVALID_ID): 4294967295."""

class Error(RuntimeError):
    """A bad spec, a malformed file, a saved structure of another scene."""

_Real = TypeVar("_Real", np.float32, np.float64)  # the rays' dtype: float64 on precision=double structures

class _CastResult(TypedDict, Generic[_Real]):
    t_hit: npt.NDArray[_Real]            # (...)       inf on a miss; float64 for float64 rays
    geometry_ids: _UInt32Array           # (...)       INVALID_ID on a miss
    primitive_ids: _UInt32Array          # (...)       INVALID_ID on a miss
    primitive_uvs: npt.NDArray[_Real]    # (..., 2)
    primitive_normals: _Float32Array     # (..., 3)

class _IntersectionList(TypedDict, Generic[_Real]):
    ray_splits: _UInt32Array             # (N + 1,)    ray i's crossings are [ray_splits[i], ray_splits[i+1])
    ray_ids: _UInt32Array                # (M,)
    t_hit: npt.NDArray[_Real]            # (M,)        float64 for float64 rays
    geometry_ids: _UInt32Array           # (M,)
    primitive_ids: _UInt32Array          # (M,)
    primitive_uvs: npt.NDArray[_Real]    # (M, 2)

class _ClosestPoints(TypedDict):
    points: _Float32Array                # (..., 3)
    geometry_ids: _UInt32Array           # (...)
    primitive_ids: _UInt32Array          # (...)
    primitive_uvs: _Float32Array         # (..., 2)
    primitive_normals: _Float32Array     # (..., 3)

class _Located(TypedDict):
    instance_ids: _UInt32Array           # (...)       INVALID_ID for a miss's id
    geometry_ids: _UInt32Array           # (...)       the prototype's geometry
    primitive_ids: _UInt32Array          # (...)       within that geometry

class _RaySet(TypedDict, total=False):
    rays: _Float32Array                  # (N, 6)      ox oy oz dx dy dz, unit directions
    tmin: _Float32Array                  # (N,)        0
    tmax: _Float32Array                  # (N,)        inf, or short of the light for shadow rays
    pixel: _UInt32Array                  # (N,)        y * width + x; absent for the random set
    set: str
    any_hit: bool                        # True: trace with test_occlusions
    width: int
    height: int
    eye: _Triple
    center: _Triple
    vfov_deg: float
    light: _Triple
    interior: bool

class Scene:
    """Triangles and shapes that structures are built over."""
    def __init__(self, vertices: npt.ArrayLike, triangles: npt.ArrayLike) -> None:
        """vertices (V, 3) of any float dtype, finite; triangles (T, 3) of any integer dtype, indices in 0..V-1."""
    @property
    def name(self) -> str: ...
    @property
    def primitive_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def shape_count(self) -> int: ...
    @property
    def bounds(self) -> _Bounds:
        """((xmin, ymin, zmin), (xmax, ymax, zmax))."""
    @property
    def vertices(self) -> _Float32Array:
        """A copy, float32 (V, 3)."""
    @property
    def triangles(self) -> _UInt32Array:
        """A copy, uint32 (T, 3)."""
    def set_vertices(self, geometry_id: int, vertices: npt.ArrayLike) -> None:
        """Moves geometry geometry_id's vertices to (N, 3) of any float dtype (N its own vertex count); then Accel.refit(scene)."""
    def add_geometry(self, other: Scene) -> int:
        """Appends other's triangles as a new geometry -> its geometry id."""
    def add_instance(self, geometry_id: int, transform: npt.ArrayLike) -> int:
        """Places geometry geometry_id under a (3, 4) or (4, 4) affine transform -> the instance id; then geometries are prototypes."""
    @property
    def instance_count(self) -> int: ...

class Accel:
    """An acceleration structure over a scene: thicket.build(scene, spec) or thicket.load(path, scene)."""
    @property
    def spec(self) -> str: ...
    @property
    def scene(self) -> Scene: ...
    @property
    def bounds(self) -> _Bounds: ...
    @property
    def double_precision(self) -> bool:
        """Built with precision=double: cast_rays, test_occlusions, count_intersections and list_intersections take
        float64 rays too and trace them in double."""
    def stats(self) -> Dict[str, Any]:
        """spec, primitives, nodes, leaves, max_depth, bytes, primitive_bytes, sah_cost, build_ms, extra."""
    def save(self, path: _Path, overwrite: bool = False) -> None: ...
    @property
    def refittable(self) -> bool:
        """Whether refit() is supported (bvh, bvh8, obb)."""
    def refit(self, scene: Scene, nthreads: int = 0) -> None:
        """Updates the structure for scene's moved vertices (same primitives, same order); thicket.Error if it cannot refit."""
    @property
    def instance_count(self) -> int: ...
    def set_transform(self, instance_id: int, transform: npt.ArrayLike) -> None:
        """Moves an instance to a (3, 4) or (4, 4) affine transform, rebuilding only the top level."""
    def locate(self, primitive_ids: npt.ArrayLike) -> _Located:
        """Flattened primitive ids (...) of a structure with instances -> instance, geometry and primitive ids (...)."""
    def cast_rays(self, rays: npt.NDArray[_Real], nthreads: int = 0, coherent: bool = False) -> _CastResult[_Real]:
        """rays float32 (..., 6) or (..., 8) -> closest hits, each array of the rays' leading shape; float64 rays
        on a precision=double structure only (t_hit and primitive_uvs then float64; the others raise ValueError
        naming precision=double)."""
    def test_occlusions(self, rays: Union[_Float32Array, _Float64Array], tnear: Optional[float] = None, tfar: Optional[float] = None,
                        nthreads: int = 0, coherent: bool = False) -> npt.NDArray[np.bool_]:
        """rays float32 (..., 6) or (..., 8) -> bool (...); float64 rays as cast_rays."""
    def count_intersections(self, rays: Union[_Float32Array, _Float64Array], nthreads: int = 0) -> npt.NDArray[np.int32]:
        """rays float32 (..., 6) or (..., 8) -> int32 (...); float64 rays as cast_rays (crossings found in double)."""
    def list_intersections(self, rays: npt.NDArray[_Real], nthreads: int = 0) -> _IntersectionList[_Real]:
        """rays float32 (..., 6) or (..., 8), N of them in row order -> every crossing, sorted by t per ray; float64
        rays as cast_rays (t_hit and primitive_uvs then float64)."""
    def compute_closest_points(self, query_points: _Float32Array, nthreads: int = 0) -> _ClosestPoints:
        """query_points float32 (..., 3); float64 is a ValueError on every structure (point queries are float32)."""
    def compute_distance(self, query_points: _Float32Array, nthreads: int = 0) -> _Float32Array:
        """query_points float32 (..., 3) -> float32 (...)."""
    def compute_signed_distance(self, query_points: _Float32Array, nthreads: int = 0, nsamples: int = 1) -> _Float32Array:
        """query_points float32 (..., 3) -> float32 (...), negative inside."""
    def compute_occupancy(self, query_points: _Float32Array, nthreads: int = 0, nsamples: int = 1) -> _Float32Array:
        """query_points float32 (..., 3) -> float32 (...), 1 inside and 0 outside."""
    @overload
    def render(self, view: Literal["normal"] = "normal", width: int = 640, height: int = 480,
               eye: Optional[_Vector3] = None, center: Optional[_Vector3] = None, up: Optional[_Vector3] = None,
               vfov_deg: Optional[float] = None, counter: None = None, nthreads: int = 0) -> _Float32Array:
        """float32 (height, width, 3): unit normals faced to the camera, (0, 0, 0) on a miss."""
    @overload
    def render(self, view: Literal["depth"], width: int = 640, height: int = 480,
               eye: Optional[_Vector3] = None, center: Optional[_Vector3] = None, up: Optional[_Vector3] = None,
               vfov_deg: Optional[float] = None, counter: None = None, nthreads: int = 0) -> _Float32Array:
        """float32 (height, width): hit distance, inf on a miss."""
    @overload
    def render(self, view: Literal["heatmap"], width: int = 640, height: int = 480,
               eye: Optional[_Vector3] = None, center: Optional[_Vector3] = None, up: Optional[_Vector3] = None,
               vfov_deg: Optional[float] = None, counter: Optional[Literal["nodes", "prims"]] = None,
               nthreads: int = 0) -> _UInt32Array:
        """uint32 (height, width): nodes visited (or primitives tested) per pixel's ray."""

_S = TypeVar("_S", bound=np.generic)

class _Answer(np.ndarray[Any, np.dtype[_S]], Generic[_S]):
    """A RaycastingScene answer: a numpy array with Open3D Tensor's numpy() and isfinite()."""
    def numpy(self) -> npt.NDArray[_S]: ...
    def isfinite(self) -> npt.NDArray[np.bool_]: ...

class _SceneCast(TypedDict):
    t_hit: _Answer[np.float32]             # (...)       inf on a miss
    geometry_ids: _Answer[np.uint32]       # (...)       add_triangles' id; INVALID_ID on a miss
    primitive_ids: _Answer[np.uint32]      # (...)       the triangle within its geometry; INVALID_ID on a miss
    primitive_uvs: _Answer[np.float32]     # (..., 2)
    primitive_normals: _Answer[np.float32]  # (..., 3)
    instance_ids: NotRequired[_Answer[np.uint32]]  # (...)       with instances: add_instance's id, else INVALID_ID

class _SceneIntersections(TypedDict):
    ray_splits: _Answer[np.uint32]         # (N + 1,)
    ray_ids: _Answer[np.uint32]            # (M,)
    t_hit: _Answer[np.float32]             # (M,)
    geometry_ids: _Answer[np.uint32]       # (M,)
    primitive_ids: _Answer[np.uint32]      # (M,)       within the geometry
    primitive_uvs: _Answer[np.float32]     # (M, 2)
    instance_ids: NotRequired[_Answer[np.uint32]]  # (M,)        with instances: add_instance's id, else INVALID_ID

class _SceneClosest(TypedDict):
    points: _Answer[np.float32]            # (..., 3)
    geometry_ids: _Answer[np.uint32]       # (...)
    primitive_ids: _Answer[np.uint32]      # (...)      within the geometry
    primitive_uvs: _Answer[np.float32]     # (..., 2)
    primitive_normals: _Answer[np.float32]  # (..., 3)
    instance_ids: NotRequired[_Answer[np.uint32]]  # (...)       with instances: add_instance's id, else INVALID_ID

_Input = Union[npt.ArrayLike, Any]  # a numpy array, a list, an Open3D Tensor

class RaycastingScene:
    """Open3D's RaycastingScene: several meshes, each a geometry id, and instances of them."""
    INVALID_ID: int
    def __init__(self, nthreads: int = 0, accel: str = "bvh8") -> None:
        """nthreads for refits (0: one per core); accel: the structure's spec string."""
    @overload
    def add_triangles(self, vertex_positions: _Input, triangle_indices: _Input) -> int:
        """vertex_positions (V, 3) floats, triangle_indices (T, 3) ints -> the new geometry id (0, 1, ...)."""
    @overload
    def add_triangles(self, mesh: Union[Scene, Any]) -> int:
        """A thicket.Scene of triangles or an Open3D t.geometry.TriangleMesh -> the new geometry id."""
    def set_vertices(self, geometry_id: int, vertex_positions: _Input) -> None:
        """(N, 3) floats, N the geometry's vertex count; the next query or refit() updates the structure."""
    def refit(self) -> None:
        """Brings the structure up to date now (refit, or a rebuild for a structure that cannot refit)."""
    @property
    def refit_rebuilds(self) -> int:
        """How many times a move was answered by a rebuild because the structure could not refit (logged on "thicket")."""
    def add_instance(self, geometry_id: int, transform: _Input) -> int:
        """Draws geometry geometry_id again under a (3, 4) or (4, 4) affine transform -> the instance id (0, 1, ...)."""
    def set_transform(self, instance_id: int, transform: _Input) -> None:
        """Moves an instance; the next query rebuilds only the top level."""
    def cast_rays(self, rays: _Input, nthreads: int = 0) -> _SceneCast:
        """rays float32 (..., 6) or (..., 8) -> closest hits, each array of the rays' leading shape."""
    def test_occlusions(self, rays: _Input, tnear: float = 0.0, tfar: float = ..., nthreads: int = 0) -> _Answer[np.bool_]:
        """rays float32 (..., 6) -> bool (...); tfar defaults to inf."""
    def count_intersections(self, rays: _Input, nthreads: int = 0) -> _Answer[np.int32]:
        """rays float32 (..., 6) -> int32 (...)."""
    def list_intersections(self, rays: _Input, nthreads: int = 0) -> _SceneIntersections:
        """rays float32 (..., 6), N of them in row order -> every crossing, sorted by t per ray."""
    def compute_closest_points(self, query_points: _Input, nthreads: int = 0) -> _SceneClosest:
        """query_points float32 (..., 3)."""
    def compute_distance(self, query_points: _Input, nthreads: int = 0) -> _Answer[np.float32]:
        """query_points float32 (..., 3) -> float32 (...)."""
    def compute_signed_distance(self, query_points: _Input, nthreads: int = 0, nsamples: int = 1) -> _Answer[np.float32]:
        """query_points float32 (..., 3) -> float32 (...), negative inside."""
    def compute_occupancy(self, query_points: _Input, nthreads: int = 0, nsamples: int = 1) -> _Answer[np.float32]:
        """query_points float32 (..., 3) -> float32 (...), 1 inside and 0 outside."""
    @overload
    @staticmethod
    def create_rays_pinhole(fov_deg: float, center: _Vector3, eye: _Vector3, up: _Vector3,
                            width_px: int, height_px: int) -> _Answer[np.float32]:
        """float32 (height_px, width_px, 6), as thicket.create_rays_pinhole."""
    @overload
    @staticmethod
    def create_rays_pinhole(intrinsic_matrix: _Input, extrinsic_matrix: _Input, width_px: int,
                            height_px: int) -> _Answer[np.float32]:
        """intrinsic (3, 3), extrinsic (4, 4) world to camera -> float32 (height_px, width_px, 6)."""

def load_scene(path: _Path, *, flatten: bool = False) -> Scene:
    """A PLY, OBJ, glTF or JSON scene file, or a built-in name ('cornell', 'teapot-patches').

    A glTF mesh that several nodes place becomes one geometry with an instance per node;
    flatten=True gives one triangle soup with a copy per node instead."""

def build(scene: Scene, spec: str = "bvh8") -> Accel:
    """A structure from a spec string NAME[:key=value,...] (see accels())."""

def load(path: _Path, scene: Scene) -> Accel:
    """A structure saved by Accel.save, for the same scene."""

def accels() -> List[Dict[str, Any]]:
    """Every registered structure: name, summary, partitioning, options, variants, can_load."""

@overload
def create_rays_pinhole(fov_deg: float, center: _Vector3, eye: _Vector3, up: _Vector3,
                        width_px: int, height_px: int) -> _Float32Array:
    """float32 (height_px, width_px, 6): origin, then the unnormalized direction (Open3D's)."""
@overload
def create_rays_pinhole(intrinsic_matrix: Union[npt.ArrayLike, Any], extrinsic_matrix: Union[npt.ArrayLike, Any],
                        width_px: int, height_px: int) -> _Float32Array:
    """intrinsic (3, 3), extrinsic (4, 4) world to camera -> float32 (height_px, width_px, 6)."""

def rays(scene: Scene, set: Literal["primary", "shadow", "diffuse", "random"] = "primary", width: int = 320,
         height: int = 240, eye: Optional[_Vector3] = None, center: Optional[_Vector3] = None,
         up: Optional[_Vector3] = None, vfov_deg: Optional[float] = None, nthreads: int = 0) -> _RaySet:
    """The bench's ray set, as `thicket rays --set`: rays float32 (N, 6), tmin/tmax float32 (N,), ..."""

def path_trace(scene: Union[Scene, Accel], spp: int = 16, width: int = 640, height: int = 480,
               eye: Optional[_Vector3] = None, center: Optional[_Vector3] = None, up: Optional[_Vector3] = None,
               vfov_deg: Optional[float] = None, seed: int = 0, max_depth: int = 64,
               integrator: Literal["path", "whitted"] = "path", lights: Optional[Sequence[_Light]] = None,
               nthreads: int = 0) -> _Float32Array:
    """float32 (height, width, 3) linear radiance, as `thicket render --integrator path`."""

def heat_colours(counts: npt.ArrayLike, heat_max: Optional[float] = None) -> npt.NDArray[np.uint8]:
    """counts (...) -> uint8 (..., 3), the CLI's heatmap ramp."""

def save_png(path: _Path, image: npt.ArrayLike, exposure: Optional[float] = None, overwrite: bool = False) -> None:
    """uint8 (H, W, 3) or (H, W) as it is; float (H, W, 3) radiance sRGB-encoded."""

__all__: List[str]
