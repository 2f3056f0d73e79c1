"""Build hook: compiles navverse.nav's RecastNavigation extension (``navverse.nav._recast``) and the
Spot model's leg forces (``navverse.sim._legs``).

The extension links against the system RecastNavigation (Debian/Ubuntu package ``librecast-dev``,
which ``make setup`` installs). Set ``RECAST_INCLUDE_DIR`` / ``RECAST_LIBRARY_DIR`` to use a copy
installed elsewhere.
"""

import os
from pathlib import Path

from pybind11.setup_helpers import Pybind11Extension
from pybind11.setup_helpers import build_ext as _build_ext
from setuptools import setup

NAV = Path("navverse") / "nav"
INCLUDE_CANDIDATES = [
    os.environ.get("RECAST_INCLUDE_DIR", ""),
    "/usr/include/recastnavigation",
    "/usr/local/include/recastnavigation",
]
RECAST_INCLUDE = next((d for d in INCLUDE_CANDIDATES if d and Path(d, "Recast.h").is_file()), None)
LIBRARY_DIRS = [os.environ["RECAST_LIBRARY_DIR"]] if os.environ.get("RECAST_LIBRARY_DIR") else []


class build_ext(_build_ext):  # noqa: N801 - setuptools command name
    """Fail early, with the fix, when the RecastNavigation headers are missing."""

    def run(self) -> None:
        if RECAST_INCLUDE is None:
            raise SystemExit(
                "error: RecastNavigation headers not found (looked for Recast.h in "
                + ", ".join(d for d in INCLUDE_CANDIDATES if d)
                + "). Install the system package `librecast-dev` (`make setup` does: "
                "sudo apt-get install librecast-dev), or set RECAST_INCLUDE_DIR/RECAST_LIBRARY_DIR."
            )
        super().run()


ext = Pybind11Extension(
    "navverse.nav._recast",
    sources=[
        str(NAV / "_recast.cpp"),
        str(NAV / "csrc" / "build.cpp"),
        str(NAV / "csrc" / "navmesh.cpp"),
        str(NAV / "csrc" / "polyanya.cpp"),
    ],
    depends=[str(NAV / "csrc" / "navmesh.h"), str(NAV / "csrc" / "polyanya.h")],
    include_dirs=[RECAST_INCLUDE or "/usr/include/recastnavigation"],
    library_dirs=LIBRARY_DIRS,
    libraries=["Recast", "Detour"],
    cxx_std=17,
    extra_compile_args=["-O2"],
)

# The Spot model's leg forces (navverse/sim/spot.py): the same IEEE double arithmetic as the Python
# formulas, so no fused multiply-adds.
legs = Pybind11Extension(
    "navverse.sim._legs",
    sources=[str(Path("navverse") / "sim" / "csrc" / "legs.cpp")],
    cxx_std=17,
    extra_compile_args=["-O2", "-ffp-contract=off"],
)

setup(ext_modules=[ext, legs], cmdclass={"build_ext": build_ext})
