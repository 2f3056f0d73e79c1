"""The ``@stage`` decorator and the registry of stages.

A stage is a plain function ``fn(ctx: StageContext, params: P) -> None`` with one frozen params
model ``P`` (a :class:`~pipeline.params.Params` subclass). It declares the artifacts it reads and
the artifacts it writes; the graph of a build is derived from these declarations.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import typing
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from pipeline.code_version import module_code_hash
from pipeline.errors import DagError
from pipeline.params import Params

_NAME_CHARS = frozenset("abcdefghijklmnopqrstuvwxyz0123456789_")


@dataclass(frozen=True)
class Input:
    """An input declaration of a stage.

    Parameters
    ----------
    name : str
        Artifact name.
    many : bool
        If true the stage receives a list of artifact directories (from several targets, bound
        through the recipe's ``links``); otherwise exactly one.
    """

    name: str
    many: bool = False


@dataclass(frozen=True)
class StageSpec:
    """A registered stage.

    Attributes
    ----------
    name : str
        Unique stage name (also the key of its section in recipes).
    fn : callable
        The stage function ``fn(ctx, params)``.
    params_model : type of Params
        The stage's parameter model.
    inputs : tuple of Input
        Artifacts read.
    outputs : tuple of str
        Artifacts written (one directory each).
    version : str
        Manual version string; bump it when behaviour changes in code the stage does not import.
    doc : str
        First line of the function's docstring: what the stage produces.
    """

    name: str
    fn: Callable[..., Any]
    params_model: type[Params]
    inputs: tuple[Input, ...]
    outputs: tuple[str, ...]
    version: str
    doc: str

    @property
    def module(self) -> str:
        """Dotted name of the module defining the stage (imported by workers)."""
        return self.fn.__module__

    def code_version(self) -> str:
        """Hash of the stage's source, the project modules it imports, and its manual version."""
        return f"{self.version}:{module_code_hash(self.module)}"


_REGISTRY: dict[str, StageSpec] = {}


def _check_name(kind: str, name: str) -> None:
    if not name or not set(name) <= _NAME_CHARS or name[0].isdigit():
        raise ValueError(f"{kind} name {name!r} must be lower_snake_case")


def stage(
    *,
    name: str,
    inputs: Iterable[str | Input] = (),
    outputs: Iterable[str],
    params: type[Params] | None = None,
    version: str = "1",
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Register a stage function.

    Parameters
    ----------
    name : str
        Stage name, unique across the registry.
    inputs : iterable of str or Input
        Artifact names read (a plain string is a single input).
    outputs : iterable of str
        Artifact names written.
    params : type of Params, optional
        The params model; by default the annotation of the function's ``params`` argument.
    version : str
        Manual version, part of the cache key.

    Returns
    -------
    callable
        The decorator; it returns the function unchanged.
    """

    def register(fn: Callable[..., Any]) -> Callable[..., Any]:
        _check_name("stage", name)
        model = params or _params_annotation(fn)
        if not (isinstance(model, type) and issubclass(model, Params)):
            raise TypeError(f"stage {name!r}: params model must subclass pipeline.Params, got {model!r}")
        if not model.model_config.get("frozen"):
            raise TypeError(f"stage {name!r}: params model {model.__name__} must be frozen")
        declared_inputs = tuple(i if isinstance(i, Input) else Input(i) for i in inputs)
        declared_outputs = tuple(outputs)
        for artifact in [i.name for i in declared_inputs] + list(declared_outputs):
            _check_name("artifact", artifact)
        if not declared_outputs:
            raise TypeError(f"stage {name!r} declares no outputs")
        overlap = {i.name for i in declared_inputs} & set(declared_outputs)
        if overlap:
            raise TypeError(f"stage {name!r} both reads and writes {sorted(overlap)}")
        doc = inspect.getdoc(fn) or ""
        if not doc:
            raise TypeError(f"stage {name!r} needs a one-line docstring saying what it produces")
        spec = StageSpec(
            name=name,
            fn=fn,
            params_model=model,
            inputs=declared_inputs,
            outputs=declared_outputs,
            version=version,
            doc=doc.splitlines()[0],
        )
        existing = _REGISTRY.get(name)
        if existing is not None and (existing.module, existing.fn.__qualname__) != (
            spec.module,
            fn.__qualname__,
        ):
            raise DagError(f"two stages are named {name!r}: {existing.module} and {spec.module}")
        _REGISTRY[name] = spec
        return fn

    return register


def _params_annotation(fn: Callable[..., Any]) -> Any:
    hints = typing.get_type_hints(fn)
    if "params" not in hints:
        raise TypeError(f"{fn.__qualname__}: annotate the 'params' argument with the params model")
    return hints["params"]


def get_stage(name: str) -> StageSpec:
    """The registered stage called ``name``.

    Raises
    ------
    KeyError
        If no stage of that name is registered.
    """
    return _REGISTRY[name]


def registered_stages() -> dict[str, StageSpec]:
    """A copy of the registry: ``{name: spec}``."""
    return dict(_REGISTRY)


def discover(package: str) -> dict[str, StageSpec]:
    """Import every module of ``package`` so that its stages register, and return the registry."""
    root = importlib.import_module(package)
    for info in pkgutil.iter_modules(root.__path__, prefix=f"{package}."):
        importlib.import_module(info.name)
    return registered_stages()


def import_stage(module: str, name: str) -> StageSpec:
    """Import ``module`` (e.g. in a worker process) and return its registered stage ``name``."""
    importlib.import_module(module)
    return get_stage(name)
