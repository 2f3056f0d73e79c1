"""Code versions of stages: a hash of a module's source and of the project modules it imports.

The closure of a stage module is found from source files alone, without importing anything: each
module's imports are read from its syntax tree and looked up as files under the project's source
root (the folder that holds the stage's top-level package). Only the project's own packages are
followed (not the standard library or installed packages), so editing a stage, or a library module
it uses, changes the cache key of every artifact it makes. A compiled extension module of the
project (``.so``/``.pyd``) counts by its bytes, so rebuilding it from changed C++ sources also
changes the keys of what depends on it.

The closure fails closed: a project module that an import names but that cannot be found or read
raises :class:`~pipeline.errors.CodeVersionError` naming it, rather than leaving a smaller key.
Imports under ``if TYPE_CHECKING:`` are not followed (they never run), and a project module that
defines a module-level ``__getattr__`` (lazy imports the syntax tree cannot see) is refused.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import importlib.machinery
import importlib.metadata
import importlib.util
import sys
import sysconfig
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from pipeline.errors import CodeVersionError

_ENGINE_PACKAGE = __name__.partition(".")[0]
_EXTENSION_SUFFIXES = tuple(importlib.machinery.EXTENSION_SUFFIXES)


@functools.cache
def _external_roots() -> tuple[Path, ...]:
    roots = {Path(sysconfig.get_paths()[key]).resolve() for key in ("stdlib", "platstdlib", "purelib")}
    roots |= {Path(sys.prefix).resolve(), Path(sys.base_prefix).resolve()}
    return tuple(roots)


@dataclass(frozen=True)
class _Project:
    """Where the project's sources are and which top-level packages are the project's."""

    root: Path
    packages: frozenset[str]

    def owns(self, name: str) -> bool:
        top = name.partition(".")[0]
        return top in self.packages and top != _ENGINE_PACKAGE

    def candidates(self, name: str) -> list[Path]:
        """Files that would hold module ``name``, in the order Python's import system tries them."""
        base = self.root.joinpath(*name.split("."))
        return [base / "__init__.py", base.with_name(base.name + ".py")] + [
            base.with_name(base.name + suffix) for suffix in _EXTENSION_SUFFIXES
        ]

    def find(self, name: str) -> Path | None:
        """The file of module ``name``, or ``None`` when there is none."""
        return next((path for path in self.candidates(name) if path.exists()), None)


def _project_of(module: str) -> _Project:
    """The source root of ``module`` and the project's top-level packages there."""
    loaded = sys.modules.get(module)
    origin = getattr(loaded, "__file__", None)
    if origin is None:
        try:
            spec = importlib.util.find_spec(module)
        except (ImportError, ValueError) as exc:
            raise CodeVersionError(f"cannot find stage module {module!r}: {exc}") from None
        origin = spec.origin if spec is not None else None
    if origin is None:
        raise CodeVersionError(f"cannot find the source file of stage module {module!r}")
    path = Path(origin).resolve()
    depth = module.count(".") + (1 if path.name == "__init__.py" else 0)
    root = path.parents[depth]
    if any(root == external or root.is_relative_to(external) for external in _external_roots()):
        # installed into site-packages: the project is the stage's distribution (or its own package)
        top = module.partition(".")[0]
        by_distribution = importlib.metadata.packages_distributions()
        mine = set(by_distribution.get(top, ()))
        packages = {name for name, dists in by_distribution.items() if mine & set(dists)} | {top}
    else:
        packages = {p.name for p in root.iterdir() if (p / "__init__.py").is_file()}
        packages |= {p.stem for p in root.glob("*.py")}
        packages |= {p.name.split(".")[0] for p in root.iterdir() if p.name.endswith(_EXTENSION_SUFFIXES)}
    return _Project(root=root, packages=frozenset(packages))


def _parse(path: Path, name: str) -> ast.Module:
    try:
        source = path.read_bytes()
        return ast.parse(source, filename=str(path))
    except (OSError, SyntaxError, ValueError) as exc:
        raise CodeVersionError(
            f"cannot read project module {name!r} ({path}): {type(exc).__name__}: {exc}; the cache keys of "
            "the stages that import it cannot be computed: fix or restore the file"
        ) from None


def _is_type_checking(test: ast.expr) -> bool:
    if isinstance(test, ast.Name):
        return test.id == "TYPE_CHECKING"
    return isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"


def _runtime_nodes(body: list[ast.stmt]) -> Iterator[ast.AST]:
    """Every node of ``body`` that can run: the bodies of ``if TYPE_CHECKING:`` are left out."""
    stack: list[ast.AST] = list(reversed(body))
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            stack.extend(reversed(node.orelse))
            continue
        stack.extend(reversed(list(ast.iter_child_nodes(node))))


def _top_level_statements(body: list[ast.stmt]) -> Iterator[ast.stmt]:
    """Statements that run at import time at module level (inside if/try blocks, not in functions)."""
    for statement in body:
        yield statement
        if isinstance(statement, ast.If) and _is_type_checking(statement.test):
            yield from _top_level_statements(statement.orelse)
        elif isinstance(statement, (ast.If, ast.For, ast.While, ast.With)):
            yield from _top_level_statements(statement.body)
            yield from _top_level_statements(getattr(statement, "orelse", []))
        elif isinstance(statement, ast.Try):
            for block in (statement.body, statement.orelse, statement.finalbody):
                yield from _top_level_statements(block)
            for handler in statement.handlers:
                yield from _top_level_statements(handler.body)


def _bound_names(tree: ast.Module) -> tuple[set[str], bool]:
    """Names a module binds at import time, and whether it has a star import."""
    names: set[str] = set()
    star = False
    for statement in _top_level_statements(tree.body):
        if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(statement.name)
        elif isinstance(statement, (ast.Import, ast.ImportFrom)):
            for alias in statement.names:
                if alias.name == "*":
                    star = True
                else:
                    names.add(alias.asname or alias.name.partition(".")[0])
        elif isinstance(statement, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            for target in targets:
                names.update(n.id for n in ast.walk(target) if isinstance(n, ast.Name))
    return names, star


@dataclass(frozen=True)
class _Import:
    """A module an import statement needs (``required``), or a name that may be a submodule."""

    name: str
    required: bool
    line: int


def _imports(tree: ast.Module, module: str, *, is_package: bool) -> list[_Import]:
    package = module if is_package else module.rpartition(".")[0]
    found: list[_Import] = []
    for node in _runtime_nodes(tree.body):
        if isinstance(node, ast.Import):
            found.extend(_Import(alias.name, True, node.lineno) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parent = ".".join(parts[: len(parts) - node.level + 1])
                base = f"{parent}.{base}" if base else parent
            found.append(_Import(base, True, node.lineno))
            found.extend(_Import(f"{base}.{a.name}", False, node.lineno) for a in node.names if a.name != "*")
    return found


def _parents(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


class _Closure:
    """Walks the imports of project modules from one module, by their files."""

    def __init__(self, project: _Project) -> None:
        self.project = project
        self.files: dict[str, Path] = {}
        self.bound: dict[str, tuple[set[str], bool]] = {}
        """The names each package's ``__init__`` binds (and whether it star-imports): all that is kept
        of a syntax tree once its imports are read, so a large closure is never in memory whole."""

    def add(self, name: str, *, needed_by: str | None, line: int = 0) -> None:
        if name in self.files or not self.project.owns(name):
            return
        path = self.project.find(name)
        if path is None:
            where = f"{needed_by} (line {line}) imports" if needed_by else "the stage is in"
            looked = ", ".join(
                str(p.relative_to(self.project.root)) for p in self.project.candidates(name)[:2]
            )
            raise CodeVersionError(
                f"{where} project module {name!r}, which cannot be found (looked for {looked} or a "
                f"compiled extension under {self.project.root}); the stage's cache key would leave it "
                "out: restore the module, or build the extension (make setup)"
            )
        self.files[name] = path
        if path.suffix != ".py":
            return  # a compiled extension: hashed by its bytes, its imports are not followed
        tree = _parse(path, name)
        if path.name == "__init__.py":
            self.bound[name] = _bound_names(tree)
        if any(
            isinstance(s, ast.FunctionDef) and s.name == "__getattr__"
            for s in _top_level_statements(tree.body)
        ):
            raise CodeVersionError(
                f"project module {name!r} ({path}) defines a module-level __getattr__: the names it loads "
                "lazily are invisible to the code hash; import them from the modules that define them"
            )
        imports = _imports(tree, name, is_package=path.name == "__init__.py")
        del tree
        for parent in _parents(name):
            self.add(parent, needed_by=name)
        for imported in imports:
            if imported.required:
                for parent in _parents(imported.name):
                    self.add(parent, needed_by=name, line=imported.line)
                self.add(imported.name, needed_by=name, line=imported.line)
            else:
                self._add_if_submodule(imported, needed_by=name)

    def _add_if_submodule(self, imported: _Import, *, needed_by: str) -> None:
        """``from package import x``: ``x`` is a submodule unless the package binds the name."""
        if imported.name in self.files or not self.project.owns(imported.name):
            return
        if self.project.find(imported.name) is not None:
            self.add(imported.name, needed_by=needed_by, line=imported.line)
            return
        parent = imported.name.rpartition(".")[0]
        if parent not in self.bound:
            return  # 'from module import attribute'
        bound, star = self.bound[parent]
        if not star and imported.name.rpartition(".")[2] not in bound:
            self.add(imported.name, needed_by=needed_by, line=imported.line)  # raises: not found


@functools.cache
def module_closure(module: str) -> tuple[tuple[str, Path], ...]:
    """Project modules reachable from ``module`` by imports (itself included), sorted by name.

    Raises
    ------
    CodeVersionError
        If a project module in the closure cannot be found or read.
    """
    closure = _Closure(_project_of(module))
    closure.add(module, needed_by=None)
    return tuple(sorted(closure.files.items()))


@functools.cache
def module_code_hash(module: str) -> str:
    """sha256 (24 hex) over the sources of :func:`module_closure` of ``module``.

    Raises
    ------
    CodeVersionError
        If a project module in the closure cannot be found or read.
    """
    digest = hashlib.sha256()
    for name, path in module_closure(module):
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise CodeVersionError(f"cannot read project module {name!r} ({path}): {exc}") from None
        digest.update(name.encode())
        digest.update(b"\0")
        digest.update(data)
        digest.update(b"\0")
    return digest.hexdigest()[:24]
