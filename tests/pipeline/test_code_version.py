"""Code versions follow project imports by their files, compiled extensions included, and fail closed."""

from __future__ import annotations

import importlib.machinery
import sys
from pathlib import Path

import pytest

from pipeline.code_version import module_closure, module_code_hash
from pipeline.errors import CodeVersionError

SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]


@pytest.fixture
def package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A package 'cvpkg' whose module imports a sibling module and a compiled extension."""
    root = tmp_path / "cvpkg"
    root.mkdir()
    (root / "__init__.py").write_text("")
    (root / "helper.py").write_text("VALUE = 1\n")
    (root / "user.py").write_text("from cvpkg import helper\nfrom cvpkg import _fast\n")
    (root / f"_fast{SUFFIX}").write_bytes(b"\x7fELF compiled code v1")
    monkeypatch.syspath_prepend(str(tmp_path))
    module_closure.cache_clear()
    module_code_hash.cache_clear()
    yield root
    for name in [m for m in sys.modules if m == "cvpkg" or m.startswith("cvpkg.")]:
        del sys.modules[name]
    module_closure.cache_clear()
    module_code_hash.cache_clear()


def _fresh_hash(module: str) -> str:
    module_closure.cache_clear()
    module_code_hash.cache_clear()
    return module_code_hash(module)


def test_closure_includes_python_modules_and_extensions(package: Path):
    names = [name for name, _ in module_closure("cvpkg.user")]
    assert names == ["cvpkg", "cvpkg._fast", "cvpkg.helper", "cvpkg.user"]


def test_the_closure_is_found_without_importing(package: Path):
    (package / "user.py").write_text("import cvpkg.helper\nraise RuntimeError('imported')\n")
    assert [name for name, _ in module_closure("cvpkg.user")] == ["cvpkg", "cvpkg.helper", "cvpkg.user"]
    assert "cvpkg.user" not in sys.modules


def test_editing_a_compiled_extension_changes_the_hash(package: Path):
    before = _fresh_hash("cvpkg.user")
    extension = next(package.glob("_fast*"))
    extension.write_bytes(b"\x7fELF compiled code v2")
    after = _fresh_hash("cvpkg.user")
    assert before != after
    (package / "helper.py").write_text("VALUE = 2\n")
    assert _fresh_hash("cvpkg.user") != after


def test_a_missing_extension_is_an_error_naming_it(package: Path):
    next(package.glob("_fast*")).unlink()
    with pytest.raises(CodeVersionError, match=r"cvpkg.user \(line 2\) imports project module 'cvpkg._fast'"):
        _fresh_hash("cvpkg.user")


def test_a_missing_module_is_an_error_naming_it(package: Path):
    (package / "user.py").write_text("import cvpkg.helper\nfrom cvpkg.gone import thing\n")
    with pytest.raises(CodeVersionError, match=r"project module 'cvpkg.gone', which cannot be found"):
        _fresh_hash("cvpkg.user")


def test_a_function_level_import_of_a_missing_module_is_an_error(package: Path):
    (package / "user.py").write_text("def later():\n    from cvpkg import vanished\n    return vanished\n")
    with pytest.raises(CodeVersionError, match=r"'cvpkg\.vanished'"):
        _fresh_hash("cvpkg.user")


def test_an_unreadable_module_is_an_error_naming_it(package: Path):
    (package / "helper.py").write_bytes(b"VALUE = (\n")
    with pytest.raises(CodeVersionError, match=r"cannot read project module 'cvpkg.helper'"):
        _fresh_hash("cvpkg.user")


def test_names_bound_by_the_package_are_attributes_not_modules(package: Path):
    (package / "__init__.py").write_text("from cvpkg.helper import VALUE\nLIMIT = 3\n")
    (package / "user.py").write_text("from cvpkg import VALUE, LIMIT\n")
    assert [name for name, _ in module_closure("cvpkg.user")] == ["cvpkg", "cvpkg.helper", "cvpkg.user"]


def test_type_checking_imports_are_not_followed(package: Path):
    (package / "heavy.py").write_text("WEIGHT = 1\n")
    (package / "user.py").write_text(
        "from typing import TYPE_CHECKING\n"
        "import cvpkg.helper\n"
        "if TYPE_CHECKING:\n    from cvpkg import heavy\nelse:\n    pass\n"
    )
    assert [name for name, _ in module_closure("cvpkg.user")] == ["cvpkg", "cvpkg.helper", "cvpkg.user"]
    before = _fresh_hash("cvpkg.user")
    (package / "heavy.py").write_text("WEIGHT = 2\n")
    assert _fresh_hash("cvpkg.user") == before


def test_lazy_module_getattr_is_refused(package: Path):
    (package / "__init__.py").write_text("def __getattr__(name):\n    raise AttributeError(name)\n")
    with pytest.raises(CodeVersionError, match=r"'cvpkg' .* defines a module-level __getattr__"):
        _fresh_hash("cvpkg.user")


def test_the_navmesh_stage_depends_on_the_recast_extension_and_its_settings():
    closure = dict(module_closure("stages.navmesh"))
    assert "navverse.nav._recast" in closure
    assert closure["navverse.nav._recast"].suffix in {".so", ".pyd"}
    assert {"navverse.nav.pathfinder", "navverse.nav.settings", "navverse.nav.scene_navmesh"} <= set(closure)


def test_blockout_covers_the_primitives_it_uses_and_no_other_asset_module():
    closure = {name for name, _ in module_closure("stages.blockout")}
    assets = sorted(name for name in closure if name.startswith("navverse.assets"))
    assert assets == ["navverse.assets", "navverse.assets.primitives"]
    indoor = {name for name, _ in module_closure("stages.indoor_layout")}
    assert {
        "navverse.assets.library",
        "navverse.assets.indoor.seating",
        "navverse.assets.indoor.retail",
    } <= indoor


def test_a_stage_module_that_cannot_be_imported_is_a_clean_error(tmp_path: Path, monkeypatch):
    from pipeline.errors import StageImportError
    from pipeline.stage import discover

    package = tmp_path / "brokenstages"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "fine.py").write_text("VALUE = 1\n")
    (package / "needs_gone.py").write_text("from brokenstages import gone\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        expected = r"stage module brokenstages\.needs_gone cannot be imported"
        with pytest.raises(StageImportError, match=expected):
            discover("brokenstages")
    finally:
        for name in [m for m in sys.modules if m.startswith("brokenstages")]:
            del sys.modules[name]
