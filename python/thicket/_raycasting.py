"""thicket.RaycastingScene: Open3D's multi-geometry RaycastingScene (add_triangles -> geometry id,
queries answering geometry_ids and per-geometry primitive_ids) over one thicket.Accel.

Every geometry's triangles go into one combined thicket.Scene, in id order, and one structure is
built over it on the first query after a change. The structure's primitive ids are scene-wide;
the queries turn them into (geometry id, primitive id within the geometry) with numpy, a search
over the geometries' first ids per answer, so no Python runs per ray."""

import logging

import numpy as np

from ._arguments import count as _count_argument
from ._cameras import create_rays_pinhole as _create_rays_pinhole
from ._thicket import DEFAULT_SPEC, Error, Scene, build

__all__ = ["RaycastingScene"]

_INVALID = 4294967295
# Scene(V, T) refuses a scene of 2^32 - 1 triangles or more (ids are 32-bit, the last one meaning
# "none") and more than 2^32 vertices (32-bit indices): checked per add_triangles as well, so that
# the call that goes over is the one refused, not a later query.
_MAX_TRIANGLES = _INVALID - 1
_MAX_VERTICES = 1 << 32
_IDENTITY = np.eye(4)[:3]
_log = logging.getLogger("thicket")


class _Answer(np.ndarray):
    """A numpy array with the methods of Open3D's Tensor that code over RaycastingScene's answers
    calls: numpy() (Open3D's answers are Tensors, read with .numpy()) and isfinite(). Arrays
    computed from one stay one, as a Tensor's do; a reduction to one value is a numpy scalar."""

    def __array_wrap__(self, obj, context=None, *rest):
        out = super().__array_wrap__(obj, context, *rest)
        return out[()] if out.ndim == 0 else out

    def __repr__(self):
        return repr(self.view(np.ndarray))

    def numpy(self):
        """The same data as a plain numpy.ndarray (a view, no copy), as Tensor.numpy() gives."""
        return self.view(np.ndarray)

    def isfinite(self):
        """bool array of the same shape: numpy.isfinite of the values, as Tensor.isfinite()."""
        return np.isfinite(self.view(np.ndarray))


def _answer(a):
    return a.view(_Answer)


def _as_array(value):
    """value as a numpy array: an Open3D Tensor (or anything with .numpy()) through its numpy(), a
    list through numpy.asarray; an array as it is."""
    if not isinstance(value, np.ndarray) and hasattr(value, "numpy"):
        value = value.numpy()
    return np.asarray(value)


def _float_rows(value, name, widths):
    """Rays or query points for the Accel: float32 as they are, another float dtype (float64:
    Open3D code that forgot .astype) rounded to float32, which is what Open3D's RaycastingScene
    computes in; anything else a ValueError naming the argument, its shape and dtype."""
    a = _as_array(value)
    if a.dtype.kind != "f":
        raise ValueError(f"{name}: expected a float array of shape {widths} (float32; other float dtypes are "
                         f"rounded to float32), got shape {a.shape} {a.dtype}")
    return a if a.dtype == np.float32 else a.astype(np.float32)


def _mesh_arrays(mesh):
    """(vertices, triangles) of add_triangles(mesh): a thicket.Scene of triangles, or an Open3D
    t.geometry.TriangleMesh (its vertex positions and triangle indices)."""
    if isinstance(mesh, Scene):
        if mesh.shape_count:
            raise ValueError(f"add_triangles: the scene {mesh.name!r} has {mesh.shape_count} analytic shapes; a "
                             "RaycastingScene holds triangles only (build a thicket.Accel over that Scene instead)")
        return mesh.vertices, mesh.triangles
    if hasattr(mesh, "vertex") and hasattr(mesh, "triangle"):
        try:
            return _as_array(mesh.vertex["positions"]), _as_array(mesh.triangle["indices"])
        except KeyError as e:
            raise ValueError(f"add_triangles: the mesh has no {e} attribute (an Open3D TriangleMesh needs vertex "
                             "positions and triangle indices)") from None
    raise TypeError("add_triangles takes (vertex_positions, triangle_indices) arrays or a mesh (a thicket.Scene or an "
                    f"Open3D t.geometry.TriangleMesh), got {type(mesh).__name__}")


class RaycastingScene:
    """Open3D's RaycastingScene over Thicket: several triangle meshes, each a geometry with its id,
    and Open3D's queries, with Open3D's argument names, defaults, answer keys, dtypes and shapes.

        scene = thicket.RaycastingScene()                # or RaycastingScene(nthreads=0, accel="bvh8")
        cube = scene.add_triangles(vertices, triangles)  # (V, 3) floats, (T, 3) ints -> geometry id 0, 1, ...
        ans = scene.cast_rays(rays)                      # rays (..., 6) float32
        ans["geometry_ids"], ans["primitive_ids"]        # uint32 (...): which mesh, which of its triangles

    Code written for Open3D's RaycastingScene (open3d.t.geometry.RaycastingScene) runs once the
    class comes from thicket (`from thicket import RaycastingScene`): inputs may be numpy arrays,
    lists or Open3D Tensors, and every answer is a numpy array that also has Tensor's .numpy() (the
    array itself, as a plain ndarray) and .isfinite(). Differences from Open3D: float64 inputs
    are rounded to float32 and triangle indices may be of any integer dtype (Open3D refuses both);
    rays may have 8 columns (ox oy oz dx dy dz tmin tmax); any Thicket structure can answer
    (`accel`, a spec string: see thicket.accels()).

    Instances: add_instance(geometry_id, transform) places a geometry again under a (3, 4) or
    (4, 4) affine transform and returns the instance id (0, 1, ...); set_transform(instance_id,
    transform) moves it, and the next query rebuilds only the top level of the two-level
    structure. Every geometry stays drawn where add_triangles put it (as a mesh added to an Open3D
    scene is), an instance being one more copy; answers then also carry instance_ids (uint32, the
    add_instance id of the copy hit, INVALID_ID for a geometry's own copy and for a miss), while
    geometry_ids and primitive_ids name the instanced geometry and its triangle.

    The structure is built on the first query after add_triangles (as Open3D commits its scene),
    over every geometry added so far. set_vertices(geometry_id, vertex_positions) moves a
    geometry's vertices (same triangles); the next query, or refit(), refits the structure (or
    rebuilds it, for a structure that cannot refit). Not for use from several threads at once.
    """

    INVALID_ID = _INVALID
    """geometry_ids and primitive_ids of a miss: 4294967295 (Open3D's RaycastingScene.INVALID_ID)."""

    def __init__(self, nthreads=0, accel=DEFAULT_SPEC):
        """nthreads: threads for refitting (0: one per core); building uses the library's builder
        as thicket.build does. accel: the spec string of the structure (thicket.build's, default
        "bvh8": the fastest traversal, answers closest points itself, and refits); a bad spec is a
        thicket.Error here, not at the first query."""
        self._nthreads = _count_argument(nthreads, "nthreads", "0 (one thread per core) or a thread count")
        if self._nthreads > _INVALID:
            raise ValueError(f"nthreads must be 0 (one thread per core) or a thread count up to {_INVALID}, got {nthreads}")
        if not isinstance(accel, str):
            raise TypeError(f"accel must be a spec string such as 'bvh8', got {type(accel).__name__}")
        self._spec = accel
        # The empty scene's structure: the spec checked now, and what an empty scene answers with.
        self._scene = Scene(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
        self._accel = build(self._scene, accel)
        self._pending = []           # Scenes of the geometries added since the last build, in id order
        self._moved = {}             # geometry id -> float32 vertices set since the last build or refit
        self._first_triangle = [0]   # geometry g's triangles are [first[g], first[g + 1]) of the whole
        self._first_vertex = [0]     # and its vertices [first[g], first[g + 1])
        self._tables = None          # the id translation tables of the built scene (see _local_ids)
        self._instances = []         # (geometry id, float64 (3, 4) transform) per add_instance id
        self._built_instances = 0    # how many of them the structure has (0: it is a plain one)
        self._moved_instances = {}   # instance id -> transform set since the structure was built
        self._flat = None            # closest points with instances: the flattened scene's structure
        self._refit_rebuilds = 0     # moves a rebuild answered because the structure could not refit

    # ----------------------------------------------------------------------------------- building

    def add_triangles(self, vertex_positions=None, triangle_indices=None, mesh=None):
        """add_triangles(vertex_positions, triangle_indices) or add_triangles(mesh) -> int.

        vertex_positions: (V, 3) of any float dtype (stored as float32), every value finite;
        triangle_indices: (T, 3) of any integer dtype (uint32, int32, int64, ...), each index in
        0..V-1; lists and Open3D Tensors are taken too. mesh: a thicket.Scene of triangles, or an
        Open3D t.geometry.TriangleMesh. Returns the new geometry's id: 0 for the first call, then
        1, 2, ... (what geometry_ids answer). The structure is rebuilt on the next query.
        ValueError naming the argument (shape, dtype, a row out of range or not finite), the
        scene unchanged.
        """
        if mesh is not None:
            if vertex_positions is not None or triangle_indices is not None:
                raise TypeError("add_triangles takes either (vertex_positions, triangle_indices) or mesh, not both")
            vertices, triangles = _mesh_arrays(mesh)
        elif triangle_indices is None:
            if vertex_positions is None:
                raise TypeError("add_triangles needs (vertex_positions, triangle_indices) or a mesh")
            vertices, triangles = _mesh_arrays(vertex_positions)
        else:
            vertices, triangles = _as_array(vertex_positions), _as_array(triangle_indices)
        if vertices.dtype.kind == "f" and vertices.dtype.itemsize > 4 and vertices.ndim == 2 and len(vertices):
            # Scene(V, T) checks finiteness before its float32 rounding, which turns a float64
            # beyond float32's range into inf: that is refused here.
            big = np.flatnonzero(~(np.abs(vertices) <= np.finfo(np.float32).max).all(axis=1))
            if big.size:
                raise ValueError(f"add_triangles: vertex_positions row {big[0]} is not finite as float32: "
                                 f"{vertices[big[0]].tolist()}")
        try:
            # Scene(V, T) checks shapes, dtypes, finiteness and every index, and keeps the float32
            # and uint32 copy that the next build concatenates.
            geometry = Scene(vertices, triangles)
        except ValueError as e:
            raise ValueError(f"add_triangles(vertex_positions, triangle_indices): {e}") from None
        triangle_total = self._first_triangle[-1] + geometry.triangle_count
        vertex_total = self._first_vertex[-1] + len(vertices)
        if triangle_total > _MAX_TRIANGLES or vertex_total > _MAX_VERTICES:
            raise ValueError(f"add_triangles: the scene would hold {triangle_total} triangles and {vertex_total} "
                             f"vertices; at most {_MAX_TRIANGLES} and {_MAX_VERTICES} (32-bit ids and indices)")
        self._pending.append(geometry)
        self._first_triangle.append(triangle_total)
        self._first_vertex.append(vertex_total)
        return len(self._first_triangle) - 2

    def add_instance(self, geometry_id, transform):
        """add_instance(geometry_id, transform) -> int. Draws geometry geometry_id once more, placed by
        transform (object to world): a (3, 4) or (4, 4) array-like of numbers, a 4x4's last row
        0 0 0 1. Returns the instance's id: 0 for the first call, then 1, 2, ... (what instance_ids
        answer). The geometry stays drawn where it was added. The structure is rebuilt on the next
        query. ValueError for an id out of range or a bad transform (shape, a non-finite entry, a
        projective last row); thicket.Error for a near-singular one (condition number above 1e4);
        the scene unchanged."""
        count = len(self._first_triangle) - 1
        gid = self._geometry_id(geometry_id, count)
        self._instances.append((gid, self._checked_transform(transform)))
        return len(self._instances) - 1

    def set_transform(self, instance_id, transform):
        """set_transform(instance_id, transform) -> None. Moves instance instance_id (add_instance's id)
        to transform, as add_instance takes it; the next query rebuilds only the top level of the
        structure (the geometries' own structures are kept). Errors as add_instance's, and a
        ValueError for an id out of range; the scene unchanged."""
        count = len(self._instances)
        iid = _count_argument(instance_id, "instance_id", f"an instance id in 0..{count - 1}")
        if iid >= count:
            raise ValueError(f"instance_id must be an instance id in 0..{count - 1}, got {iid}" if count else
                             f"instance_id {iid}: the scene has no instance yet (add_instance first)")
        checked = self._checked_transform(transform)
        self._instances[iid] = (self._instances[iid][0], checked)
        if iid < self._built_instances:
            self._moved_instances[iid] = checked

    @staticmethod
    def _geometry_id(geometry_id, count):
        gid = _count_argument(geometry_id, "geometry_id", f"a geometry id in 0..{count - 1}")
        if gid >= count:
            raise ValueError(f"geometry_id must be a geometry id in 0..{count - 1}, got {gid}" if count else
                             f"geometry_id {gid}: the scene has no geometry yet (add_triangles first)")
        return gid

    @staticmethod
    def _checked_transform(transform):
        """transform as float64 (3, 4), checked now, as the library checks it (Scene.add_instance on a
        one-triangle scene), so that a bad one is refused by the call that gives it."""
        probe = Scene(np.eye(3, dtype=np.float32), np.array([[0, 1, 2]], np.uint32))
        try:
            probe.add_instance(0, _as_array(transform))  # ValueError naming what is wrong
        except Error as e:  # near-singular: the probe's own scene and instance are not the caller's
            raise Error("transform: " + str(e).split(": ", 2)[-1]) from None
        return np.array(_as_array(transform), np.float64)[:3].copy()

    def set_vertices(self, geometry_id, vertex_positions):
        """set_vertices(geometry_id, vertex_positions) -> None. Moves geometry geometry_id's vertices to
        vertex_positions, (N, 3) of any float dtype with N the count it was added with, in that
        order; its triangles keep their indices. The next query (or refit()) brings the structure
        up to date. ValueError for an id out of range, a wrong shape, dtype or count, or a value
        not finite as float32, the scene unchanged."""
        gid = self._geometry_id(geometry_id, len(self._first_triangle) - 1)
        v = _as_array(vertex_positions)
        want = self._first_vertex[gid + 1] - self._first_vertex[gid]
        if v.ndim != 2 or v.shape[1] != 3 or v.dtype.kind != "f":
            raise ValueError(f"vertex_positions: expected a float array of shape (N, 3), got shape {v.shape} {v.dtype}")
        if v.shape[0] != want:
            raise ValueError(f"vertex_positions: {v.shape[0]} rows given, geometry {gid} has {want} vertices (moving "
                             "vertices keeps the triangles: same count, same order)")
        with np.errstate(over="ignore"):  # float64 beyond float32's range becomes inf, refused next
            moved = np.array(v, np.float32)
        bad = np.flatnonzero(~np.isfinite(moved).all(axis=1))
        if bad.size:
            raise ValueError(f"vertex_positions: row {bad[0]} is not finite as float32: {v[bad[0]].tolist()}")
        self._moved[gid] = moved

    @property
    def refit_rebuilds(self):
        """int: how many times bringing the structure up to date after set_vertices rebuilt it
        instead of refitting it, because the structure cannot refit (see thicket.accels()) or
        said it could not take that move; each is also logged at INFO level on the "thicket"
        logger. Never raised: the answers are the moved scene's either way."""
        return self._refit_rebuilds

    def refit(self):
        """refit() -> None. Brings the structure up to date now rather than at the next query:
        after set_vertices, refits it (Accel.refit: the same tree, its boxes recomputed, the answers
        a rebuild's), or rebuilds it when the structure cannot refit (see thicket.accels()); after
        add_triangles, builds it over every geometry."""
        self._current()

    def _current(self):
        """The structure, brought up to date with every add_triangles and set_vertices."""
        # A scene of vertices without triangles has no geometry to move in place (Scene.set_vertices
        # refuses it): it is made again, as after add_triangles.
        if (self._pending or (self._moved and (self._instances or not self._scene.triangle_count))
                or len(self._instances) != self._built_instances):
            # An instanced structure cannot refit (moved vertices): it is built again.
            self._rebuild()
        elif self._moved_instances:
            plain = len(self._first_triangle) - 1  # the identity instances come first (_build_instanced)
            for iid, transform in sorted(self._moved_instances.items()):
                self._accel.set_transform(plain + iid, transform)
            self._moved_instances, self._flat = {}, None
        elif self._moved:
            vertices = self._scene.vertices
            self._apply_moves(vertices)
            self._scene.set_vertices(0, vertices)
            reason = "the structure does not refit"
            if self._accel.refittable:
                try:
                    self._accel.refit(self._scene, nthreads=self._nthreads)
                    reason = None
                except Error as e:  # the structure said it cannot take this move: built again
                    reason = str(e)
            if reason is not None:
                self._accel = build(self._scene, self._spec)
                self._refit_rebuilds += 1
                _log.info("RaycastingScene: rebuilt %r instead of refitting (%s)", self._spec, reason)
            self._moved = {}
        return self._accel

    def _apply_moves(self, vertices):
        for gid, moved in self._moved.items():
            vertices[self._first_vertex[gid]:self._first_vertex[gid + 1]] = moved

    def _rebuild(self):
        parts = [self._scene] + self._pending  # the built geometries, then the new ones
        vertices = np.concatenate([p.vertices for p in parts])
        # Each part's indices are its own: offset by the vertices before it (in uint32, as
        # add_triangles keeps the total within 2^32).
        starts = np.cumsum([0] + [len(p.vertices) for p in parts[:-1]])
        triangles = np.concatenate([p.triangles + np.uint32(s) for p, s in zip(parts, starts)])
        self._apply_moves(vertices)
        scene = Scene(vertices, triangles)
        accel = self._build_instanced(scene) if self._instances else build(scene, self._spec)
        # Only once both exist: a MemoryError above leaves the scene as it was, still to be built.
        self._scene, self._accel = scene, accel
        self._pending, self._moved = [], {}
        self._built_instances, self._moved_instances, self._flat = len(self._instances), {}, None
        self._tables = self._id_tables()

    def _geometry_arrays(self, scene, gid):
        """(vertices, triangles) of geometry gid of the combined scene, its indices from 0."""
        v0, v1 = self._first_vertex[gid], self._first_vertex[gid + 1]
        t0, t1 = self._first_triangle[gid], self._first_triangle[gid + 1]
        return scene.vertices[v0:v1], scene.triangles[t0:t1] - np.uint32(v0)

    def _build_instanced(self, scene):
        """The two-level structure: every geometry a prototype, drawn in place by an identity
        instance (instances 0..G-1, so that add_triangles' geometries stay drawn), then the
        add_instance ones (G + instance id)."""
        count = len(self._first_triangle) - 1
        top = Scene(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32))
        for gid in range(count):
            top.add_geometry(Scene(*self._geometry_arrays(scene, gid)))
        for gid in range(count):
            top.add_instance(gid, _IDENTITY)
        for gid, transform in self._instances:
            top.add_instance(gid, transform)
        return build(top, self._spec)

    def _flattened(self):
        """For closest points with instances (which the two-level structure does not answer): a
        structure over every instance's triangles transformed, instance by instance as the
        two-level structure numbers its primitives, so that its ids are the same flattened ids."""
        if self._flat is None:
            count = len(self._first_triangle) - 1
            places = [(gid, _IDENTITY) for gid in range(count)] + list(self._instances)
            vertices, triangles, base = [], [], 0
            for gid, transform in places:
                v, t = self._geometry_arrays(self._scene, gid)
                # float32 products, as the library carries points (Affine::point)
                m = transform.astype(np.float32)
                vertices.append(v @ m[:, :3].T + m[:, 3])
                triangles.append(t + np.uint32(base))
                base += len(v)
            self._flat = build(Scene(np.concatenate(vertices), np.concatenate(triangles)), self._spec)
        return self._flat

    def _id_tables(self):
        """(ends, geometry_of, first_of) for _local_ids: ends holds each geometry's end in the
        scene-wide ids; entry G of the two others (G geometries) is a miss's."""
        if len(self._first_triangle) <= 2:
            return None  # one geometry (or none): scene-wide ids are the geometry's own
        first = np.array(self._first_triangle, np.uint32)
        count = len(first) - 1
        geometry_of = np.append(np.arange(count, dtype=np.uint32), np.uint32(_INVALID))
        first_of = np.append(first[:-1], np.uint32(0))
        return first[1:], geometry_of, first_of

    def _local_ids(self, answer):
        """Replaces answer's geometry_ids and scene-wide primitive_ids by the geometry of each and
        the id within it (a miss's INVALID_ID stays), as Open3D numbers them; with instances, the
        flattened ids by the prototype's and adds instance_ids."""
        if self._built_instances:
            where = self._accel.locate(answer["primitive_ids"])
            instance = where["instance_ids"]
            plain = np.uint32(len(self._first_triangle) - 1)
            # A geometry's own copy (identity instance < plain) and a miss are no add_instance's.
            answer["instance_ids"] = np.where((instance >= plain) & (instance != _INVALID), instance - plain,
                                              np.uint32(_INVALID)).astype(np.uint32)
            answer["geometry_ids"] = where["geometry_ids"]
            answer["primitive_ids"] = where["primitive_ids"]
            return
        if self._tables is None:
            return
        ends, geometry_of, first_of = self._tables
        prims = answer["primitive_ids"]
        # ends[g - 1] <= p < ends[g]: p's geometry is the count of ends <= p (empty geometries
        # share their end with the one before), G for a miss's INVALID_ID, beyond every end.
        g = np.searchsorted(ends, prims, side="right")
        answer["geometry_ids"] = geometry_of[g]
        answer["primitive_ids"] = prims - first_of[g]

    # ------------------------------------------------------------------------------------ queries

    @staticmethod
    def _answers(answer):
        return {key: _answer(value) for key, value in answer.items()}

    def cast_rays(self, rays, nthreads=0):
        """cast_rays(rays, nthreads=0) -> dict. rays: float32 (..., 6) ox oy oz dx dy dz (the direction
        need not be unit: t_hit is in its lengths), or (..., 8) with a per-ray [tmin, tmax]. The
        closest hit of each: t_hit float32 (...) (inf on a miss), geometry_ids uint32 (...) (the
        add_triangles id), primitive_ids uint32 (...) (the triangle's index within its geometry;
        both INVALID_ID on a miss), primitive_uvs float32 (..., 2) (barycentric u, v),
        primitive_normals float32 (..., 3) (the unit face normal). nthreads: 0, one per core."""
        answer = self._current().cast_rays(_float_rows(rays, "rays", "(..., 6)"), nthreads=nthreads)
        self._local_ids(answer)
        return self._answers(answer)

    def test_occlusions(self, rays, tnear=0.0, tfar=float("inf"), nthreads=0):
        """test_occlusions(rays, tnear=0.0, tfar=inf, nthreads=0) -> bool (...). rays: float32 (..., 6).
        Whether each ray meets anything with tnear <= t <= tfar (rays of 8 columns: their own
        interval, and tnear/tfar left at their defaults)."""
        a = _float_rows(rays, "rays", "(..., 6)")
        interval = {}
        if not (a.ndim and a.shape[-1] == 8 and tnear == 0.0 and tfar == float("inf")):
            interval = {"tnear": tnear, "tfar": tfar}
        return _answer(self._current().test_occlusions(a, nthreads=nthreads, **interval))

    def count_intersections(self, rays, nthreads=0):
        """count_intersections(rays, nthreads=0) -> int32 (...). rays: float32 (..., 6). The surface
        crossings of each ray over every geometry (an edge or vertex shared by triangles of one
        crossing counts once)."""
        return _answer(self._current().count_intersections(_float_rows(rays, "rays", "(..., 6)"), nthreads=nthreads))

    def list_intersections(self, rays, nthreads=0):
        """list_intersections(rays, nthreads=0) -> dict. rays: float32 (..., 6), N of them taken in
        row order. Every crossing, sorted by t per ray (Open3D 0.17's layout): ray_splits uint32
        (N + 1,) (ray i's crossings are [ray_splits[i], ray_splits[i + 1])), ray_ids uint32 (M,),
        t_hit float32 (M,), geometry_ids uint32 (M,), primitive_ids uint32 (M,) (within the
        geometry), primitive_uvs float32 (M, 2)."""
        answer = self._current().list_intersections(_float_rows(rays, "rays", "(..., 6)"), nthreads=nthreads)
        self._local_ids(answer)
        return self._answers(answer)

    def compute_closest_points(self, query_points, nthreads=0):
        """compute_closest_points(query_points, nthreads=0) -> dict. query_points: float32 (..., 3),
        finite. The closest surface point of each over every geometry: points float32 (..., 3),
        geometry_ids uint32 (...), primitive_ids uint32 (...) (within the geometry; INVALID_ID
        for an empty scene), primitive_uvs float32 (..., 2), primitive_normals float32 (..., 3)."""
        answer = self._point_accel().compute_closest_points(_float_rows(query_points, "query_points", "(..., 3)"),
                                                            nthreads=nthreads)
        self._local_ids(answer)
        return self._answers(answer)

    def compute_distance(self, query_points, nthreads=0):
        """compute_distance(query_points, nthreads=0) -> float32 (...). query_points: float32 (..., 3).
        Distance to the closest surface point (inf for an empty scene)."""
        points = _float_rows(query_points, "query_points", "(..., 3)")
        return _answer(self._point_accel().compute_distance(points, nthreads=nthreads))

    def compute_signed_distance(self, query_points, nthreads=0, nsamples=1):
        """compute_signed_distance(query_points, nthreads=0, nsamples=1) -> float32 (...).
        query_points: float32 (..., 3). compute_distance, negative inside (by compute_occupancy:
        the meshes are taken to be closed and not to intersect one another, as Open3D does)."""
        points = _float_rows(query_points, "query_points", "(..., 3)")
        return _answer(self._point_accel().compute_signed_distance(points, nthreads=nthreads, nsamples=nsamples))

    def compute_occupancy(self, query_points, nthreads=0, nsamples=1):
        """compute_occupancy(query_points, nthreads=0, nsamples=1) -> float32 (...). query_points:
        float32 (..., 3). 1 inside, 0 outside, by the parity of crossings over every geometry
        along nsamples (odd, up to 5) directions, the majority deciding."""
        points = _float_rows(query_points, "query_points", "(..., 3)")
        return _answer(self._current().compute_occupancy(points, nthreads=nthreads, nsamples=nsamples))

    def _point_accel(self):
        """The structure that answers closest points: the flattened one with instances."""
        accel = self._current()
        return self._flattened() if self._built_instances else accel

    @staticmethod
    def create_rays_pinhole(*args, **kwargs):
        """create_rays_pinhole(fov_deg, center, eye, up, width_px, height_px) or
        create_rays_pinhole(intrinsic_matrix, extrinsic_matrix, width_px, height_px) -> float32
        (height_px, width_px, 6): thicket.create_rays_pinhole (Open3D's rays, same numbers)."""
        return _answer(_create_rays_pinhole(*args, **kwargs))

    def __repr__(self):
        count = len(self._first_triangle) - 1
        instances = f", {len(self._instances)} instances" if self._instances else ""
        return (f"<thicket.RaycastingScene: {count} geometr{'y' if count == 1 else 'ies'}{instances}, "
                f"{self._first_triangle[-1]} triangles, '{self._spec.split(':')[0]}'>")
