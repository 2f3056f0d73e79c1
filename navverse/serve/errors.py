"""The errors of the evaluation server: a mistake at its command line, and a refused request."""

from __future__ import annotations

from navverse.errors import NavverseError

__all__ = ["RefusedError", "ServeError"]


class ServeError(NavverseError):
    """A server that cannot start or a token command that cannot run, with what to change."""


class RefusedError(ServeError):
    """A request the server refuses: its HTTP status, the message of its ``{"error": ...}`` body and
    the headers to send with it (``Retry-After`` of a 429).

    Parameters
    ----------
    status : int
        401, 404, 413, 422, 429, ...
    message : str
        What is wrong and what to change; never a server path nor anything of a hidden goal.
    headers : dict, optional
        Extra response headers.
    """

    def __init__(self, status: int, message: str, *, headers: dict[str, str] | None = None) -> None:
        super().__init__(message)
        self.status = status
        self.message = message
        self.headers = dict(headers or {})
