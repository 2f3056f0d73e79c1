"""Build hook: compiles navverse.nav's RecastNavigation extension (added with the navmesh)."""

from setuptools import setup

setup()
