"""The ``@stage`` decorator and the registry of stages.

A stage is a plain function ``fn(ctx: StageContext, params: P) -> None`` with one frozen params
model ``P`` (a :class:`~pipeline.params.Params` subclass). It declares the artifacts it reads and
the artifacts it writes; the graph of a build is derived from these declarations.

:func:`discover` imports every module of a stage package; :func:`stage_index` reads their sources
instead and imports a stage's module when the stage is first looked up, so a command that loads a
few recipes imports only the stages they name (and the libraries those import).
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import pkgutil
import typing
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from pipeline.code_version import module_code_hash
from pipeline.errors import DagError, StageImportError
from pipeline.params import Params

_NAME_CHARS = frozenset("abcdefghijklmnopqrstuvwxyz0123456789_")

SKIP_KEY = "skip"
"""The recipe key that skips a stage with a passthrough (``stages: {storefronts: {skip: true}}``);
reserved, so no params model may have a field of this name."""


@dataclass(frozen=True)
class Input:
    """An input declaration of a stage.

    Parameters
    ----------
    name : str
        The input's name: the key of ``ctx.inputs`` and of the recipe's ``links``.
    artifact : str, optional
        The artifact it reads, when that is named otherwise (e.g. an input ``building`` that reads
        another target's ``geometry``); by default ``name``.
    many : bool
        If true the stage receives a list of artifact directories (from several targets, bound
        through the recipe's ``links``); otherwise exactly one.
    """

    name: str
    artifact: str | None = None
    many: bool = False

    @property
    def source(self) -> str:
        """The artifact read: :attr:`artifact`, or :attr:`name` when none is given."""
        return self.artifact or self.name

    def describe(self) -> str:
        """``artifact 'name'``, or ``input 'name' (artifact 'source')`` when renamed; for messages."""
        if self.source == self.name:
            return f"artifact {self.name!r}"
        return f"input {self.name!r} (artifact {self.source!r})"


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
    passthrough : dict
        ``{output: input name}``: what each output is when a recipe skips the stage
        (``skip: true``); empty when the stage cannot be skipped.
    summary : tuple of (str, str)
        ``(label, key)`` pairs: the figures of the stats the stage records (``ctx.record``, kept in
        its artifacts' manifests) that the build summary shows for each of its runs, in this order
        (see :mod:`pipeline.summary`); a key may be a dotted path into nested stats.
    appearance : bool
        Whether the stage makes only how a target looks: its recipe section is left out of the recipe
        hash (:attr:`pipeline.recipes.Target.recipe_hash`) that other stages record in what they
        write, so that changing it changes no other artifact.
    """

    name: str
    fn: Callable[..., Any]
    params_model: type[Params]
    inputs: tuple[Input, ...]
    outputs: tuple[str, ...]
    version: str
    doc: str
    passthrough: Mapping[str, str] = field(default_factory=dict)
    summary: tuple[tuple[str, str], ...] = ()
    appearance: bool = False

    @property
    def skippable(self) -> bool:
        """Whether a recipe may skip the stage (every output has a passthrough input)."""
        return bool(self.passthrough)

    def input(self, name: str) -> Input:
        """The declared input called ``name``."""
        return next(i for i in self.inputs if i.name == name)

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
    passthrough: Mapping[str, str] | None = None,
    summary: Mapping[str, str] | Iterable[str] = (),
    appearance: bool = False,
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
    passthrough : mapping, optional
        ``{output: input name}`` for a stage that is optional in a chain: a recipe may skip it
        (``skip: true``), and each output is then the artifact its input reads, unchanged. Every
        output needs one, and the inputs must be single (not ``many``).
    summary : mapping or iterable of str, optional
        What the build summary says a run made: keys of the stats the stage records with
        ``ctx.record`` (a dotted path reaches into a nested dict), shown under their own names, or
        ``{label: key}`` to show them under a label. A dict of counts is shown as its total and its
        largest entries (``dropped 3 (not a closed ring 2, degenerate geometry 1)``).
    appearance : bool
        The stage makes only how a target looks (see :attr:`StageSpec.appearance`): its recipe
        section stays out of the recipe hash other stages record.

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
        for declared in declared_inputs:
            _check_name("input", declared.name)
            _check_name("artifact", declared.source)
        for artifact in declared_outputs:
            _check_name("artifact", artifact)
        if not declared_outputs:
            raise TypeError(f"stage {name!r} declares no outputs")
        names = [i.name for i in declared_inputs]
        if len(set(names)) != len(names):
            raise TypeError(f"stage {name!r} declares an input name twice: {names}")
        overlap = set(names) & set(declared_outputs)
        if overlap:
            raise TypeError(f"stage {name!r} both reads and writes {sorted(overlap)}")
        if SKIP_KEY in model.model_fields:
            raise TypeError(f"stage {name!r}: params field {SKIP_KEY!r} is reserved for skipping stages")
        through = dict(passthrough or {})
        if through:
            single = {i.name for i in declared_inputs if not i.many}
            if set(through) != set(declared_outputs) or not set(through.values()) <= single:
                raise TypeError(
                    f"stage {name!r}: passthrough must map every output {list(declared_outputs)} "
                    f"to one of its single inputs {sorted(single)}, got {through}"
                )
        figures = _summary_fields(name, summary)
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
            passthrough=MappingProxyType(through),
            summary=figures,
            appearance=bool(appearance),
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


def _summary_fields(name: str, summary: Mapping[str, str] | Iterable[str]) -> tuple[tuple[str, str], ...]:
    """``summary`` of :func:`stage` as ``(label, key)`` pairs; a TypeError if a label or key is empty."""
    if isinstance(summary, str):
        raise TypeError(f"stage {name!r}: summary must be a list of stats keys or a {{label: key}} mapping")
    pairs = tuple(summary.items()) if isinstance(summary, Mapping) else tuple((key, key) for key in summary)
    for label, key in pairs:
        if not (isinstance(label, str) and label.strip() and isinstance(key, str)) or not all(key.split(".")):
            raise TypeError(f"stage {name!r}: summary entry {label!r}: {key!r} needs a label and a stats key")
    return pairs


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
    """Import every module of ``package`` so that its stages register, and return the registry.

    Raises
    ------
    StageImportError
        If a stage module cannot be imported (a module it needs is missing, unreadable or broken);
        the message names the stage module and the import's own error.
    """
    root = importlib.import_module(package)
    for info in pkgutil.iter_modules(root.__path__, prefix=f"{package}."):
        _import_stage_module(info.name)
    return registered_stages()


def _import_stage_module(module: str) -> None:
    """Import a stage module, its failure as a :class:`StageImportError` naming it."""
    try:
        importlib.import_module(module)
    except (ImportError, SyntaxError) as exc:
        raise StageImportError(f"stage module {module}", exc) from None


def _declared_stages(tree: ast.Module) -> list[str] | None:
    """The stage names a module's source registers with ``stage(name="...")`` calls (as decorators or
    called), or None when a call gives its name otherwise (only importing the module can tell)."""
    names = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        if not (
            (isinstance(func, ast.Name) and func.id == "stage")
            or (isinstance(func, ast.Attribute) and func.attr == "stage")
        ):
            continue
        given = next((k.value for k in node.keywords if k.arg == "name"), None)
        if not (isinstance(given, ast.Constant) and isinstance(given.value, str)):
            return None
        names.append(given.value)
    return names


class StageIndex(Mapping[str, StageSpec]):
    """The stages of a package by name, each module imported when one of its stages is looked up.

    The index is read from the modules' sources (:func:`stage_index`): a module whose source
    registers stages under literal names (``@stage(name="navmesh", ...)``) is imported when one of
    them is first looked up; a module that registers stages otherwise is imported at once. Whatever
    the sources do not settle is settled as :func:`discover` does, by importing every module of the
    package: a name the index does not hold (or that its module did not register), listing the
    stages (iteration, ``len``), and a name found in two modules (the registry's error).

    Parameters
    ----------
    package : str
        The stage package (e.g. ``"stages"``).
    modules : mapping
        ``{stage name: module}`` as read from the sources.
    """

    def __init__(self, package: str, modules: Mapping[str, str]) -> None:
        self.package = package
        self._modules = dict(modules)
        self._everything = False

    def _discover(self) -> None:
        if not self._everything:
            discover(self.package)
            self._everything = True

    def __getitem__(self, name: str) -> StageSpec:
        module = self._modules.get(name)
        if module is not None:
            _import_stage_module(module)
            if name in _REGISTRY:
                return _REGISTRY[name]
        self._discover()
        return _REGISTRY[name]

    def __iter__(self) -> Iterator[str]:
        self._discover()
        return iter(registered_stages())

    def __len__(self) -> int:
        self._discover()
        return len(_REGISTRY)


def stage_index(package: str) -> StageIndex:
    """The stages of ``package`` by name, read from its modules' sources without importing them.

    Returns
    -------
    StageIndex
        A mapping that imports a stage's module when the stage is first looked up.

    Raises
    ------
    StageImportError
        If a module that must be imported now (see :class:`StageIndex`) cannot be.
    DagError
        If two modules register a stage of the same name.
    """
    root = importlib.import_module(package)
    modules: dict[str, str] = {}
    eager: list[str] = []
    twice = False
    for info in pkgutil.iter_modules(root.__path__, prefix=f"{package}."):
        spec = importlib.util.find_spec(info.name)
        origin = spec.origin if spec is not None else None
        names = None
        if origin is not None and origin.endswith(".py"):
            try:
                with open(origin, "rb") as handle:
                    names = _declared_stages(ast.parse(handle.read(), filename=origin))
            except (OSError, SyntaxError, ValueError):
                names = None  # importing it reports what is wrong
        if names is None:
            eager.append(info.name)
            continue
        for name in names:
            twice |= modules.get(name, info.name) != info.name
            modules[name] = info.name
    if twice:
        discover(package)  # the registry names the two modules
    for module in eager:
        _import_stage_module(module)
    return StageIndex(package, modules)


def import_stage(module: str, name: str) -> StageSpec:
    """Import ``module`` (e.g. in a worker process) and return its registered stage ``name``."""
    importlib.import_module(module)
    return get_stage(name)
