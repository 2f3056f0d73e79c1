"""The registry of the built-in embodiments: a robot by name.

Two robots are built in: ``"spot"`` (:class:`~navverse.sim.spot.Spot`, a legged robot) and
``"turtlebot"`` (:class:`~navverse.sim.turtlebot.TurtleBot`, a differential-drive robot). Both implement
:class:`~navverse.sim.embodiment.Embodiment`; this module is the only one that names them, so the robots
import the protocol module and never this one.

A loop that drives a robot for one control period::

    robot = make_embodiment("spot")
    robot.spawn(world, (0.0, 0.0, 0.0), yaw=0.0)
    robot.set_command(1.0, 0.0, 0.2)
    for _ in range(PHYSICS_HZ // CONTROL_HZ):
        robot.before_step()
        world.step()

The factories import their robot when called: checking a name against :data:`EMBODIMENTS` (as recipe
validation does) does not load PyBullet.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from types import MappingProxyType

from navverse.errors import NavverseError
from navverse.sim.embodiment import Embodiment

__all__ = ["EMBODIMENTS", "UnknownEmbodimentError", "make_embodiment"]


class UnknownEmbodimentError(NavverseError):
    """An embodiment name that is not registered."""


def _spot() -> Embodiment:
    from navverse.sim.spot import Spot

    return Spot()


def _turtlebot() -> Embodiment:
    from navverse.sim.turtlebot import TurtleBot

    return TurtleBot()


EMBODIMENTS: Mapping[str, Callable[[], Embodiment]] = MappingProxyType(
    {"spot": _spot, "turtlebot": _turtlebot}
)
"""Factories of the built-in embodiments, by name (read-only)."""


def make_embodiment(name: str) -> Embodiment:
    """Create an unspawned embodiment by registry name.

    Parameters
    ----------
    name : str
        A key of :data:`EMBODIMENTS`.

    Returns
    -------
    Embodiment
        The robot, not yet spawned in a world.

    Raises
    ------
    UnknownEmbodimentError
        If `name` is not in :data:`EMBODIMENTS`.
    """
    try:
        factory = EMBODIMENTS[name]
    except KeyError:
        raise UnknownEmbodimentError(
            f"unknown embodiment {name!r}; choose one of: {', '.join(sorted(EMBODIMENTS))}"
        ) from None
    return factory()
