"""The physics runtime: a built scene in PyBullet, robots, the low-level controller, actions, the camera.

Modules, from the bottom up: ``bullet`` (PyBullet without its banners), ``collision`` (convex pieces of
objects), ``world`` (a scene as static bodies, contacts, rays), ``embodiment`` (the robot protocol and
its helpers), ``spot`` and ``turtlebot``, ``embodiments`` (the registry of robots by name),
``simulator`` (a robot in a world, ticked at 50 Hz), ``controller`` (waypoint tracking and PID),
``actions`` (discrete, waypoint and velocity actions), ``terminations``, ``rollout`` (following a
reference path), ``recorder`` (submission records), and ``camera`` / ``render`` (the ray-cast RGB-D and
semantic camera). The agent-facing Gymnasium
environment is :mod:`navverse.env`.
"""
