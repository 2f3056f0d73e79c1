"""A scene in PyBullet: terrain per class with its friction, objects as convex compounds, queries."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.assets.library import make_object
from navverse.scene.compose import ObjectPart, replace_parts
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.sim.bullet import pybullet
from navverse.sim.collision import convex_parts
from navverse.sim.world import MESH_MAX_FACES, MESH_MAX_VERTICES, PHYSICS_HZ, World, mesh_pieces, objects_near
from tests.scenes import box_part, scene_of


def small_scene() -> Scene:
    """A floor, a road strip, a wall and two objects: a bathtub (concave, id 1) and a box table (id 2)."""
    tub_mesh, tub_size = make_object("bathtub", np.random.default_rng(3))
    objects = [
        ObjectPart("bathtub", tub_mesh, (2.0, 2.0, tub_size[2] / 2), 0.3),
        box_part("table", (6.0, 2.0, 0.375), (1.2, 0.8, 0.75)),
    ]
    surfaces = (
        Surface("floor", "floor", MeshData.box((10.0, 4.0, 0.1), center=(5.0, 2.0, -0.05))),
        Surface("road", "road", MeshData.box((10.0, 2.0, 0.1), center=(5.0, -1.0, -0.05))),
        Surface("wall", "wall", MeshData.box((0.2, 6.0, 2.5), center=(10.1, 1.0, 1.25))),
    )
    return scene_of(surfaces, objects, scene_id="small", friction={"road": 0.4})


@pytest.fixture(scope="module")
def world(tmp_path_factory: pytest.TempPathFactory):
    with World(small_scene(), collision_cache=tmp_path_factory.mktemp("coacd")) as w:
        yield w


def _drop_box(world: World, position) -> int:
    c = world.client
    shape = c.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[0.1, 0.1, 0.1])
    return c.createMultiBody(baseMass=1.0, baseCollisionShapeIndex=shape, basePosition=position)


def test_terrain_bodies_carry_their_class_and_friction(world: World):
    terrain = {
        info.terrain_class: (body, info) for body, info in world.bodies.items() if info.kind == "terrain"
    }
    assert set(terrain) == {"floor", "road", "wall"}
    for name, friction, navigable in (("floor", 0.9, True), ("road", 0.4, True), ("wall", 0.6, False)):
        body, info = terrain[name]
        assert info.friction == pytest.approx(friction) and info.navigable is navigable
        assert world.client.getDynamicsInfo(body, -1)[1] == pytest.approx(friction)  # lateral friction
    assert [info.object_id for info in world.objects] == [1, 2]
    # The objects are one compound body (a building is within one tile); a point on each is
    # attributed to the right object.
    assert len(world.object_bodies) == 1 and world.bodies[world.object_bodies[0]].kind == "object"
    assert world.object_at([6.0, 2.0, 0.75]).object_id == 2
    assert world.object_at([2.0, 2.0, 0.1]).category == "bathtub"


def test_surface_below_and_bounds(world: World):
    info, height = world.surface_below([5.0, -1.0, 1.0])
    assert info.terrain_class == "road" and height == pytest.approx(0.0, abs=1e-6)
    info, height = world.surface_below([6.0, 2.0, 2.0])
    assert info.kind == "object" and info.object_id == 2 and height == pytest.approx(0.75, abs=1e-3)
    assert world.surface_below([50.0, 50.0, 1.0])[0] is None
    assert world.inside_bounds([5.0, 1.0, 0.3]) and not world.inside_bounds([30.0, 1.0, 0.3])


def test_a_falling_box_lands_and_reports_its_contacts(world: World):
    box = _drop_box(world, [6.0, 2.0, 1.5])  # onto the table
    for _ in range(PHYSICS_HZ):
        world.step()
    position, _ = world.client.getBasePositionAndOrientation(box)
    assert position[2] == pytest.approx(0.85, abs=0.01)  # resting on the 0.75 m top
    contacts = world.contacts(box)
    assert contacts and all(c.body.object_id == 2 for c in contacts)
    assert sum(c.force for c in contacts) == pytest.approx(9.81, rel=0.05)
    world.client.removeBody(box)


def test_the_bathtub_is_hollow_for_physics(world: World):
    # The tub's concave shell is decomposed: a box dropped into the basin sinks below the rim.
    tub = next(o for o in world.scene.objects if o.annotation.category == "bathtub")
    parts = convex_parts(tub.mesh)
    assert len(parts) > 3
    rim = tub.annotation.center[2] + tub.annotation.size[2] / 2
    box = _drop_box(world, [tub.annotation.center[0], tub.annotation.center[1], rim + 0.3])
    for _ in range(PHYSICS_HZ):
        world.step()
    assert world.client.getBasePositionAndOrientation(box)[0][2] < rim - 0.15
    world.client.removeBody(box)


def test_decompositions_are_cached_on_disk(tmp_path):
    tub, _ = make_object("bathtub", np.random.default_rng(11))
    first = convex_parts(tub, cache_dir=tmp_path)
    assert list(tmp_path.glob("*.npz"))
    again = convex_parts(tub, cache_dir=tmp_path)
    assert len(first) == len(again) and all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))


def test_same_scene_same_physics():
    def run() -> tuple:
        with World(small_scene(), collision_cache=None) as w:
            box = _drop_box(w, [6.3, 2.2, 1.2])
            w.client.resetBaseVelocity(box, [0.7, 0.1, 0.0])
            for _ in range(PHYSICS_HZ):
                w.step()
            return w.client.getBasePositionAndOrientation(box)

    assert run() == run()


def test_objects_keep_every_convex_piece():
    # A rack of 30 separate posts: 30 convex parts, more than PyBullet's 16 shapes per shape array.
    posts = MeshData.concatenate(
        [MeshData.box((0.1, 0.1, 1.0), center=(0.3 * k - 4.35, 0.0, 0.0)) for k in range(30)]
    )
    rack = ObjectPart("shelf", posts, (5.0, 2.0, 0.5))
    scene = replace_parts(small_scene(), objects=[rack])  # the rack in place of the other objects
    (rack_id,) = (o.id for o in scene.annotations.objects)
    with World(scene, collision_cache=None) as w:
        assert len(convex_parts(posts)) == 30
        box = _drop_box(w, [5.0 + 4.35, 2.0, 1.5])  # onto the last post
        for _ in range(PHYSICS_HZ):
            w.step()
        assert w.client.getBasePositionAndOrientation(box)[0][2] == pytest.approx(1.1, abs=0.01)
        assert {c.body.object_id for c in w.contacts(box)} == {rack_id}


def _l_prism(height: float, arm: float) -> MeshData:
    """A closed L-shaped prism: the unit square minus its ``(1 - arm)``-sided upper right corner, extruded."""
    outline = [(0.0, 0.0), (1.0, 0.0), (1.0, arm), (arm, arm), (arm, 1.0), (0.0, 1.0)]
    ring = len(outline)
    vertices = np.array([(x, y, z) for z in (0.0, height) for x, y in outline])
    bottom = [(0, 2, 1), (0, 3, 2), (0, 4, 3), (0, 5, 4)]  # a fan about the inner corner's opposite
    top = [(ring + a, ring + b, ring + c) for a, c, b in bottom]
    sides = []
    for i in range(ring):
        j = (i + 1) % ring
        sides += [(i, j, ring + j), (i, ring + j, ring + i)]
    return MeshData(vertices, np.array(bottom + top + sides))


@pytest.mark.parametrize(("arm", "decomposed"), [(0.8, False), (0.32, False), (0.2, True)])
def test_a_part_is_decomposed_when_its_hull_is_much_larger(arm: float, decomposed: bool, tmp_path):
    # The L's area is 1 - (1 - arm)^2 and its hull's 1 - (1 - arm)^2 / 2: their ratio is 1.02 for an
    # arm of 0.8, 1.43 for 0.32 (both under 1.5: the hull is kept) and 1.89 for 0.2 (decomposed).
    mesh = _l_prism(0.5, arm)
    parts = convex_parts(mesh, cache_dir=tmp_path)
    if decomposed:  # CoACD's pieces
        assert len(parts) >= 2
    else:
        (hull,) = parts
        # the hull's points are mesh vertices, in the mesh's order
        index = [int(np.flatnonzero((mesh.vertices == p).all(axis=1))[0]) for p in hull]
        assert index == sorted(index) and len(index) == 10  # the inner corner's two vertices are inside
    for piece in parts:
        assert piece.min() >= -1e-6 and piece[:, :2].max() <= 1.0 + 1e-6


def test_parts_are_faces_joined_by_edges_two_faces_share():
    # Two closed boxes touching along an edge line are separate parts; an open box (a missing face)
    # has no volume and keeps its hull, and so does a flat square (a flat hull), after them.
    first = MeshData.box((0.1, 0.1, 0.1), center=(0.0, 0.0, 0.0))
    second = MeshData.box((0.1, 0.1, 0.1), center=(0.1, 0.0, 0.0))
    open_box = MeshData.box((0.4, 0.4, 0.4), center=(2.0, 0.0, 0.0))
    open_box = MeshData(open_box.vertices, open_box.faces[2:])
    corners = np.array([[5.0, 0, 0], [6.0, 0, 0], [6.0, 1, 0], [5.0, 1, 0]])
    square = MeshData(corners, np.array([[0, 1, 2], [0, 2, 3]]))
    parts = convex_parts(MeshData.concatenate([first, second, open_box, square]))
    assert [len(p) for p in parts] == [8, 8, 8, 4]
    np.testing.assert_array_equal(parts[3], corners)
    assert parts[0][:, 0].max() == pytest.approx(0.05) and parts[1][:, 0].min() == pytest.approx(0.05)


def test_objects_near_paths():
    scene = small_scene()  # the bathtub (id 1) at (2, 2), the table (id 2) at (6, 2), 1.2 x 0.8 m
    assert objects_near(scene, [np.array([[6.0, -3.0, 0.0], [6.0, -1.0, 0.0]])], margin=1.0) == set()
    assert objects_near(scene, [np.array([[6.0, -3.0, 0.0], [6.0, -1.0, 0.0]])], margin=2.5) == {2}
    assert objects_near(scene, [np.array([[2.0, 2.0]])], margin=1.0) == {1}  # one point
    assert objects_near(scene, [np.array([[0.0, 4.0], [9.0, 4.0]])], margin=2.5) == {1, 2}
    assert objects_near(scene, [], margin=5.0) == set()


def test_a_world_of_some_objects_loads_only_their_geometry():
    # The table alone: a box dropped on it lands on its top, one dropped on the bathtub falls through
    # to the floor; contacts are still attributed among every object.
    with World(small_scene(), collision_cache=None, object_ids={2}) as w:
        assert [info.object_id for info in w.objects] == [1, 2]
        on_table, on_tub = _drop_box(w, [6.0, 2.0, 1.5]), _drop_box(w, [2.0, 2.0, 1.5])
        for _ in range(PHYSICS_HZ):
            w.step()
        assert w.client.getBasePositionAndOrientation(on_table)[0][2] == pytest.approx(0.85, abs=0.01)
        assert w.client.getBasePositionAndOrientation(on_tub)[0][2] == pytest.approx(0.1, abs=0.01)
        assert {c.body.object_id for c in w.contacts(on_table)} == {2}
    with World(small_scene(), collision_cache=None, object_ids=set()) as w:
        assert w.object_bodies == ()


def _grid_floor(cells: int, size: float) -> MeshData:
    """A flat floor of ``cells`` × ``cells`` squares, two triangles each, ``size`` m across."""
    ticks = np.linspace(0.0, size, cells + 1)
    x, y = np.meshgrid(ticks, ticks)
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    corner = (np.arange(cells)[:, None] * (cells + 1) + np.arange(cells)[None, :]).ravel()
    a, b, c, d = corner, corner + 1, corner + cells + 2, corner + cells + 1
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return MeshData(vertices, faces)


def test_a_terrain_class_beyond_pybullets_mesh_limits_loads_in_pieces() -> None:
    floor = _grid_floor(300, 60.0)  # 180,000 triangles: more than one PyBullet mesh shape holds
    pieces = mesh_pieces(floor)
    assert len(pieces) == 2
    assert all(p.num_faces <= MESH_MAX_FACES and len(p.vertices) <= MESH_MAX_VERTICES for p in pieces)
    # The pieces hold the same triangles, each once.
    triangles = np.sort(np.concatenate([p.vertices[p.faces].reshape(-1, 9) for p in pieces]), axis=0)
    assert np.array_equal(triangles, np.sort(floor.vertices[floor.faces].reshape(-1, 9), axis=0))
    scene = scene_of([Surface("floor", "floor", floor)], scene_id="big-floor")
    with World(scene, collision_cache=None) as big:
        floors = [b for b, info in big.bodies.items() if info.terrain_class == "floor"]
        assert len(floors) == 2
        for x in (5.0, 55.0):  # a ray finds the floor over either piece
            hit = big.client.rayTest([x, 30.0, 1.0], [x, 30.0, -1.0])[0]
            assert hit[0] in floors and hit[3][2] == pytest.approx(0.0, abs=1e-6)
