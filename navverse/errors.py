"""Errors a user can cause. The CLI prints them and exits 1, without a traceback."""


class NavverseError(Exception):
    """Base class of every error caused by user input (files, recipes, submissions, scenes)."""


class SceneError(NavverseError):
    """A scene directory is missing, incomplete or of an unsupported format version."""


def rebuild_hint(scene_id: str | None = None) -> str:
    """How to repair a damaged or outdated built scene: the build command that finds and replaces it."""
    return (
        f"rebuild it with `navverse build --verify {scene_id or '<scene_id>'}` "
        "(it finds damaged files and rebuilds them)"
    )
