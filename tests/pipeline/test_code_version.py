"""Code versions follow project imports, compiled extensions included."""

from __future__ import annotations

import importlib.machinery
import sys
from pathlib import Path

import pytest

from pipeline.code_version import module_closure, module_code_hash


@pytest.fixture
def package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A package 'cvpkg' whose module imports a sibling module and a compiled extension."""
    root = tmp_path / "cvpkg"
    root.mkdir()
    (root / "__init__.py").write_text("")
    (root / "helper.py").write_text("VALUE = 1\n")
    (root / "user.py").write_text("from cvpkg import helper\nfrom cvpkg import _fast\n")
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    (root / f"_fast{suffix}").write_bytes(b"\x7fELF compiled code v1")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield root
    for name in [m for m in sys.modules if m == "cvpkg" or m.startswith("cvpkg.")]:
        del sys.modules[name]


def _fresh_hash(module: str) -> str:
    module_closure.cache_clear()
    module_code_hash.cache_clear()
    return module_code_hash(module)


def test_closure_includes_python_modules_and_extensions(package: Path):
    module_closure.cache_clear()
    names = [name for name, _ in module_closure("cvpkg.user")]
    assert names == ["cvpkg", "cvpkg._fast", "cvpkg.helper", "cvpkg.user"]


def test_editing_a_compiled_extension_changes_the_hash(package: Path):
    before = _fresh_hash("cvpkg.user")
    extension = next(package.glob("_fast*"))
    extension.write_bytes(b"\x7fELF compiled code v2")
    after = _fresh_hash("cvpkg.user")
    assert before != after
    (package / "helper.py").write_text("VALUE = 2\n")
    assert _fresh_hash("cvpkg.user") != after


def test_the_navmesh_stage_depends_on_the_recast_extension():
    closure = dict(module_closure("stages.navmesh"))
    assert "navverse.nav._recast" in closure
    assert closure["navverse.nav._recast"].suffix in {".so", ".pyd"}
