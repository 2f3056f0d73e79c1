"""Base model of stage parameters, and source-file fields whose content is part of the cache key.

Where a recipe may read files (the file-access policy): a :data:`SourceFile` names a regular file

- inside the project (the workspace root, which holds ``data/raw/``), symbolic links followed first,
  so a link inside the project to a file outside it is outside;
- or inside an installed package's data: ``{package_data: <package>, file: <path in the package>}``;
- or inside a folder of the allow-list: ``navverse build --allow-read DIR`` (repeatable; the
  context manager :func:`allow_reading`) and the environment variable ``NAVVERSE_ALLOW_READ``
  (folders separated by ``os.pathsep``). The allow-list is not part of any cache key.

Every source file must be a regular file (not a directory, named pipe or device) of at most
:data:`MAX_SOURCE_BYTES`; that is checked with ``os.stat`` before the file is ever opened. The
location is checked when a recipe is validated (the validation context names the project:
``{"recipe_dir": ..., "workspace_root": ...}``); parameters validated again without a context
(a worker process re-reading parameters that were already checked, or library code) get the
regular-file and size checks only.
"""

from __future__ import annotations

import importlib.util
import os
import stat
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, ValidationInfo

ALLOW_READ_ENV = "NAVVERSE_ALLOW_READ"
"""Environment variable: folders (``os.pathsep``-separated) recipes may read files from."""

ALLOW_READ_OPTION = "--allow-read"
"""The command-line option that adds a folder to the allow-list (named in error messages)."""

MAX_SOURCE_BYTES = 2 * 1024**3
"""Largest source file a recipe may name (2 GiB): source files are hashed and parsed whole."""

_EXTRA_ROOTS: ContextVar[tuple[Path, ...]] = ContextVar("navverse_allow_read", default=())


class Params(BaseModel):
    """Frozen, strict-keyed base class of every stage's parameter model.

    Unknown keys are errors, instances are immutable, non-finite floats (``inf``, ``nan``) are
    refused, and defaults are validated, so a params object is a complete, hashable description
    of what a stage will do. A field's docstring (the string literal under it) is its description,
    which the documentation's parameter reference shows; descriptions are not part of a cache key
    (the key hashes the field values, :meth:`~pydantic.BaseModel.model_dump`).
    """

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        validate_default=True,
        allow_inf_nan=False,
        use_attribute_docstrings=True,
    )

    def dependency_files(self) -> Mapping[str, Path]:
        """Files the stage reads besides those its ``Path`` fields name (e.g. USD sublayers).

        Their content is part of the cache key, like a ``Path`` field's. The default: none.

        Returns
        -------
        Mapping
            ``{name: path}``; names are identifiers (no dots) unlike the model's field names.
        """
        return {}


# ------------------------------------------------------------------------------------ the allow-list


@contextmanager
def allow_reading(folders: Iterable[Path | str]) -> Iterator[None]:
    """Let recipes validated inside the block read files in ``folders`` too (``--allow-read``).

    Parameters
    ----------
    folders : iterable of Path or str
        Folders (or single files) added to the allow-list; symbolic links are resolved.
    """
    token = _EXTRA_ROOTS.set(_EXTRA_ROOTS.get() + tuple(Path(f).expanduser().resolve() for f in folders))
    try:
        yield
    finally:
        _EXTRA_ROOTS.reset(token)


def _env_roots() -> tuple[Path, ...]:
    value = os.environ.get(ALLOW_READ_ENV, "")
    return tuple(Path(part).expanduser().resolve() for part in value.split(os.pathsep) if part.strip())


@dataclass(frozen=True)
class ReadPolicy:
    """Where the files a recipe names may be.

    Parameters
    ----------
    project : Path
        The workspace root (resolved); everything under it may be read.
    allowed : tuple of Path
        Further folders (resolved): the allow-list.
    """

    project: Path
    allowed: tuple[Path, ...] = ()

    @classmethod
    def for_project(cls, root: Path | str) -> ReadPolicy:
        """The policy of a project: its root, and the allow-list of ``--allow-read`` and the environment."""
        return cls(Path(root).resolve(), _EXTRA_ROOTS.get() + _env_roots())

    @classmethod
    def from_context(cls, info: ValidationInfo) -> ReadPolicy | None:
        """The policy of a validation context naming ``workspace_root``; None without one."""
        context = info.context if isinstance(info.context, Mapping) else {}
        root = context.get("workspace_root")
        return None if root is None else cls.for_project(root)

    def allows(self, path: Path) -> bool:
        """Whether a resolved path lies inside the project or a folder of the allow-list."""
        return any(path == root or path.is_relative_to(root) for root in (self.project, *self.allowed))

    def refusal(self, path: Path, *, written: str) -> str | None:
        """Why a resolved ``path`` may not be read (None: it may).

        Parameters
        ----------
        path : Path
            The path with symbolic links resolved.
        written : str
            How the recipe (or file) names it, for the message.
        """
        if self.allows(path):
            return None
        folder = path.parent
        same = Path(written).is_absolute() and os.path.normpath(written) == str(path)
        what = str(path) if same else f"{written!r} resolves to {path} (symbolic links followed) and"
        return (
            f"{what} is outside the project {self.project}: recipes read only files inside their "
            "project (e.g. data/raw/) or an installed package's data ({package_data: <package>, "
            "file: <path>}); copy the file into the project, or allow its folder with "
            f"'navverse build {ALLOW_READ_OPTION} {folder}' (or {ALLOW_READ_ENV}={folder})"
        )


# ------------------------------------------------------------------------------- file kind and size


def file_kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in words, for messages."""
    kinds = (
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    )
    return next((name for test, name in kinds if test(mode)), "a special file")


def _size_text(size: int) -> str:
    return f"{size / 1024**3:.2f} GiB" if size >= 1024**3 else f"{size / 1024**2:.1f} MiB"


def regular_file_problem(path: Path, *, max_bytes: int = MAX_SOURCE_BYTES) -> str | None:
    """Why ``path`` is not a readable source file (None: it is one), without opening it.

    Parameters
    ----------
    path : Path
        A resolved path.
    max_bytes : int
        The size cap.

    Returns
    -------
    str or None
        "file not found: ...", "... is a named pipe (FIFO), not a regular file ...", "... is 3.00 GiB,
        over the ... limit ...", or None.
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return f"file not found: {path}"
    except OSError as exc:
        return f"cannot read {path}: {exc.strerror or exc}"
    if not stat.S_ISREG(info.st_mode):
        return f"{path} is {file_kind(info.st_mode)}, not a regular file; name a regular file"
    if info.st_size > max_bytes:
        return (
            f"{path} is {_size_text(info.st_size)}, over the {_size_text(max_bytes)} limit of a source "
            "file; make it smaller first (e.g. decimate or split the mesh in Blender)"
        )
    return None


# ---------------------------------------------------------------------------------------- SourceFile


def _package_data_path(value: Mapping[str, Any]) -> Path:
    """The file named by ``{package_data: <package>, file: <relative path>}``, inside the package's folder.

    The package is located, not imported.
    """
    keys = set(value)
    if keys != {"package_data", "file"}:
        extra = ", ".join(sorted(str(k) for k in keys - {"package_data", "file"})) or "none"
        raise ValueError(
            "a package data source needs exactly the keys 'package_data' and 'file' "
            f"(unknown keys: {extra}); or give a path to the file"
        )
    package, file = value["package_data"], value["file"]
    if not isinstance(package, str) or not isinstance(file, str) or not package or not file:
        raise ValueError("'package_data' (a package name) and 'file' (a path inside it) must be strings")
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        spec = None
    if spec is None:
        raise ValueError(
            f"unknown package {package!r} in 'package_data': it is not installed here; install it "
            "or give a path to the file"
        )
    folders = [Path(p).resolve() for p in spec.submodule_search_locations or ()]
    if not folders:
        raise ValueError(f"{package!r} in 'package_data' is a module, not a package with data files")
    for root in folders:
        path = (root / file).resolve()
        if path.is_relative_to(root) and os.path.lexists(path):
            return path
    raise ValueError(
        f"package {package!r} has no data file {file!r} (looked in {', '.join(map(str, folders))})"
    )


def _resolve_source_file(value: Any, info: ValidationInfo) -> Path:
    if isinstance(value, Mapping):
        path = _package_data_path(value)
    elif isinstance(value, str | os.PathLike):
        path = _recipe_path(Path(value), info)
    else:
        raise ValueError("give a path to a file, or {package_data: <package>, file: <path in the package>}")
    problem = regular_file_problem(path)
    if problem is not None:
        if problem.startswith("file not found"):
            problem += " (paths are relative to the recipe's folder)"
        raise ValueError(problem)
    return path


def _recipe_path(given: Path, info: ValidationInfo) -> Path:
    """A path of a recipe, resolved against the recipe's folder and checked against the policy."""
    context = info.context if isinstance(info.context, Mapping) else {}
    base = context.get("recipe_dir")
    path = given.expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    resolved = path.resolve()
    policy = ReadPolicy.from_context(info)
    if policy is not None:
        refusal = policy.refusal(resolved, written=str(given))
        if refusal is not None:
            raise ValueError(refusal)
    return resolved


SourceFile = Annotated[Path, BeforeValidator(_resolve_source_file)]
"""A path to an input file of a stage: a path relative to the recipe's folder, or ``{package_data:
<package>, file: <path>}`` (a data file of an installed package, e.g. ``pybullet_data``). Resolved
(symbolic links followed), confined by the file-access policy (see the module docstring), a regular
file of at most :data:`MAX_SOURCE_BYTES`; its content hash is part of the stage's cache key (editing
the file rebuilds what depends on it)."""


def source_files(params: BaseModel) -> dict[str, Path]:
    """Every existing file named by a ``Path`` value in ``params`` (nested models and sequences
    included), and the :meth:`Params.dependency_files` of every params model in it.

    Returns
    -------
    dict
        ``{dotted_field_path: path}``; the cache key holds each file's content hash.
    """
    found: dict[str, Path] = {}
    _collect(params, "", found)
    return found


def _collect(value: Any, prefix: str, found: dict[str, Path]) -> None:
    if isinstance(value, Path):
        if value.is_file():
            found[prefix.rstrip(".")] = value
    elif isinstance(value, BaseModel):
        for name in type(value).model_fields:
            _collect(getattr(value, name), f"{prefix}{name}.", found)
        if isinstance(value, Params):
            for name, path in value.dependency_files().items():
                found[f"{prefix}{name}"] = path
    elif isinstance(value, list | tuple):
        for index, item in enumerate(value):
            _collect(item, f"{prefix}{index}.", found)
    elif isinstance(value, dict):
        for key, item in value.items():
            _collect(item, f"{prefix}{key}.", found)
