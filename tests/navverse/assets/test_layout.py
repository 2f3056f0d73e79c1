"""The object library's layout: families in subpackages by place, apart from each other, registered by
the registry, over the core; its import contracts hold and catch an import across them."""

from __future__ import annotations

import importlib
import pkgutil
import shutil
from pathlib import Path

import pytest

from navverse.assets import indoor, outdoor
from navverse.assets.library import asset, categories
from pipeline.code_version import module_closure
from tests.test_layers import PACKAGES, REPO, lint_imports

FAMILIES = {
    package.__name__: [f"{package.__name__}.{m.name}" for m in pkgutil.iter_modules(package.__path__)]
    for package in (indoor, outdoor)
}
INDEPENDENCE = "object library: no family imports another (indoor, outdoor, facade)"
LAYERS = "object library: the registry over the families over the core (navverse.assets)"


@pytest.mark.parametrize("package", sorted(FAMILIES))
def test_every_family_is_registered_and_belongs_where_it_stands(package: str):
    outdoor_package = package == outdoor.__name__
    for name in FAMILIES[package]:
        family = importlib.import_module(name)
        assert family.ASSETS, name
        for item in family.ASSETS:
            assert asset(item.category) is item
            assert item.outdoor == outdoor_package, f"{item.category} of {name}"


def test_the_families_declare_every_category_once():
    names = [name for modules in FAMILIES.values() for name in modules]
    declared = [item.category for name in names for item in importlib.import_module(name).ASSETS]
    assert sorted(declared) == list(categories())


def test_a_stage_code_hash_covers_the_families_it_builds():
    closure = {name for name, _ in module_closure("stages.storefronts")}
    assert {"navverse.assets.facade.storefronts", "navverse.assets.facade.storefront_signs"} <= closure
    assert {
        "navverse.assets.library",
        "navverse.assets.indoor.seating",
        "navverse.assets.outdoor.vehicles",
    } <= closure


def _not_python(directory: str, names: list[str]) -> set[str]:
    return {n for n in names if n == "__pycache__" or n.endswith((".so", ".cpp", ".h"))}


@pytest.mark.parametrize(
    ("module", "statement", "contract", "broken_import"),
    [
        (
            "navverse/assets/indoor/seating.py",
            "from navverse.assets.indoor import tables",
            INDEPENDENCE,
            "navverse.assets.indoor.seating -> navverse.assets.indoor.tables",
        ),
        (
            "navverse/assets/outdoor/vehicles.py",
            "from navverse.assets.indoor.seating import ASSETS",
            INDEPENDENCE,
            "navverse.assets.outdoor.vehicles -> navverse.assets.indoor.seating",
        ),
        (
            "navverse/assets/outdoor/street_furniture.py",
            "from navverse.assets.facade import storefronts",
            INDEPENDENCE,
            "navverse.assets.outdoor.street_furniture -> navverse.assets.facade.storefronts",
        ),
        (
            "navverse/assets/outdoor/nature.py",
            "from navverse.assets.library import asset",
            LAYERS,
            "navverse.assets.outdoor.nature -> navverse.assets.library",
        ),
        (
            "navverse/assets/fittings.py",
            "from navverse.assets.indoor import seating",
            LAYERS,
            "navverse.assets.fittings -> navverse.assets.indoor.seating",
        ),
    ],
    ids=["indoor-indoor", "outdoor-indoor", "outdoor-facade", "family-registry", "core-family"],
)
def test_an_import_across_the_families_breaks_a_contract(
    tmp_path: Path, module: str, statement: str, contract: str, broken_import: str
) -> None:
    for package in PACKAGES:
        shutil.copytree(REPO / package, tmp_path / package, ignore=_not_python)
    shutil.copy(REPO / "pyproject.toml", tmp_path / "pyproject.toml")
    target = tmp_path / module
    target.write_text(f"{target.read_text()}\n\ndef _injected() -> None:\n    {statement}\n")
    code, output = lint_imports(tmp_path)
    assert code == 1, output
    assert f"{contract} BROKEN" in output
    assert broken_import in output
