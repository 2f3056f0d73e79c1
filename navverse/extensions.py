"""The error raised when a compiled extension of navverse cannot be imported."""

from __future__ import annotations


def missing_extension(module: str, *, library: str, package: str) -> ImportError:
    """The error of a compiled extension (`module`) that is not built or cannot load its system
    `library` (from the Debian/Ubuntu `package` ``make setup`` installs)."""
    owner = module.rsplit(".", 1)[0]
    return ImportError(
        f"{owner}'s C++ extension ({module}) is not built or cannot load its {library} libraries: install "
        f"the system package {package}, then reinstall navverse (`make setup` does both)"
    )
