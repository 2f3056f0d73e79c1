"""How scenes look: light, sky and materials, an appearance layer kept apart from the geometry.

A scene's look never changes its geometry, its navmesh or its episodes: the look is computed from a
built scene and :class:`~navverse.look.settings.LookSettings` (time of day, sun, exposure, material
variant), used by the camera renderer (:mod:`navverse.sim.render`) for RGB only; depth, instance and
terrain images do not depend on it.

Modules: ``settings.py`` (the settings, one declaration each), ``sky.py`` (the sun's position and
colour from the time of day and the latitude, the sky's colours and the light it sheds).
Like :mod:`navverse.scene`, this ``__init__`` imports nothing: names come from their modules.
"""
