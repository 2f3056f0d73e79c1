"""Build hook: compiles navverse.nav's RecastNavigation extension (``navverse.nav._recast``), the
Spot model's leg forces (``navverse.sim._legs``) and the camera's packet ray caster
(``navverse.sim._raycast``).

The extensions link against the system RecastNavigation and Embree 3 (Debian/Ubuntu packages
``librecast-dev`` and ``libembree-dev``, which ``make setup`` installs). Set ``RECAST_INCLUDE_DIR`` /
``RECAST_LIBRARY_DIR`` (``EMBREE_INCLUDE_DIR`` / ``EMBREE_LIBRARY_DIR``) to use a copy installed
elsewhere.
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
EMBREE_CANDIDATES = [os.environ.get("EMBREE_INCLUDE_DIR", ""), "/usr/include", "/usr/local/include"]
EMBREE_INCLUDE = next((d for d in EMBREE_CANDIDATES if d and Path(d, "embree3", "rtcore.h").is_file()), None)
EMBREE_LIBRARY_DIRS = [os.environ["EMBREE_LIBRARY_DIR"]] if os.environ.get("EMBREE_LIBRARY_DIR") else []


class build_ext(_build_ext):  # noqa: N801 - setuptools command name
    """Fail early, with the fix, when the RecastNavigation or Embree headers are missing."""

    def run(self) -> None:
        missing = []
        if RECAST_INCLUDE is None:
            missing.append(("RecastNavigation", "Recast.h", INCLUDE_CANDIDATES, "librecast-dev", "RECAST"))
        if EMBREE_INCLUDE is None:
            missing.append(("Embree 3", "embree3/rtcore.h", EMBREE_CANDIDATES, "libembree-dev", "EMBREE"))
        for name, header, candidates, package, variable in missing:
            raise SystemExit(
                f"error: {name} headers not found (looked for {header} in "
                + ", ".join(d for d in candidates if d)
                + f"). Install the system package `{package}` (`make setup` does: "
                f"sudo apt-get install {package}), or set {variable}_INCLUDE_DIR/{variable}_LIBRARY_DIR."
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

# Pedestrians on the navmesh (navverse/dynamics/crowd.py): DetourCrowd over a copy of a navmesh read by
# the navmesh extension's own code. A module of its own, so that changing it leaves the bytes of
# navverse.nav._recast, which key every navmesh and episode artifact, as they are.
DYNAMICS = Path("navverse") / "dynamics"
crowd = Pybind11Extension(
    "navverse.dynamics._crowd",
    sources=[
        str(DYNAMICS / "_crowd.cpp"),
        str(DYNAMICS / "csrc" / "crowd.cpp"),
        str(NAV / "csrc" / "navmesh.cpp"),
        str(NAV / "csrc" / "polyanya.cpp"),
    ],
    depends=[str(DYNAMICS / "csrc" / "crowd.h"), str(NAV / "csrc" / "navmesh.h")],
    include_dirs=[RECAST_INCLUDE or "/usr/include/recastnavigation"],
    library_dirs=LIBRARY_DIRS,
    libraries=["Recast", "Detour", "DetourCrowd"],
    cxx_std=17,
    extra_compile_args=["-O2"],
)

# The camera's ray caster (navverse/sim/raycast.py): Embree picks its SIMD code at run time.
raycast = Pybind11Extension(
    "navverse.sim._raycast",
    sources=[str(Path("navverse") / "sim" / "csrc" / "raycast.cpp")],
    include_dirs=[EMBREE_INCLUDE or "/usr/include"],
    library_dirs=EMBREE_LIBRARY_DIRS,
    libraries=["embree3"],
    cxx_std=17,
    extra_compile_args=["-O2"],
)

setup(ext_modules=[ext, legs, raycast, crowd], cmdclass={"build_ext": build_ext})
