"""A scene in PyBullet: terrain per class with its friction, objects as convex compounds, queries."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.assets.library import make_object
from navverse.scene.compose import ObjectPart, replace_parts
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.sim.bullet import pybullet
from navverse.sim.collision import convex_parts
from navverse.sim.world import PHYSICS_HZ, World
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
