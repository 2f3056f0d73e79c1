"""A built scene in PyBullet: static terrain per class with its friction, static objects, contacts.

Every terrain class is one static body (a concave triangle mesh of all its surfaces) with the class's
friction, so a contact tells which surface it is on. The objects of each 300 m square of ground
(:data:`OBJECT_TILE`; a building is one) are one static body, a compound of the convex pieces of
every object (:mod:`navverse.sim.collision`); contacts and ray hits on it are attributed to the
object whose box holds the point (:meth:`World.object_at`). PyBullet multiplies the frictions of
two touching bodies, so robots use friction 1 on their feet and wheels: the terrain's value is the
contact's.

The world runs in its own DIRECT client (several worlds can live in one process) at
:data:`PHYSICS_HZ`; :meth:`World.step` advances one physics step.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from navverse.scene.directory import read_scene
from navverse.scene.geometry import MeshData, Scene
from navverse.sim.bullet import connect, pybullet
from navverse.sim.collision import convex_parts, default_cache_dir, hulls_file
from navverse.sim.rates import CONTROL_HZ, PHYSICS_HZ

__all__ = [
    "CONTROL_HZ",
    "GRAVITY",
    "OBJECT_FRICTION",
    "OBJECT_TILE",
    "PHYSICS_HZ",
    "BodyInfo",
    "Contact",
    "World",
    "objects_near",
]

GRAVITY = 9.81
OBJECT_FRICTION = 0.6
"""Friction of objects (furniture); terrain classes carry their own."""
OBJECT_TILE = 300.0
"""Side of the ground squares whose objects make one static compound body (m)."""


MESH_MAX_VERTICES = 131_072
"""Most vertices PyBullet takes in one mesh shape given by arrays."""
MESH_MAX_FACES = 174_762
"""Most triangles PyBullet takes in one mesh shape given by arrays (its index limit is 524,288)."""


def mesh_pieces(mesh: MeshData) -> list[MeshData]:
    """``mesh`` cut into runs of its faces, each within :data:`MESH_MAX_VERTICES` and
    :data:`MESH_MAX_FACES`, each with only the vertices it uses (a city's draped ground on hills
    holds more than one shape may)."""
    if mesh.num_faces <= MESH_MAX_FACES and len(mesh.vertices) <= MESH_MAX_VERTICES:
        return [mesh]
    pieces, pending = [], [mesh.faces]
    while pending:
        faces = pending.pop()
        used, local = np.unique(faces, return_inverse=True)
        if len(faces) <= MESH_MAX_FACES and len(used) <= MESH_MAX_VERTICES:
            pieces.append(MeshData(mesh.vertices[used], local.reshape(-1, 3)))
        else:
            half = len(faces) // 2
            pending += [faces[half:], faces[:half]]
    return pieces


@dataclass(frozen=True)
class BodyInfo:
    """What a static body of the world is: a terrain class or an object."""

    kind: str  # "terrain" or "object"
    terrain_class: str | None = None
    object_id: int | None = None
    category: str | None = None
    navigable: bool = False
    friction: float = OBJECT_FRICTION


@dataclass(frozen=True)
class Contact:
    """A contact between a robot link and a static body of the world."""

    link: int  # the robot's link index (-1: base)
    body: BodyInfo
    position: tuple[float, float, float]  # on the world body
    normal: tuple[float, float, float]  # from the world body towards the robot
    force: float  # normal force (N)


def objects_near(scene: Scene, paths: Sequence[ArrayLike], *, margin: float) -> set[int]:
    """Ids of the scene's objects whose box comes within ``margin`` (m, horizontally) of a path.

    Parameters
    ----------
    scene : Scene
        The scene.
    paths : sequence of array_like, shape (K, 2) or (K, 3)
        Polylines (a single point is a path too).
    margin : float
        Horizontal distance (m) from a path to an object's box (the circle around its footprint).

    Returns
    -------
    set of int
        Object ids (:attr:`ObjectAnnotation.id`).
    """
    annotations = [obj.annotation for obj in scene.objects]
    if not annotations or not paths:
        return set()
    centers = np.array([a.center[:2] for a in annotations], dtype=float)
    reach = np.hypot(*np.array([a.size[:2] for a in annotations], dtype=float).T) / 2.0 + margin
    near = np.zeros(len(annotations), dtype=bool)
    for path in paths:
        points = np.asarray(path, dtype=float).reshape(-1, np.shape(path)[-1])[:, :2]
        starts, ends = points[:-1] if len(points) > 1 else points, points[1:] if len(points) > 1 else points
        segment = ends - starts
        length2 = np.einsum("ij,ij->i", segment, segment)
        offset = centers[:, None, :] - starts[None, :, :]
        along = np.clip(
            np.einsum("nmk,mk->nm", offset, segment) / np.where(length2 > 0.0, length2, 1.0), 0.0, 1.0
        )
        gap = offset - along[..., None] * segment[None, :, :]
        near |= (np.einsum("nmk,nmk->nm", gap, gap) <= (reach * reach)[:, None]).any(axis=1)
    return {annotations[i].id for i in np.flatnonzero(near)}


class World:
    """A scene loaded into its own PyBullet client.

    Parameters
    ----------
    scene : Scene or path
        The scene, or a built scene directory.
    collision_cache : Path or None, optional
        Directory where convex decompositions of concave object parts are cached (default
        :func:`~navverse.sim.collision.default_cache_dir`; None keeps them in memory only).
    terrain_friction : float, optional
        Friction coefficient given to every terrain class instead of its own (the friction diagnostic
        of the paper's kinodynamics table); None keeps the scene's values.
    object_ids : collection of int, optional
        The scene objects given collision geometry (see :func:`objects_near`); None: every object.
        Contacts and ray hits are still attributed among all of the scene's objects.

    Attributes
    ----------
    bodies : dict of int to BodyInfo
        The static bodies: one per terrain class, and the objects' compound (``kind="object"``
        without an id; :meth:`contacts` and :meth:`surface_below` name the object itself).
    objects : list of BodyInfo
        One per scene object, in the scene's order.
    object_bodies : tuple of int
        The objects' compound bodies, one per :data:`OBJECT_TILE` square of the ground that holds
        objects (one for a building; none when the scene has no objects).
    """

    def __init__(
        self,
        scene: Scene | str | os.PathLike[str],
        *,
        collision_cache: Path | str | None = "default",
        terrain_friction: float | None = None,
        object_ids: Collection[int] | None = None,
    ) -> None:
        if terrain_friction is not None and not (math.isfinite(terrain_friction) and terrain_friction >= 0.0):
            raise ValueError(f"terrain_friction must be a finite number >= 0, got {terrain_friction!r}")
        self.terrain_friction = terrain_friction
        self.scene = scene if isinstance(scene, Scene) else read_scene(Path(scene))
        self.client = connect()
        c = self.client
        c.setGravity(0.0, 0.0, -GRAVITY)
        c.setTimeStep(1.0 / PHYSICS_HZ)
        c.setPhysicsEngineParameter(deterministicOverlappingPairs=1, numSolverIterations=20)
        # Bound client functions: the client builds a new partial on every attribute access.
        self._step_simulation = c.stepSimulation
        self._contact_points = c.getContactPoints
        self.bodies: dict[int, BodyInfo] = {}
        self.time = 0.0
        self.steps = 0
        self._load_terrain()
        self._load_objects(
            default_cache_dir() if collision_cache == "default" else collision_cache,
            None if object_ids is None else frozenset(object_ids),
        )
        bounds = self.scene.annotations.bounds
        self.bounds = (np.asarray(bounds.min, dtype=float), np.asarray(bounds.max, dtype=float))

    # ------------------------------------------------------------------ loading

    def _static_mesh_bodies(self, mesh: MeshData, info: BodyInfo) -> list[int]:
        """Static triangle-mesh bodies of ``mesh``: one per piece within PyBullet's mesh limits."""
        c = self.client
        bodies = []
        for piece in mesh_pieces(mesh):
            shape = c.createCollisionShape(
                pybullet.GEOM_MESH,
                vertices=piece.vertices.tolist(),
                indices=piece.faces.reshape(-1).tolist(),
                flags=pybullet.GEOM_FORCE_CONCAVE_TRIMESH,
            )
            body = c.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape)
            c.changeDynamics(body, -1, lateralFriction=info.friction, restitution=0.0, rollingFriction=0.0,
                             spinningFriction=0.0)  # fmt: skip
            self.bodies[body] = info
            bodies.append(body)
        return bodies

    def _load_terrain(self) -> None:
        classes = self.scene.annotations.terrain_classes
        by_class: dict[str, list[MeshData]] = {}
        for surface in self.scene.surfaces:
            by_class.setdefault(surface.terrain_class, []).append(surface.mesh)
        for name, meshes in by_class.items():
            tc = classes[name]
            mesh = MeshData.concatenate(meshes)
            if mesh.num_faces == 0:
                continue
            friction = tc.friction if self.terrain_friction is None else self.terrain_friction
            self._static_mesh_bodies(
                mesh, BodyInfo("terrain", terrain_class=name, navigable=tc.navigable, friction=friction)
            )

    def _load_objects(self, cache: Path | None, only: frozenset[int] | None) -> None:
        # The objects are static compounds of every convex piece in world coordinates, one per
        # OBJECT_TILE square: Bullet refreshes the bounds of every body each step, static ones
        # included, so a body per object would cost more than the robot's own physics in a
        # furnished building; and one compound for a whole city makes every contact of a robot
        # with several links walk a compound spanning the city (a populated km² stepped 5 times
        # slower with the TurtleBot). Which object a contact or a ray touches is found from the
        # objects' boxes (:meth:`object_at`).
        annotations = [obj.annotation for obj in self.scene.objects]
        self.objects = [BodyInfo("object", object_id=a.id, category=a.category) for a in annotations]
        self._object_center = np.array([a.center for a in annotations], dtype=float).reshape(-1, 3)
        self._object_half = np.array([a.size for a in annotations], dtype=float).reshape(-1, 3) / 2.0
        self._object_yaw = np.array([a.yaw for a in annotations], dtype=float)
        self.object_bodies: tuple[int, ...] = ()
        tiles: dict[tuple[int, int], list[np.ndarray]] = {}
        for obj, center, yaw in zip(self.scene.objects, self._object_center, self._object_yaw, strict=True):
            if only is not None and obj.annotation.id not in only:
                continue
            c, s = math.cos(yaw), math.sin(yaw)
            rotation_t = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # row vectors @ R.T
            key = (math.floor(center[0] / OBJECT_TILE), math.floor(center[1] / OBJECT_TILE))
            tiles.setdefault(key, []).extend(
                part @ rotation_t + center for part in convex_parts(obj.mesh, cache_dir=cache)
            )
        if not any(tiles.values()):
            return
        if cache is None or only is not None:  # a subset's hulls would only fill the cache
            self._scratch = tempfile.TemporaryDirectory(prefix="navverse-hulls-")
            directory = Path(self._scratch.name)
        else:
            directory = cache / "hulls"
        bodies = []
        for _, hulls in sorted(tiles.items()):
            if not hulls:
                continue
            shape = self.client.createCollisionShape(
                pybullet.GEOM_MESH, fileName=str(hulls_file(hulls, directory))
            )
            body = self.client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape)
            self.client.changeDynamics(body, -1, lateralFriction=OBJECT_FRICTION, restitution=0.0)
            self.bodies[body] = BodyInfo("object", friction=OBJECT_FRICTION)
            bodies.append(body)
        self.object_bodies = tuple(bodies)

    def object_at(self, point: Sequence[float]) -> BodyInfo:
        """The object whose box contains (or, failing that, is nearest to) a point on the objects' body."""
        offset = np.asarray(point, dtype=float) - self._object_center
        c, s = np.cos(self._object_yaw), np.sin(self._object_yaw)
        x, y = offset[:, 0], offset[:, 1]
        local = np.stack([c * x + s * y, -s * x + c * y, offset[:, 2]], axis=1)
        outside = np.maximum(np.abs(local) - self._object_half, 0.0)
        return self.objects[int(np.argmin(np.einsum("ij,ij->i", outside, outside)))]

    def _resolve(self, body: int, point: Sequence[float]) -> BodyInfo | None:
        """What a static body is at a point of it (for the objects' body: the object there)."""
        if body in self.object_bodies:
            return self.object_at(point)
        return self.bodies.get(body)

    # ------------------------------------------------------------------ stepping and queries

    def step(self) -> None:
        """Advance the simulation by one physics step."""
        self._step_simulation()
        self.steps += 1
        self.time = self.steps / PHYSICS_HZ

    def contacts(self, robot: int) -> list[Contact]:
        """Contacts of a robot body (every link) with the world's static bodies."""
        found = []
        for point in self._contact_points(bodyA=robot):
            info = self._resolve(point[2], point[6])
            if info is not None:
                found.append(Contact(point[3], info, point[6], point[7], point[9]))
        return found

    def surface_below(
        self, position: Sequence[float], *, depth: float = 2.0
    ) -> tuple[BodyInfo | None, float]:
        """The static body straight below ``position`` (within ``depth``) and the height of its surface.

        Robots and other bodies that are not part of the scene are looked through.
        """
        x, y, z = (float(v) for v in position)
        top, bottom = z + 0.05, z - depth
        while top > bottom:  # look through robots and other dynamic bodies
            hit = self.client.rayTest((x, y, top), (x, y, bottom))[0]
            if hit[0] < 0:
                break
            info = self._resolve(hit[0], hit[3])
            if info is not None:
                return info, float(hit[3][2])
            top = float(hit[3][2]) - 1e-4
        return None, math.nan

    def ray_batch(self, starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cast rays: (hit fraction (K,) with 1 for no hit, hit points (K, 3), hit body ids (K,) or -1)."""
        hits = self.client.rayTestBatch(starts.tolist(), ends.tolist())
        fraction = np.array([h[2] if h[0] >= 0 else 1.0 for h in hits])
        points = np.array([h[3] for h in hits], dtype=float)
        bodies = np.array([h[0] for h in hits], dtype=np.int64)
        return fraction, points, bodies

    def inside_bounds(self, position: Sequence[float], *, margin: float = 2.0) -> bool:
        """Whether a point is within the scene's bounds (plus ``margin`` m horizontally, any height above)."""
        p = np.asarray(position, dtype=float)
        lo, hi = self.bounds
        return bool(
            lo[0] - margin <= p[0] <= hi[0] + margin
            and lo[1] - margin <= p[1] <= hi[1] + margin
            and p[2] >= lo[2] - margin
        )

    def close(self) -> None:
        """Disconnect the physics client (and drop temporary hull files)."""
        if self.client is not None:
            self.client.disconnect()
            self.client = None  # type: ignore[assignment]
        scratch = getattr(self, "_scratch", None)
        if scratch is not None:
            scratch.cleanup()

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
