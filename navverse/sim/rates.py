"""The simulation's clock rates, in a module of their own so that code that only counts ticks (a
recorder, a termination monitor) imports no physics engine."""

from __future__ import annotations

__all__ = ["CONTROL_HZ", "PHYSICS_HZ"]

PHYSICS_HZ = 200
"""Physics steps per simulated second."""
CONTROL_HZ = 50
"""Controller updates per simulated second (every PHYSICS_HZ // CONTROL_HZ physics steps)."""
