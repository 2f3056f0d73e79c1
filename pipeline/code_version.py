"""Code versions of stages: a hash of a module's source and of the project modules it imports.

Only modules of the same source tree are followed (not the standard library or site-packages), so
editing a stage, or a library module it uses, changes the cache key of every artifact it makes.
A compiled extension module of the project (``.so``/``.pyd``) counts by its bytes, so rebuilding
it from changed C++ sources also changes the keys of what depends on it.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import importlib.machinery
import importlib.util
import sys
import sysconfig
from pathlib import Path


@functools.cache
def _external_roots() -> tuple[Path, ...]:
    roots = {Path(sysconfig.get_paths()[key]).resolve() for key in ("stdlib", "platstdlib", "purelib")}
    roots |= {Path(sys.prefix).resolve(), Path(sys.base_prefix).resolve()}
    return tuple(roots)


_ENGINE_PACKAGE = __name__.partition(".")[0]
_EXTENSION_SUFFIXES = tuple(importlib.machinery.EXTENSION_SUFFIXES)


def _module_file(name: str) -> Path | None:
    if name == _ENGINE_PACKAGE or name.startswith(f"{_ENGINE_PACKAGE}."):
        return None  # the engine does not change what a stage produces
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    if spec is None or spec.origin is None or not spec.origin.endswith((".py", *_EXTENSION_SUFFIXES)):
        return None
    path = Path(spec.origin).resolve()
    if any(path.is_relative_to(root) for root in _external_roots()):
        return None
    return path


def _imported_names(path: Path, module: str) -> set[str]:
    if path.suffix != ".py":
        return set()  # a compiled extension: hashed by its bytes, its imports are not followed
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parent = ".".join(parts[: len(parts) - node.level + 1])
                base = f"{parent}.{base}" if base else parent
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return names


def _parents(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


@functools.cache
def module_closure(module: str) -> tuple[tuple[str, Path], ...]:
    """Project modules reachable from ``module`` by imports (itself included), sorted by name."""
    seen: dict[str, Path] = {}
    stack = [module]
    while stack:
        name = stack.pop()
        if name in seen:
            continue
        path = _module_file(name)
        if path is None:
            continue
        seen[name] = path
        for imported in _imported_names(path, name):
            for candidate in [*_parents(imported), imported]:
                if candidate not in seen:
                    stack.append(candidate)
    return tuple(sorted(seen.items()))


@functools.cache
def module_code_hash(module: str) -> str:
    """sha256 (24 hex) over the sources of :func:`module_closure` of ``module``."""
    digest = hashlib.sha256()
    for name, path in module_closure(module):
        digest.update(name.encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()[:24]
