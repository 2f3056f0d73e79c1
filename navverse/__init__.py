"""NavVerse: scenes, a physics-verified episode dataset and an evaluator for robot navigation."""

from navverse.errors import NavverseError

__version__ = "0.1.0"

__all__ = ["NavverseError", "__version__"]
