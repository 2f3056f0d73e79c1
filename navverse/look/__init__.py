"""How scenes look: light, sky and materials, an appearance layer kept apart from the geometry.

A scene's look never changes its geometry, its navmesh or its episodes: the look is computed from a
built scene and :class:`~navverse.look.settings.LookSettings` (time of day, sun, exposure, material
variant), used by the camera renderer (:mod:`navverse.sim.render`) for RGB only; depth, instance and
terrain images do not depend on it.

Modules: ``settings.py`` (the settings, one declaration each; the evaluation look; training draws),
``sky.py`` (the sun's position and colour from the time of day and the latitude, the sky's colours
and light), ``rooms.py`` (rooms' lamps, which room a point is in), ``patterns.py`` (lattice hashes,
noise, laid units), ``materials.py`` (the material catalogue and its tiles), ``facades.py`` (windows,
frames, doors, plinths), ``markings.py`` (lane and edge lines from mapped roads), ``scene_look.py``
(a scene's look compiled for the renderer), ``files.py`` (``look.json``; finding a scene's look) and
``usd_look.py`` (the look as a USD layer). Like :mod:`navverse.scene`, this ``__init__`` imports
nothing: names come from their modules.
"""
