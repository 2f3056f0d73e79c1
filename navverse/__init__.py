"""NavVerse: scenes, a physics-verified episode dataset and an evaluator for robot navigation.

The Python API is :mod:`navverse.api` (``import navverse.api as nv``: ``nv.build``, ``nv.load_scene``,
``nv.make_env``, ``nv.generate_building``, ``nv.generate_city``). It is not imported here: every build
stage's cache key covers this package module, and should not cover the API's imports.
"""

from navverse.errors import NavverseError

__version__ = "0.1.0"

__all__ = ["NavverseError", "__version__"]
