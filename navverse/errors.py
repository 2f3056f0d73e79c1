"""Errors a user can cause. The CLI prints them and exits 1, without a traceback."""


class NavverseError(Exception):
    """Base class of every error caused by user input (files, recipes, submissions, scenes)."""


class SceneError(NavverseError):
    """A scene directory is missing, incomplete or of an unsupported format version."""
